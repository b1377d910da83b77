#!/usr/bin/env bash
# Samples from a "device" judged by validate, with no GPU: device_standin is a
# separate program, the built-in warp cosine_hemisphere compiled as warpcheck
# builds it, with -ffast-math (and fused multiply-adds where the processor has
# them), and in double. What it asserts (issue 39's "Done when"):
#   1. the normal build's outputs for the inputs validate recorded, replayed,
#      give the same verdicts and the same figures as the warp run in-process,
#      and agree with validate's own outputs bit for bit (--compare, 0 ulps);
#   2. the fast-math build against the normal one: the exact comparison reports
#      its ulp histogram; replayed, the fast-math outputs pass every check;
#      the same for the float-vs-double pair;
#   3. independent draws (the device's own generator): the two-sample test
#      passes the normal build against the fast-math one and fails a build with
#      a 1% error; each judged against the pdf (--judge-samples) likewise.
# usage: run_device_standin.sh VALIDATE DEVICE_STANDIN WORKDIR
set -euo pipefail
validate=$1 device=$2 work=$3
rm -rf "$work" && mkdir -p "$work" && cd "$work"
case_name=cosine_hemisphere
run=(--filter "$case_name" --check consistency --check chi2 --check unbinned --seed 1 --samples 2e5 --progress none
     --color never)
fail() { echo "FAIL: $*" >&2; exit 1; }
# The figures of each row of a JSON results file, as "case check name=value" lines.
figures() {
  tr -d '\n' <"$1" | grep -o '"case":"[^"]*","check":"[^"]*"\|"figures":{[^}]*}' | paste -d ' ' - -
}

echo "== 1. in-process, and the device's normal build replayed"
"$validate" "${run[@]}" --record-inputs u.npy --record-outputs x_inprocess.npy --json inprocess.json >inprocess.txt ||
  fail "the in-process run did not pass: $(cat inprocess.txt)"
"$device" normal u.npy x_normal.npy
"$validate" "${run[@]}" --replay u.npy x_normal.npy --json replay.json >replay.txt ||
  fail "the device's outputs did not pass: $(cat replay.txt)"
cat replay.txt
[ "$(figures inprocess.json)" = "$(figures replay.json)" ] || fail "replayed figures differ from the in-process run's"
[ -n "$(figures replay.json)" ] || fail "no figures read from the results"
"$validate" --compare x_inprocess.npy x_normal.npy --inputs u.npy --filter "$case_name" --color never >same.txt ||
  fail "the normal build does not agree bit for bit: $(cat same.txt)"
grep -q "100% identical" same.txt || fail "expected every output identical: $(cat same.txt)"

for build in fma double; do
  echo "== 2. the $build build against the normal one"
  "$device" "$build" u.npy "x_$build.npy"
  # The tolerance is the claim under test; 0 asks for every difference, the histogram shows it.
  status=0
  "$validate" --compare x_normal.npy "x_$build.npy" --inputs u.npy --filter "$case_name" --color never --wide \
    --json "ulps_$build.json" >"ulps_$build.txt" || status=$?
  [ $status -le 1 ] || fail "--compare did not run: $(cat "ulps_$build.txt")"
  head -2 "ulps_$build.txt"
  # The same in ulps of 1 below 1 (the directions' scale): what a renderer would read.
  "$validate" --compare x_normal.npy "x_$build.npy" --ulp-floor 1 --filter "$case_name" --color never --wide |
    sed -n 2p || true
  grep -q '"title":"Distance histogram"' "ulps_$build.json" || fail "no ulp histogram in the $build comparison"
  echo "ulp histogram (ulps: outputs):"
  grep -oE '"title":"Distance histogram","columns":\["ulps","outputs"\],"rows":\[(\["[^"]*","[0-9]+"\],?)*\]' \
    "ulps_$build.json" | grep -oE '\["[^"]*","[0-9]+"\]' | tr -d '[]"' | tr ',' ' ' | paste -sd ';' -
  "$validate" "${run[@]}" --replay u.npy "x_$build.npy" >"replay_$build.txt" ||
    fail "the $build build's outputs did not pass the checks: $(cat "replay_$build.txt")"
done

echo "== 3. independent draws"
"$device" normal --draw 1000000 --seed 11 a_normal.npy
"$device" fma --draw 1000000 --seed 12 b_fma.npy
"$device" error1pct --draw 1000000 --seed 13 c_error.npy
"$validate" --two-sample a_normal.npy b_fma.npy --filter "$case_name" --color never >pair.txt ||
  fail "the normal and fast-math builds differ in distribution: $(cat pair.txt)"
head -2 pair.txt
status=0
"$validate" --two-sample a_normal.npy c_error.npy --filter "$case_name" --color never >error.txt || status=$?
head -2 error.txt
[ $status -eq 1 ] || fail "the build with a 1% error passed the two-sample test (status $status)"
"$validate" --judge-samples b_fma.npy --filter "$case_name" --color never >judge.txt ||
  fail "the fast-math draws failed against the pdf: $(cat judge.txt)"
status=0
"$validate" --judge-samples c_error.npy --filter "$case_name" --color never >judge_error.txt || status=$?
[ $status -eq 1 ] || fail "the 1% error passed against the pdf (status $status)"
echo "device stand-in: all assertions hold"

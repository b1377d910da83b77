#!/usr/bin/env bash
# Installs the warpcheck build tree into a scratch prefix, builds the GoogleTest
# example against the installed package (warpcheck::gtest and
# warpcheck_discover_tests), and shows: ctest lists one test per (case, check),
# labelled by check; every test passes with correct warps; with a wrong warp
# added, the gtest binary fails with the lines validate prints, the same
# figures and level, and the evidence file it names.
# Usage: run_gtest_example.sh BUILD_DIR EXAMPLE_SOURCE_DIR
set -euo pipefail
build_dir=$1
example_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "gtest example: $*"; exit 1; }

cmake --install "$build_dir" --prefix "$work/prefix" > "$work/install.log"
cmake -S "$example_dir" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release \
  > "$work/configure.log" || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/build" -j2 > "$work/build.log" || { cat "$work/build.log"; exit 1; }
b=$work/build
export WARPCHECK_SAMPLES=200000 WARPCHECK_EVIDENCE_DIR="$work/evidence"

# ctest -N: one test per (case, check) job of the validate program, labelled by check.
"$b/validate_power_warps" --list-jobs --all > "$work/jobs.txt"
jobs=$(wc -l < "$work/jobs.txt")
(cd "$b" && ctest -N -R '^validate_power_warps/') > "$work/listed.txt"
listed=$(grep -c 'Test *#' "$work/listed.txt" || true)
[ "$jobs" -gt 0 ] && [ "$listed" -eq "$jobs" ] || fail "ctest -N lists $listed tests for $jobs jobs"
grep -q 'validate_power_warps/chi2/power\[n=4\]$' "$work/listed.txt" || fail "no test validate_power_warps/chi2/power[n=4]"
chi2_jobs=$(grep -c "^chi2	" "$work/jobs.txt")
(cd "$b" && ctest -L '^chi2$' -j2 --output-junit "$work/chi2.xml" > "$work/ctest_chi2.log") ||
  { cat "$work/ctest_chi2.log"; fail "ctest -L chi2 failed"; }
[ "$(grep -c '<testcase' "$work/chi2.xml")" -eq "$chi2_jobs" ] || fail "JUnit of ctest -L chi2: not one testcase per chi2 job"

# Every test of the example (the per-job ctest tests and the gtest tests) passes.
(cd "$b" && ctest -j2 --output-on-failure > "$work/ctest.log") || { cat "$work/ctest.log"; fail "ctest failed"; }
gtests=$("$b/power_warps_test" --gtest_list_tests | grep -c '^  ')
[ "$gtests" -eq $((jobs + 1)) ] || fail "power_warps_test has $gtests tests, not one per job plus one"

# A wrong warp added: the gtest binary fails, with the complete failure text.
status=0
WARPCHECK_EVIDENCE_DIR="$work/evidence" "$b/power_warps_test_wrong" --gtest_filter='*power_wrong*' \
  > "$work/wrong.txt" 2>&1 || status=$?
echo "--- the failure text of the wrong warp (power_warps_test_wrong --gtest_filter='*power_wrong*'):"
sed -n '/warpcheck: chi2 failed/,/evidence:/p' "$work/wrong.txt"
echo "---"
[ "$status" -ne 0 ] || fail "the wrong warp passed its gtest tests"
for line in "warpcheck: chi2 failed on power_wrong\[n=2\]" "^FAIL  *chi2  *power_wrong\[n=2\]  *chi2 " \
            "FAIL chi2 power_wrong\[n=2\]: " "p-value .* is below the corrected level" \
            "chi2 power_wrong\[n=2\]: p-value .* at level " \
            "rerun: WARPCHECK_SEED=1 WARPCHECK_SAMPLES=200000 WARPCHECK_ALPHA=0.01 .*power_warps_test_wrong --gtest_filter='warpcheck/PowerWarps.Passes/power_wrong_n_2__chi2'" \
            "evidence: $work/evidence/power_wrong_n_2__chi2.html"; do
  grep -q -- "$line" "$work/wrong.txt" || fail "the failure text lacks: $line"
done
grep -q "power_wrong\[n=2\]" "$work/evidence/power_wrong_n_2__chi2.html" || fail "no HTML evidence"
# The same through EXPECT_WARP_PASSES on a warp object with its case info.
WARPCHECK_EVIDENCE_DIR="$work/evidence" "$b/power_warps_test_wrong" --gtest_filter='PowerWarp.WrongLobe' \
  > "$work/wrong_lobe.txt" 2>&1 && fail "EXPECT_WARP_PASSES passed the wrong warp"
for line in "warpcheck: warpcheck::make_warp_case(lobe(2), WrongPowerWarp{}) (power_lobe\[n=2\]) failed checks:" \
            "FAIL chi2 power_lobe\[n=2\]: p-value" "rerun: .*--gtest_filter='PowerWarp.WrongLobe'" \
            "evidence: $work/evidence/power_lobe_n_2.html"; do
  grep -q -- "$line" "$work/wrong_lobe.txt" || { cat "$work/wrong_lobe.txt"; fail "EXPECT_WARP_PASSES's text lacks: $line"; }
done

# The same figures and level as the validate program of the same warps and seed,
# whose rerun line names that program.
status=0
"$b/validate_power_warps_wrong" --all --samples "$WARPCHECK_SAMPLES" --color never > "$work/validate_wrong.txt" 2>&1 || status=$?
[ "$status" -eq 1 ] || fail "validate_power_warps_wrong exited $status, not 1"
row() { grep -E "^FAIL +chi2 +power_wrong" "$1" | tr -s ' '; }
level() { grep -E "^Statistical tests:" "$1" | head -1; }
[ -n "$(row "$work/validate_wrong.txt")" ] && [ "$(row "$work/wrong.txt")" = "$(row "$work/validate_wrong.txt")" ] ||
  fail "gtest and validate differ: '$(row "$work/wrong.txt")' vs '$(row "$work/validate_wrong.txt")'"
[ "$(level "$work/wrong.txt")" = "$(level "$work/validate_wrong.txt")" ] ||
  fail "levels differ: '$(level "$work/wrong.txt")' vs '$(level "$work/validate_wrong.txt")'"
grep -q "rerun: $b/validate_power_warps_wrong --filter 'power_wrong\[n=2\]' --check chi2" "$work/validate_wrong.txt" ||
  fail "the validate program's rerun line does not name it"

# GoogleTest sharding: three shards run every test once, the level is the whole suite's.
for i in 0 1 2; do
  GTEST_TOTAL_SHARDS=3 GTEST_SHARD_INDEX=$i "$b/power_warps_test_wrong" > "$work/shard$i.txt" 2>&1 || true
done
ran=$(cat "$work"/shard?.txt | grep -c '^\[ RUN      \]' || true)
total=$("$b/power_warps_test_wrong" --gtest_list_tests | grep -c '^  ')
[ "$ran" -eq "$total" ] || fail "three gtest shards ran $ran tests of $total"
[ "$(level "$(grep -l 'FAIL  *chi2  *power_wrong' "$work"/shard?.txt)")" = "$(level "$work/validate_wrong.txt")" ] ||
  fail "a gtest shard's level is not the whole suite's"
echo "gtest example: built against the installed package; $jobs ctest tests, one per (case, check); passed"

#!/usr/bin/env bash
# Runs the hostile-warp program with a 1 s budget and checks that one bad warp
# never takes the run down: exit status 1, exactly the six hostile checks of
# each kind as ERROR rows naming their cause, the healthy rows passing, both
# reports written, and the whole run within its budgets plus a few seconds.
# Usage: run_hostile.sh HOSTILE_EXE WORK_DIR [--no-crashes]
# --no-crashes (sanitizer builds): leave out the warps that crash, which
# AddressSanitizer intercepts itself.
set -uo pipefail
exe=$1
work=$2
mkdir -p "$work"
filters=(--filter healthy --filter hostile_exit --filter hostile_busy_loop --filter hostile_sleep)
expected=(hostile_exit hostile_busy_loop hostile_sleep)
if [ "${3:-}" != --no-crashes ]; then
  filters+=(--filter hostile_segfault --filter hostile_abort --filter hostile_allocate)
  expected+=(hostile_segfault hostile_abort hostile_allocate)
fi
rm -f "$work/hostile.json" "$work/hostile.html"
start=$(date +%s)
"$exe" "${filters[@]}" --check roundtrip --samples 20000 --threads 2 --time-budget 1 --memory-limit 512 \
  --color never --json "$work/hostile.json" --report "$work/hostile.html" > "$work/table.txt" 2> "$work/stderr.txt"
status=$?
elapsed=$(( $(date +%s) - start ))
cat "$work/table.txt"
fail() { echo "FAIL: $*"; cat "$work/stderr.txt"; exit 1; }
[ "$status" -eq 1 ] || fail "exit status $status, expected 1"
# Two jobs at a time, none longer than 10x its 1 s budget (the sleeper's
# wall-clock backstop), the others far shorter: 30 s leaves room for a busy machine.
[ "$elapsed" -le 30 ] || fail "took $elapsed s"
errors=$(grep -c "^ERROR" "$work/table.txt")
[ "$errors" -eq "${#expected[@]}" ] || fail "$errors ERROR rows, expected ${#expected[@]}"
# grep without -q reads all its input: with -q it may exit first and the
# writer's SIGPIPE then fails the pipeline under pipefail.
row() { grep -A3 "$1" "$work/table.txt" "$work/hostile.json" | grep "$2" > /dev/null || fail "$1 does not say '$2'"; }
# (LeakSanitizer may turn exit(0)'s status into its own.)
[ "${3:-}" = --no-crashes ] && row hostile_exit "before returning a result" \
  || row hostile_exit "called exit(0) before returning a result"
row hostile_busy_loop "over its CPU time budget of 1 s"
row hostile_sleep "did not finish within 10 s of wall time"
if [ "${3:-}" != --no-crashes ]; then
  row hostile_segfault "killed by signal 11 (SIGSEGV)"
  row hostile_abort "aborted (SIGABRT)"
  row hostile_allocate "ran out of memory"
fi
[ "$(grep -c "^pass" "$work/table.txt")" -eq 2 ] || fail "the healthy rows did not pass"
[ -s "$work/hostile.json" ] || fail "no JSON report"
[ -s "$work/hostile.html" ] || fail "no HTML report"
echo "hostile warps: ${#expected[@]} ERROR rows naming their causes; healthy rows passed; reports written in $elapsed s"

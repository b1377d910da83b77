#!/usr/bin/env bash
# Runs the hostile-warp program (hostile_warps.cpp) in one scenario and checks
# that a bad warp costs at most its own row, that nothing it starts outlives its
# check or a killed run, and that the tool's own output stays its own.
# Usage: run_hostile.sh HOSTILE_EXE WORK_DIR SCENARIO [--no-crashes]
# Scenarios (each a ctest of its own, seconds each):
#   faults        crash, abort, exit, endless loop, endless sleep, runaway
#                 allocation: one ERROR row each naming the cause
#   children      a child and a daemon that hold the worker's pipes forever:
#                 the run does not wait for them, and they are gone when the
#                 check ends (a later check looks)
#   output        a warp that prints: its lines in its row's evidence, never in
#                 the tool's output (`--json -` stays valid JSON)
#   killed        validate killed mid-run (TERM, INT, HUP, QUIT, KILL) with
#                 spinning, stopped and daemonising warps: no process left 2 s later
#   memory        the memory budget is the run's: two workers share it
#   no_isolation  --no-isolation: a warp's chdir() does not move the reports,
#                 its exit(0) is reported (status 1), its prints stay off stdout
#   lights        a light that throws: ERROR rows naming it; NaN pdfs of a
#                 light and of an MIS sum fail the checks that meet them
#   cli           control bytes in a case name never reach the terminal raw;
#                 --list-jobs > /dev/full fails; --filter '[a=1,b=3]' is one
#                 pattern; SIGHUP/SIGQUIT during a report's write leave no
#                 temporary file
# --no-crashes (sanitizer builds): leave out the warps that crash or need a
# memory limit, which AddressSanitizer intercepts or does not allow.
set -uo pipefail
exe=$(realpath "$1")
work=$(realpath -m "$2")
scenario=$3
no_crashes=${4:-}
rm -rf "$work/$scenario"
mkdir -p "$work/$scenario"
work=$work/$scenario
ulimit -c 0  # SIGQUIT would leave a core file

# HOSTILE_KEEP_GOING=1: report every failed assertion of the scenario, not
# only the first (to see what an older build gets wrong).
failures=0
fail() {
  echo "FAIL ($scenario): $*"
  failures=$((failures + 1))
  [ -n "${HOSTILE_KEEP_GOING:-}" ] && return 0
  for f in "$work"/*.txt; do [ -f "$f" ] && { echo "--- $f"; head -c 4000 "$f"; }; done
  exit 1
}
# grep without -q reads all its input: with -q it may exit first and the
# writer's SIGPIPE then fails the pipeline under pipefail.
contains() { grep -F -- "$2" "$1" > /dev/null; }

# The scenario's summary line, when nothing failed.
passed() { [ "$failures" -eq 0 ] && echo "$*"; true; }

# Whether a process is gone: no such process, or a zombie.
gone() {
  local stat
  stat=$(cat "/proc/$1/stat" 2> /dev/null) || return 0
  [ "$(sed 's/.*) //' <<< "$stat" | cut -c1)" = Z ]
}

# Waits up to $2 seconds for every pid in directory $1 to be gone; prints those left.
left_after() {
  local deadline=$((SECONDS + $2)) left
  while :; do
    left=""
    for f in "$1"/*; do [ -e "$f" ] && ! gone "${f##*/}" && left+=" ${f##*/}"; done
    [ -z "$left" ] && return 0
    if [ "$SECONDS" -ge "$deadline" ]; then echo "$left"; return 1; fi
    sleep 0.05
  done
}

# Kills (for the next scenario's sake) whatever a failed check left behind.
cleanup_pids() { for f in "$1"/*; do [ -e "$f" ] && kill -9 "${f##*/}" 2> /dev/null; done; true; }

scenario_faults() {
  local filters=(--filter healthy_a --filter healthy_b --filter hostile_exit --filter hostile_busy_loop
                 --filter hostile_sleep)
  local expected=(hostile_exit hostile_busy_loop hostile_sleep)
  if [ "$no_crashes" != --no-crashes ]; then
    filters+=(--filter hostile_segfault --filter hostile_abort --filter hostile_allocate)
    expected+=(hostile_segfault hostile_abort hostile_allocate)
  fi
  local start=$SECONDS
  "$exe" "${filters[@]}" --check roundtrip --samples 20000 --threads 2 --time-budget 1 --memory-limit 512 \
    --color never --json "$work/hostile.json" --report "$work/hostile.html" > "$work/table.txt" 2> "$work/stderr.txt"
  local status=$? elapsed=$((SECONDS - start))
  [ "$status" -eq 1 ] || fail "exit status $status, expected 1"
  # Two jobs at a time, none longer than 10x its 1 s budget (the sleeper's
  # wall-clock backstop), the others far shorter: 30 s leaves room for a busy machine.
  [ "$elapsed" -le 30 ] || fail "took $elapsed s"
  local errors
  errors=$(grep -c "^ERROR" "$work/table.txt")
  [ "$errors" -eq "${#expected[@]}" ] || fail "$errors ERROR rows, expected ${#expected[@]}"
  row() { grep -A3 "$1" "$work/table.txt" "$work/hostile.json" | grep -F -- "$2" > /dev/null || fail "$1 does not say '$2'"; }
  # (LeakSanitizer may turn exit(0)'s status into its own.)
  if [ "$no_crashes" = --no-crashes ]; then row hostile_exit "before returning a result"
  else row hostile_exit "called exit(0) before returning a result"; fi
  # What is known about a check over its budget: the CPU time it used against
  # the budget, and how to raise it.
  row hostile_busy_loop "over its CPU time budget of 1 s (set by --time-budget): used "
  row hostile_busy_loop "s of CPU time and was killed"
  row hostile_busy_loop "passes with a larger budget or fewer --samples"
  row hostile_sleep "did not finish within 10 s of wall time"
  if [ "$no_crashes" != --no-crashes ]; then
    row hostile_segfault "killed by signal 11 (SIGSEGV)"
    row hostile_abort "aborted (SIGABRT)"
    row hostile_allocate "ran out of memory"
    row hostile_allocate "the 256 MiB of address space each worker may use (--memory-limit 512 MiB, shared by the 2"
  fi
  [ "$(grep -c "^pass" "$work/table.txt")" -eq 2 ] || fail "the healthy rows did not pass"
  [ -s "$work/hostile.json" ] || fail "no JSON report"
  [ -s "$work/hostile.html" ] || fail "no HTML report"
  passed "faults: ${#expected[@]} ERROR rows naming their causes; healthy rows passed; reports written in $elapsed s"
}

scenario_children() {
  mkdir -p "$work/pids"
  local start=$SECONDS
  # One worker at a time: hostile_zz_checks_reaped runs after the two that
  # leave processes behind, and fails if any is still there.
  HOSTILE_PIDS=$work/pids timeout 120 "$exe" --filter hostile_child_holds_pipes --filter hostile_daemon_holds_pipes \
    --filter hostile_zz_checks_reaped --check roundtrip --samples 20000 --threads 1 --time-budget 5 --color never \
    > "$work/table.txt" 2> "$work/stderr.txt"
  local status=$? elapsed=$((SECONDS - start))
  local left
  left=$(left_after "$work/pids" 2) || { cleanup_pids "$work/pids"; fail "processes left after the run:$left"; }
  [ "$status" -ne 124 ] || fail "the run hung: it waited for the warps' children (killed after 120 s)"
  [ "$status" -eq 0 ] || fail "exit status $status, expected 0 (every row passes)"
  [ "$(ls "$work/pids" | wc -l)" -eq 2 ] || fail "expected 2 recorded processes, found $(ls "$work/pids" | wc -l)"
  # The children sleep forever: the run waits for none of them. Each job is
  # short (its budget is 5 s), so 40 s is a busy machine, not a wait.
  [ "$elapsed" -le 40 ] || fail "took $elapsed s: it waited for the warps' children"
  passed "children: the run took $elapsed s and every process the warps started was gone when its check ended"
}

scenario_output() {
  "$exe" --filter hostile_prints --filter healthy_a --check roundtrip --samples 20000 --threads 2 --color never \
    --json - > "$work/stdout.txt" 2> "$work/stderr.txt"
  local status=$?
  [ "$status" -eq 0 ] || fail "exit status $status, expected 0"
  jq -e . "$work/stdout.txt" > /dev/null || fail "standard output is not JSON"
  ! contains "$work/stderr.txt" "hostile_prints: a line" || fail "the warp's output reached validate's stderr"
  local lines
  lines=$(jq -r '.results[] | select(.case == "hostile_prints") | .tables[]
                 | select(.title | startswith("Output of the warp")) | "\(.title): \(.rows[][0])"' "$work/stdout.txt")
  echo "$lines" > "$work/captured.txt"
  contains "$work/captured.txt" "Output of the warp (stdout): hostile_prints: a line on stdout (printf)" ||
    fail "the row does not show the warp's printf line"
  contains "$work/captured.txt" "Output of the warp (stdout): hostile_prints: a line on stdout (std::cout)" ||
    fail "the row does not show the warp's std::cout line"
  contains "$work/captured.txt" "Output of the warp (stderr): hostile_prints: a line on stderr" ||
    fail "the row does not show the warp's stderr line"
  passed "output: --json - is valid JSON; the warp's three lines are in its row's evidence only"
}

# Starts a run of spinning, stopped, forking and daemonising warps, waits until all of
# them are running, sends signal $1 to validate, and requires every worker,
# descendant and the supervisor to be gone 2 s later.
kill_mid_run() {
  local sig=$1 pids=$work/pids-$1
  mkdir -p "$pids"
  HOSTILE_PIDS=$pids "$exe" --filter hostile_busy_loop --filter hostile_stop --filter hostile_child_spins \
    --filter hostile_daemon_sleeps --check roundtrip --threads 4 --time-budget 60 --color never \
    > "$work/table-$sig.txt" 2> "$work/stderr-$sig.txt" &
  local validate=$! deadline=$((SECONDS + 60))
  # 6 processes: the two lone workers, and a worker and its child or daemon for each of the two others.
  while [ "$(ls "$pids" | wc -l)" -lt 6 ]; do
    [ "$SECONDS" -lt "$deadline" ] || { kill -9 "$validate"; cleanup_pids "$pids"; fail "SIG$sig: the warps did not start"; }
    sleep 0.05
  done
  # The supervisor: validate's child.
  for p in $(cat /proc/"$validate"/task/*/children 2> /dev/null); do : > "$pids/$p"; done
  kill -"$sig" "$validate"
  local left
  left=$(left_after "$pids" 2) || { cleanup_pids "$pids"; fail "SIG$sig: processes left 2 s after validate was killed:$left"; }
  wait "$validate"
  passed "killed: after SIG$sig, none of the $(ls "$pids" | wc -l) processes of the run was left within 2 s"
}

scenario_killed() {
  set -m  # a background job of a script ignores SIGINT and SIGQUIT otherwise
  for sig in TERM INT HUP QUIT KILL; do kill_mid_run "$sig"; done
}

scenario_memory() {
  [ "$no_crashes" = --no-crashes ] && { echo "memory: no memory limit under AddressSanitizer"; exit 77; }
  # Two jobs (two checks of one case), each holding 700 MiB of address space.
  local run=(--filter hostile_reserve_700 --check roundtrip --check consistency --samples 20000 --memory-limit 1024
             --color never)
  "$exe" "${run[@]}" --threads 2 > "$work/two.txt" 2>&1
  [ $? -eq 1 ] || fail "two workers sharing 1024 MiB: expected both rows to run out of memory"
  [ "$(grep -c "^ERROR" "$work/two.txt")" -eq 2 ] || fail "two workers sharing 1024 MiB: expected 2 ERROR rows"
  contains "$work/two.txt" "the 512 MiB of address space each worker may use (--memory-limit 1024 MiB, shared by the 2 workers" ||
    fail "the out-of-memory row does not state the worker's share"
  "$exe" "${run[@]}" --threads 1 > "$work/one.txt" 2>&1 || fail "one worker with all 1024 MiB: expected a pass"
  passed "memory: 700 MiB fits a lone worker's 1024 MiB, not each of two workers' 512 MiB"
}

scenario_no_isolation() {
  mkdir -p "$work/start" "$work/elsewhere"
  (cd "$work/start" && HOSTILE_CHDIR=$work/elsewhere "$exe" --no-isolation --filter hostile_chdir --filter hostile_prints \
    --check roundtrip --samples 20000 --threads 1 --color never --json - --report report.html \
    > "$work/stdout.txt" 2> "$work/stderr.txt")
  local status=$?
  [ "$status" -eq 0 ] || fail "chdir: exit status $status, expected 0"
  [ -s "$work/start/report.html" ] || fail "chdir: the report is not in the starting directory"
  [ ! -e "$work/elsewhere/report.html" ] || fail "chdir: the report followed the warp's chdir()"
  jq -e . "$work/stdout.txt" > /dev/null || fail "a printing warp in-process: standard output is not JSON"
  "$exe" --no-isolation --filter hostile_exit --check roundtrip --samples 20000 --threads 1 --color never \
    --json "$work/exit.json" > "$work/exit.txt" 2> "$work/exit-stderr.txt"
  status=$?
  [ "$status" -eq 1 ] || fail "exit(0): exit status $status, expected 1"
  contains "$work/exit-stderr.txt" "validate: the warp of case hostile_exit called exit() during check roundtrip" ||
    fail "exit(0): the message does not name the case and check"
  passed "no_isolation: reports stay in the starting directory; exit(0) is status 1 naming the check; stdout stays JSON"
}

scenario_cli() {
  # Control bytes: the table, the failure message, the rerun command, --list and --list-jobs.
  "$exe" --filter hostile_name --check roundtrip --samples 20000 --threads 1 --color never > "$work/escape.txt" 2>&1
  "$exe" --filter hostile_name --list-jobs >> "$work/escape.txt" 2>&1
  "$exe" --filter hostile_name --list >> "$work/escape.txt" 2>&1
  if LC_ALL=C grep -P '[\x00-\x08\x0b-\x1f\x7f]' "$work/escape.txt" > /dev/null; then
    fail "a control byte of a case name reached the terminal"
  fi
  contains "$work/escape.txt" 'hostile_name\x1b[2J\x1b]0;owned\x07\x0d\x0a' || fail "the name is not shown escaped"
  contains "$work/escape.txt" "--filter \$'hostile_name\\x1b[2J\\x1b]0;owned\\x07\\x0d\\x0a'" ||
    fail "the rerun command does not quote the name as \$'...'"
  # A full stdout is an error.
  "$exe" --all --list-jobs > /dev/full 2> "$work/full.txt"
  local status=$?
  [ "$status" -eq 2 ] || fail "--list-jobs > /dev/full: exit status $status, expected 2"
  contains "$work/full.txt" "could not write the job list to standard output" || fail "--list-jobs > /dev/full: no message"
  # A pattern with a comma in brackets is one pattern.
  "$exe" --filter '[a=1,b=3]' --check roundtrip --list-jobs > "$work/comma.txt" 2>&1
  [ "$(cat "$work/comma.txt")" = "$(printf 'roundtrip\thealthy_params[a=1,b=3]')" ] ||
    fail "--filter '[a=1,b=3]' selected: $(cat "$work/comma.txt")"
  # A signal while a report's temporary file is written removes it.
  for sig in 1 2 3 15; do
    rm -rf "$work/out"
    mkdir -p "$work/out"
    echo old > "$work/out/report.json"
    # (In a subshell: the shell's own "Hangup" notice goes to /dev/null too.)
    (HOSTILE_SIGNAL_IN_FSYNC=$sig "$exe" --filter healthy_a --check roundtrip --samples 20000 --threads 1 \
      --color never --json "$work/out/report.json"; exit $?) > /dev/null 2>&1
    status=$?
    [ "$status" -eq $((128 + sig)) ] || fail "signal $sig in fsync: exit status $status, expected $((128 + sig))"
    [ "$(ls -A "$work/out")" = report.json ] || fail "signal $sig during a write left: $(ls -A "$work/out")"
    [ "$(cat "$work/out/report.json")" = old ] || fail "signal $sig during a write changed the old report"
  done
  passed "cli: names escaped; /dev/full is an error; '[a=1,b=3]' is one pattern; HUP, INT, QUIT, TERM during a write leave no temporary file"
}

scenario_lights() {
  # A light whose own intersection throws, a light that returns a NaN pdf, and
  # an MIS sum whose light pdf is NaN on half the sphere: each check that
  # calls the throwing part is an ERROR row naming the exception; every check
  # that meets a NaN fails, none passes over it.
  "$exe" --filter hostile_light_throws --filter hostile_light_nan_pdf --filter hostile_mis_nan_pdf --samples 20000 \
    --threads 2 --time-budget 10 --color never --wide > "$work/table.txt" 2> "$work/stderr.txt"
  local status=$?
  [ "$status" -eq 1 ] || fail "exit status $status, expected 1"
  for check in light_radiance light_support light_irradiance; do
    grep -E "^  ERROR $check hostile_light_throws: .*hostile: no light here" "$work/table.txt" > /dev/null ||
      fail "$check of the throwing light is not an ERROR naming its exception"
  done
  for check in sample_pdf light_irradiance; do
    grep -E "^FAIL +$check +hostile_light_nan_pdf" "$work/table.txt" > /dev/null || fail "$check passed a NaN pdf"
  done
  for check in consistency sample_pdf mis_weights mis_estimator; do
    grep -E "^FAIL +$check +hostile_mis_nan_pdf" "$work/table.txt" > /dev/null || fail "$check passed a NaN MIS pdf"
  done
  passed "lights: a throwing light's checks are ERROR rows naming the exception; NaN pdfs fail sample_pdf, light_irradiance and the MIS checks"
}

"scenario_$scenario"
[ "$failures" -eq 0 ] || exit 1

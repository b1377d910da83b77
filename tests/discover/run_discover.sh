#!/usr/bin/env bash
# warpcheck_discover_tests on a program whose case names are awkward
# (discover_names.cpp): ctest -N lists one test per job; each name that
# ctest -N prints, given to ctest -R, selects that test; every test runs its
# own job and passes, the one whose case name is too long for a file name
# included; failing, that one writes its evidence under a shortened name, in
# the ctest integration's own folder.
# Usage: run_discover.sh PROGRAM CMAKE_MODULE_DIR WORK_DIR
set -euo pipefail
program=$1
modules=$2
work=$3
rm -rf "$work"
mkdir -p "$work/project"
fail() { echo "discover: $*"; exit 1; }

cat > "$work/project/CMakeLists.txt" <<CMAKE
cmake_minimum_required(VERSION 3.25)
project(discover NONE)
enable_testing()
include("$modules/warpcheckDiscoverTests.cmake")
add_executable(discover_names IMPORTED)
set_target_properties(discover_names PROPERTIES IMPORTED_LOCATION "$program")
warpcheck_discover_tests(discover_names EXTRA_ARGS --all --check roundtrip --samples 1000)
CMAKE
cmake -S "$work/project" -B "$work/build" > "$work/configure.log" || { cat "$work/configure.log"; exit 1; }
cd "$work/build"

jobs=$("$program" --list-jobs --all --check roundtrip | wc -l)
ctest -N > "$work/listed.txt"
listed=$(grep -c 'Test *#' "$work/listed.txt" || true)
[ "$jobs" -eq 8 ] && [ "$listed" -eq "$jobs" ] || { cat "$work/listed.txt"; fail "ctest -N lists $listed tests for $jobs jobs"; }

# A name copied from ctest -N selects its test, and only it.
sed -n 's/^ *Test *#[0-9]*: //p' "$work/listed.txt" > "$work/names.txt"
while IFS= read -r name; do
  selected=$(ctest -N -R "$name" | grep -c 'Test *#' || true)
  [ "$selected" -eq 1 ] || fail "ctest -R '$name' selects $selected tests"
done < "$work/names.txt"
grep -qx 'discover_names/roundtrip/power{n=4}~[0-9a-f]\{8\}' "$work/names.txt" ||
  fail "power[n=4] and power{n=4} do not each carry a hash: $(grep power "$work/names.txt")"

# Each test runs its own job (the job list's line k is test k) and passes.
ctest -j2 --output-on-failure > "$work/ctest.log" || { cat "$work/ctest.log"; fail "ctest failed"; }
grep -q "100% tests passed, 0 tests failed out of $jobs" "$work/ctest.log" || { cat "$work/ctest.log"; fail "not every test passed"; }
ctest -V -R 'semi_colon' > "$work/semi.log"
grep -q 'roundtrip  *semi;colon\[a=1\]' "$work/semi.log" || { cat "$work/semi.log"; fail "the semi;colon test ran another job"; }

# A failing test of the long name writes its evidence, under a name of at most
# 255 bytes, in ctest/discover_names/ (the GoogleTest adapter writes in gtest/).
status=0
DISCOVER_WRONG=1 WARPCHECK_EVIDENCE_DIR="$work/evidence" ctest -R '_long' --output-on-failure > "$work/wrong.log" 2>&1 ||
  status=$?
[ "$status" -ne 0 ] || fail "the wrong long-named case passed"
evidence=$(sed -n 's/^HTML report written to //p' "$work/wrong.log")
[ -n "$evidence" ] && [ -f "$evidence" ] || { cat "$work/wrong.log"; fail "no evidence written for the long name"; }
[ "$(dirname "$evidence")" = "$work/evidence/ctest/discover_names" ] || fail "evidence not in ctest/discover_names/: $evidence"
file=$(basename "$evidence")
[ "${#file}" -le 255 ] && [[ "$file" == llll*_[0-9a-f]*__roundtrip.html ]] || fail "evidence file name not shortened: $file"
grep -q '_long\[a=1\]' "$evidence" || fail "the evidence does not name the case"
echo "discover: $jobs awkward names, one ctest test each, each selected by its own name; evidence $file"

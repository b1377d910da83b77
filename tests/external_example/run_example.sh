#!/usr/bin/env bash
# Installs the warpcheck build tree into a scratch prefix, builds the external
# example against the installed package (find_package(warpcheck)), and runs it.
# Usage: run_example.sh BUILD_DIR EXAMPLE_SOURCE_DIR
set -euo pipefail
build_dir=$1
example_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cmake --install "$build_dir" --prefix "$work/prefix" > "$work/install.log"
cmake -S "$example_dir" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release \
  > "$work/configure.log" || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/build" -j2 > "$work/build.log" || { cat "$work/build.log"; exit 1; }

# The program has the whole CLI: list, run, and reject bad input.
"$work/build/validate_my_warps" --list | grep -q "linear\[a=1,b=3\]"
"$work/build/validate_my_warps" --all --samples 200000 --color never
status=0
"$work/build/validate_my_warps" --filter no_such_warp 2> /dev/null || status=$?
[ "$status" -eq 2 ] || { echo "expected exit status 2 for an unknown warp, got $status"; exit 1; }
echo "external example: built against the installed package and passed"

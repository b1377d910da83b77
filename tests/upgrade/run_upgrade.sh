#!/usr/bin/env bash
# Upgrading from warpcheck 0.1: a client written against it (client_0_1.cpp:
# the include path <validate/external.h>, the positional make_warp_case,
# make_weighted_case and make_u32_float_case) builds against this release's
# installed package, with a deprecation warning for each old form that names
# what replaces it, and its cases pass every check that applies.
# Usage: run_upgrade.sh BUILD_DIR CLIENT_SOURCE_DIR
set -euo pipefail
build_dir=$1
client_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "upgrade: $*"; exit 1; }

cmake --install "$build_dir" --prefix "$work/prefix" > "$work/install.log"
cmake -S "$client_dir" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release \
  > "$work/configure.log" || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/build" > "$work/build.log" 2>&1 || { cat "$work/build.log"; fail "the 0.1 client does not build"; }

# (GCC says the include path's in a note, #pragma message, which it shows from
# an installed header; the rest are -Wdeprecated-declarations warnings.)
for warning in \
  "<validate/external.h> is deprecated: include <validate/api/external.h> instead" \
  "make_warp_case(info, sample, pdf, invert) is deprecated .*: use make_warp_case(info, warp_of(sample).with_pdf(pdf).with_invert(invert))" \
  "make_warp_case(info, sample, pdf) is deprecated .*: use make_warp_case(info, warp_of(sample).with_pdf(pdf))" \
  "make_warp_case(info, sample) with a callable is deprecated .*: use make_warp_case(info, warp_of(sample))" \
  "make_weighted_case(info, sample, eval, pdf) is deprecated .*: use make_warp_case(info, warp_of(sample).with_eval(eval).with_pdf(pdf))" \
  "make_u32_float_case(info, monotone, sample, pdf, invert) is deprecated .*: use make_u32_float_case(info, monotone, warp_of(sample).with_pdf(pdf).with_invert(invert))"; do
  grep -q -- "$warning" "$work/build.log" || { cat "$work/build.log"; fail "no warning: $warning"; }
done

status=0
"$work/build/validate_client_0_1" --all --samples 200000 --color never --progress none > "$work/run.txt" 2>&1 || status=$?
[ "$status" -eq 0 ] || { cat "$work/run.txt"; fail "the 0.1 client's cases did not all pass (exit $status)"; }
for case in 'linear\[a=1,b=3\]' cosine_returned_pdf table_no_pdf 'phong_mixture\[n=50,select=0.3\]' renderer_unit_float; do
  grep -Eq "^pass +[a-z_0-9]+ +$case" "$work/run.txt" || { cat "$work/run.txt"; fail "no passing row of $case"; }
done
echo "upgrade: the 0.1 client builds with $(grep -c 'deprecated' "$work/build.log") deprecation lines and passes"

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
"$work/build/validate_my_warps" --all --samples 200000 --color never | tee "$work/all.txt"

# Samplers that return more than a point: each correct one passes the checks of
# its kind (with every other applicable check, in --all above); each wrong twin
# fails the check meant to catch it.
expect_row() {  # VERDICT CHECK CASE
  grep -Eq "^$1 +$2 +$(printf '%s' "$3" | sed 's/[][]/\\&/g')( |\$)" "$work/all.txt" \
    || { echo "expected a '$1' row for check $2 on $3"; exit 1; }
}
expect_row pass sample_pdf cosine_returned_pdf
expect_row pass consistency table_no_pdf
expect_row pass inverse_pdf_mean table_no_pdf
for point in "n=5,select=0.3" "n=5,select=0.6" "n=50,select=0.3" "n=50,select=0.6"; do
  for check in weight weight_mean chi2; do expect_row pass "$check" "phong_mixture[$point]"; done
done
for check in pmf discrete_chi2 remapped_u; do expect_row pass "$check" alias_table; done
for twin in cosine_returned_pdf_wrong:sample_pdf table_no_pdf_wrong:inverse_pdf_mean \
            phong_mixture_wrong:weight_mean alias_table_wrong:remapped_u; do
  name=${twin%%:*} check=${twin##*:}
  status=0
  "$work/build/validate_my_warps" --filter "$name" --check "$check" --samples 200000 --color never \
    > "$work/all.txt" || status=$?
  [ "$status" -eq 1 ] || { cat "$work/all.txt"; echo "expected $name to fail $check (exit 1), got $status"; exit 1; }
  expect_row FAIL "$check" "$name"
done
status=0
"$work/build/validate_my_warps" --filter no_such_warp 2> /dev/null || status=$?
[ "$status" -eq 2 ] || { echo "expected exit status 2 for an unknown warp, got $status"; exit 1; }
echo "external example: built against the installed package and passed"

#!/usr/bin/env bash
# Installs the warpcheck build tree into a scratch prefix, builds the external
# example against the installed package (find_package(warpcheck)), and runs it:
# every correct warp passes every check that applies (--all exits 0, round
# trips of the warp without an inverse are n/a), and each wrong twin fails the
# check meant to catch it.
# Usage: run_example.sh BUILD_DIR EXAMPLE_SOURCE_DIR
set -euo pipefail
build_dir=$1
example_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cmake --install "$build_dir" --prefix "$work/prefix" > "$work/install.log"
# The installed include folder holds only what a renderer writes against and
# what that includes (cmake/PublicHeaders.cmake): at most 30 headers, and none
# of the private rooms' (the command line, the worker supervisor, the checks).
installed=$(find "$work/prefix/include/warpcheck" -name '*.h' | wc -l)
[ "$installed" -le 30 ] || { echo "$installed installed headers, more than 30"; exit 1; }
for private in validate/cli/cli.h validate/run/worker_supervisor.h validate/run/runner.h validate/run/job.h \
  validate/run/thread_pool.h validate/checks/checks.h validate/checks/check.h validate/gtest/job_tests.h \
  reports/render.h reports/result.h; do
  [ ! -e "$work/prefix/include/warpcheck/$private" ] || { echo "private header $private installed"; exit 1; }
done
echo "$installed installed headers"
cmake -S "$example_dir" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release \
  > "$work/configure.log" || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/build" -j2 > "$work/build.log" || { cat "$work/build.log"; exit 1; }
program="$work/build/validate_my_warps"

# The program has the whole CLI: list, run, and reject bad input.
"$program" --list | grep -q "linear\[a=1,b=3\]"
"$program" --all --samples 200000 --color never | tee "$work/all.txt"
grep -Eq "^n/a +roundtrip +cosine_hemisphere_no_inverse +not applicable: the warp has no inverse" "$work/all.txt" \
  || { echo "expected an n/a round trip for the warp without an inverse"; exit 1; }

# Samplers that return more than a point: each correct one passes the checks of
# its kind (with every other applicable check, in --all above).
expect_row() {  # VERDICT CHECK CASE; a weak row is a pass that states it could not see a 5% tilt
  local verdict=$1
  [ "$verdict" != pass ] || verdict='(pass|weak)'
  grep -Eq "^$verdict +$2 +$(printf '%s' "$3" | sed 's/[][]/\\&/g')( |\$)" "$work/all.txt" \
    || { echo "expected a '$1' row for check $2 on $3"; exit 1; }
}
expect_row pass sample_pdf cosine_returned_pdf
expect_row pass consistency table_no_pdf
expect_row pass inverse_pdf_mean table_no_pdf
for point in "n=5,select=0.3" "n=5,select=0.6" "n=50,select=0.3" "n=50,select=0.6"; do
  for check in weight weight_mean chi2; do expect_row pass "$check" "phong_mixture[$point]"; done
done
for check in pmf discrete_chi2 remapped_u; do expect_row pass "$check" alias_table; done
expect_row pass exhaustive renderer_unit_float  # all 2^32 inputs, on the fast path
status=0
"$program" --filter no_such_warp 2> /dev/null || status=$?
[ "$status" -eq 2 ] || { echo "expected exit status 2 for an unknown warp, got $status"; exit 1; }

# Each wrong twin, run by its full name, fails the check meant to catch it.
expect_fail() {  # case check [text the failure must contain] [text it must not contain]
  local out status=0
  out=$("$program" --filter "$1" --check "$2" --samples 200000 --color never 2>&1) || status=$?
  [ "$status" -eq 1 ] || { echo "$out"; echo "expected $1 to fail $2 (exit 1), got exit $status"; exit 1; }
  grep -Eq "^FAIL +$2 +" <<< "$out" || { echo "$out"; echo "expected a FAIL row for $2 of $1"; exit 1; }
  [ -z "${3:-}" ] || grep -qF "$3" <<< "$out" || { echo "$out"; echo "expected '$3' in the failure of $1"; exit 1; }
  [ -z "${4:-}" ] || ! grep -qF "$4" <<< "$out" || { echo "$out"; echo "did not expect '$4' for $1"; exit 1; }
}
expect_fail "normal_pdf_forgets_sigma[mu=2,sigma=0.5]" chi2 ", not 1 (tolerance"
expect_fail "mirrored_exponential_inverse_flipped[b=1,rate=4]" roundtrip
expect_fail "cosine_hemisphere_no_inverse_half_pdf" chi2 ", not 1 (tolerance"
expect_fail "uniform_sphere_azimuth_bent" tabulated "view phi:" "view cos theta:"
expect_fail cosine_returned_pdf_wrong sample_pdf
expect_fail table_no_pdf_wrong inverse_pdf_mean
expect_fail phong_mixture_wrong weight_mean
expect_fail alias_table_wrong remapped_u
expect_fail renderer_unit_float_swapped exhaustive
# A warp written as a template over its float type (its chi-square check on the vectorised path).
for check in consistency chi2 unbinned; do expect_row pass "$check" templated_cone; done
expect_fail templated_cone_too_wide chi2

# A renderer's BSDF over three outgoing directions passes every BSDF check (in
# --all); its wrong twin fails the check meant for it.
for theta in 0 60 85; do
  for check in bsdf_chi2 bsdf_unbinned bsdf_weight bsdf_albedo bsdf_reciprocity; do expect_row pass "$check" "renderer_diffuse[theta_o=$theta]"; done
done
expect_fail "renderer_diffuse_not_reciprocal[theta_o=60]" bsdf_reciprocity "not reciprocal"

# A C++17 translation unit registers one case of every kind through
# validate/api/register17.h; every correct one passes (--all exits 0), and each
# wrong twin of a kind fails the check meant to catch it.
program="$work/build/validate_my_warps17"
"$program" --all --samples 200000 --color never | tee "$work/all.txt"
expect_row pass roundtrip "logistic_cxx17[mu=-3,s=0.25]"
expect_row pass tabulated "logistic_cxx17[mu=-3,s=0.25]"
grep -Eq "^n/a +roundtrip +cosine_cxx17_no_inverse +not applicable: the warp has no inverse" "$work/all.txt" \
  || { echo "expected an n/a round trip for the C++17 warp without an inverse"; exit 1; }
expect_row pass chi2 cosine_cxx17_no_inverse
expect_row pass sample_pdf cosine_cxx17_returned_pdf
expect_row pass inverse_pdf_mean table_cxx17_no_pdf
for check in pmf discrete_chi2; do expect_row pass "$check" choice_cxx17; done
for check in pmf discrete_chi2 remapped_u; do expect_row pass "$check" choice_cxx17_remapped; done
for n in 5 50; do
  for check in weight weight_mean chi2; do expect_row pass "$check" "phong_cxx17[n=$n]"; done
done
expect_row pass exhaustive unit_float_cxx17    # all 2^32 inputs, the block loop compiled as C++17
expect_row pass exhaustive one_to_two_cxx17    # the top 23 of 64 bits
for theta in 0 70; do expect_row pass bsdf_weight "diffuse_cxx17[theta_o=$theta]"; done
# A stochastic BSDF from C++17: judged in expectation, the pointwise checks n/a.
expect_row pass bsdf_expectation "noisy_diffuse_cxx17[theta_o=30]"
for check in bsdf_weight bsdf_chi2 bsdf_albedo; do expect_row n/a "$check" "noisy_diffuse_cxx17[theta_o=30]"; done
for check in chi2 consistency sample_pdf light_radiance light_support light_irradiance; do
  expect_row pass "$check" sphere_light_cxx17
done
expect_fail cosine_cxx17_no_inverse_half_pdf chi2 ", not 1 (tolerance"
expect_fail cosine_cxx17_returned_pdf_wrong sample_pdf
expect_fail table_cxx17_no_pdf_wrong inverse_pdf_mean
expect_fail choice_cxx17_pmf_swapped discrete_chi2
expect_fail choice_cxx17_remap_not_rescaled remapped_u
expect_fail "phong_cxx17_wrong[n=20]" weight_mean
expect_fail unit_float_cxx17_swapped exhaustive
expect_fail one_to_two_cxx17_swapped exhaustive
expect_fail "diffuse_cxx17_weight_no_cos[theta_o=70]" bsdf_weight
expect_fail "noisy_diffuse_cxx17_biased[theta_o=30]" bsdf_expectation
expect_fail sphere_light_cxx17_double_radiance light_radiance "differs from L(ref, wi)"
expect_row pass mis_estimator direct_cxx17
# A spectral BSDF from C++17 (add_spectral_bsdf_grid), each hero channel; two lights in one MIS sum.
for hero in 0 1 2; do
  for check in bsdf_chi2 bsdf_weight bsdf_spectral; do expect_row pass "$check" "rgb_cxx17[theta_o=40,hero=$hero]"; done
done
for check in sample_pdf mis_estimator; do expect_row pass "$check" direct_two_lights_cxx17; done
expect_fail "rgb_cxx17_green_high[theta_o=40,hero=0]" bsdf_spectral "in channel 1"
expect_fail direct_two_lights_cxx17_pdf_swapped mis_weights "small_sphere_light_cxx17: pdf 0, in the MIS sum"
# Parameters at their extremes, from C++17 (w17::add_bsdf_grid with ranges):
# the correct family comes out clean; the planted NaN is found and shrunk to R = 0.
"$program" --fuzz --filter diffuse_grid_cxx17 | tee "$work/fuzz.txt"
grep -q ": 0 findings, 0 refusals" "$work/fuzz.txt" || { echo "expected diffuse_grid_cxx17 to fuzz clean"; exit 1; }
if "$program" --fuzz --filter diffuse_grid_cxx17_dark_nan > "$work/fuzz_nan.txt"; then
  echo "expected --fuzz to find the planted NaN of diffuse_grid_cxx17_dark_nan"; exit 1
fi
grep -q "shrunk to  diffuse_grid_cxx17_dark_nan\[R=0,theta_o=0\]" "$work/fuzz_nan.txt" \
  || { cat "$work/fuzz_nan.txt"; echo "expected the planted NaN shrunk to R=0, theta_o=0"; exit 1; }
expect_fail direct_cxx17_area_pdf mis_weights "do not sum to 1"
# The Python package installs with the rest, where the build made it (cmake/Python.cmake),
# and imports from the prefix with the interpreter it was built for.
python=$(sed -n 's/^Python3_EXECUTABLE:[A-Z]*=//p' "$build_dir/CMakeCache.txt")
if [ -e "$build_dir/validate/python/warpcheck/__init__.py" ]; then
  PYTHONPATH="$work/prefix/lib/python3/dist-packages" "$python" -c \
    'import warpcheck; assert "chi2" in warpcheck.check_names(); print("python package installed:", warpcheck.__file__)' \
    || { echo "the installed Python package does not import"; exit 1; }
fi
echo "external example: built against the installed package and passed"

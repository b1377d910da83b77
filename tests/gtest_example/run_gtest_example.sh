#!/usr/bin/env bash
# Installs the warpcheck build tree into a scratch prefix, builds the GoogleTest
# example against the installed package (warpcheck::gtest and
# warpcheck_discover_tests), and shows: ctest lists one test per (case, check),
# labelled by check; every test passes with correct warps (n/a ones skipped);
# ctest names are clean; WARPCHECK_* settings reach both integrations and an
# invalid one fails every test; with a wrong warp added, the gtest binary fails
# at the user's line with the lines validate prints, the same figures and
# level, and the evidence file it names (a failing ctest test too); a BSDF and
# its wrong twin likewise (EXPECT_BSDF_PASSES); names that would collide are
# made unique; a registration that throws fails.
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
# (Named as ctest -R reads it: power[n=4] is listed power{n=4}, a name that selects itself.)
grep -q 'validate_power_warps/chi2/power{n=4}$' "$work/listed.txt" || fail "no test validate_power_warps/chi2/power{n=4}"
chi2_jobs=$(grep -c "^chi2	" "$work/jobs.txt")
(cd "$b" && ctest -L '^chi2$' -LE wrong -j2 --output-junit "$work/chi2.xml" > "$work/ctest_chi2.log") ||
  { cat "$work/ctest_chi2.log"; fail "ctest -L chi2 failed"; }
[ "$(grep -c '<testcase' "$work/chi2.xml")" -eq "$chi2_jobs" ] || fail "JUnit of ctest -L chi2: not one testcase per chi2 job"

# Every test of the example (the per-job ctest tests and the gtest tests) passes;
# the n/a round trips of the warp without an inverse are skipped, saying why.
(cd "$b" && ctest -j2 -LE wrong --output-on-failure > "$work/ctest.log") || { cat "$work/ctest.log"; fail "ctest failed"; }
gtests=$("$b/power_warps_test" --gtest_list_tests | grep -c '^  ')
# (plus the four assertions: a warp, a BSDF, a light and an MIS case)
[ "$gtests" -eq $((jobs + 4)) ] || fail "power_warps_test has $gtests tests, not one per job plus four"
# The BSDF cases are in the suite with the BSDF checks, and only those.
"$b/power_warps_test" --gtest_list_tests > "$work/gtests.txt"
grep -q '^  Passes/diffuse_theta_o_60__bsdf_unbinned$' "$work/gtests.txt" || fail "no BSDF check of a BSDF case in the suite"
! grep -q '^  Passes/diffuse_theta_o_60__chi2$' "$work/gtests.txt" || fail "a warp's check on a BSDF case"
"$b/power_warps_test" --gtest_filter='*power_no_inverse_n_3__roundtrip' > "$work/skip.txt" 2>&1 ||
  { cat "$work/skip.txt"; fail "an n/a test failed"; }
grep -q '^\[  SKIPPED \] warpcheck/PowerWarps.Passes/power_no_inverse_n_3__roundtrip' "$work/skip.txt" &&
  grep -q 'roundtrip does not apply to power_no_inverse\[n=3\]: ' "$work/skip.txt" ||
  { cat "$work/skip.txt"; fail "an n/a check is not a skipped test that says why"; }
grep -q 'power_no_inverse_n_3__roundtrip.*Skipped' "$work/ctest.log" || fail "ctest does not show the n/a test as skipped"
suite_line=$(grep -n '^WARPCHECK_TEST_SUITE' "$example_dir/power_warps_test.cpp" | cut -d: -f1)
grep -q "power_warps_test.cpp:$suite_line: Skipped" "$work/skip.txt" || { cat "$work/skip.txt"; fail "the skip is not at the user's line"; }

# Clean ctest names, without "# GetParam() = ...": a name anchored at its end matches.
(cd "$b" && ctest -N) > "$work/all_listed.txt"
! grep -q 'GetParam' "$work/all_listed.txt" || fail "a ctest name carries GetParam: $(grep -m1 GetParam "$work/all_listed.txt")"
[ "$(cd "$b" && ctest -N -R 'power_n_4__chi2$' | grep -c 'Test *#')" -eq 1 ] || fail "ctest -R 'power_n_4__chi2\$' selects no test"
# A float parameter is named by the float: n = 0.3f reads power[n=0.3].
grep -q "	power\[n=0.3\]$" "$work/jobs.txt" || fail "n = 0.3f is not named power[n=0.3]: $(cut -f2 "$work/jobs.txt" | sort -u)"

# Settings from ctest's environment: counts as people write them, and an invalid
# value fails every test of both integrations with the variable and the reason.
(cd "$b" && WARPCHECK_SAMPLES=1e5 ctest -R 'validate_power_warps/chi2/power{n=4}$' -V > "$work/env.log") ||
  { cat "$work/env.log"; fail "WARPCHECK_SAMPLES=1e5 ctest failed"; }
grep -q '(seed 1, 100000 samples' "$work/env.log" || { cat "$work/env.log"; fail "WARPCHECK_SAMPLES=1e5 was not used"; }
status=0
(cd "$b" && WARPCHECK_SAMPLES=lots ctest -j2 -LE wrong --output-on-failure > "$work/invalid.log" 2>&1) || status=$?
all=$(cd "$b" && ctest -N -LE wrong | grep -c 'Test *#')
[ "$status" -ne 0 ] && grep -q "0% tests passed, $all tests failed out of $all" "$work/invalid.log" ||
  { tail -20 "$work/invalid.log"; fail "WARPCHECK_SAMPLES=lots did not fail all $all tests"; }
for line in "validate_power_warps: WARPCHECK_SAMPLES='lots' is not a count" \
            "warpcheck: WARPCHECK_SAMPLES='lots' is not a count .*; no check ran"; do
  grep -q -- "$line" "$work/invalid.log" || fail "WARPCHECK_SAMPLES=lots: no line '$line'"
done

# A failing ctest test of warpcheck_discover_tests writes its evidence and names it.
status=0
(cd "$b" && WARPCHECK_EVIDENCE_DIR="$work/ctest_evidence" ctest -R 'wrong/chi2/power_wrong' --output-on-failure \
  > "$work/wrong_ctest.log" 2>&1) || status=$?
[ "$status" -ne 0 ] || fail "the wrong warp's ctest test passed"
grep -q "HTML report written to $work/ctest_evidence/ctest/wrong/power_wrong_n_2__chi2.html" "$work/wrong_ctest.log" ||
  { cat "$work/wrong_ctest.log"; fail "the failing ctest test does not name its evidence"; }
grep -q "power_wrong\[n=2\]" "$work/ctest_evidence/ctest/wrong/power_wrong_n_2__chi2.html" || fail "no HTML evidence from ctest"

# Names that would collide get a hash suffix each, and every test runs.
"$b/awkward_registration_test" > "$work/awkward.txt" 2>&1 || { cat "$work/awkward.txt"; fail "awkward_registration_test failed"; }
[ "$("$b/awkward_registration_test" --gtest_list_tests | grep -cE '^  Passes/power_n_2_[0-9a-f]{8}__chi2$')" -eq 2 ] ||
  fail "two cases named alike do not get two suffixed tests: $("$b/awkward_registration_test" --gtest_list_tests)"
# A registration that throws: one failing test with the reason, and a filter
# that then selects nothing fails too.
status=0
BREAK_REGISTRATION=1 "$b/awkward_registration_test" > "$work/broken.txt" 2>&1 || status=$?
[ "$status" -ne 0 ] && grep -q "could not build the suite: the lobe table could not be read" "$work/broken.txt" ||
  { cat "$work/broken.txt"; fail "a registration that throws did not fail its test"; }
status=0
BREAK_REGISTRATION=1 "$b/awkward_registration_test" --gtest_filter='warpcheck/Awkward.Passes/power_n_2_*__chi2' \
  > "$work/broken_filter.txt" 2>&1 || status=$?
[ "$status" -ne 0 ] && grep -q "no test was selected, and the suite warpcheck/Awkward could not be built" "$work/broken_filter.txt" ||
  { cat "$work/broken_filter.txt"; fail "a broken suite whose filter selects nothing passed"; }
# A program built on warpcheck::main says its own name in its messages.
status=0
BREAK_REGISTRATION=1 "$b/validate_awkward" --all > "$work/broken_main.txt" 2>&1 || status=$?
[ "$status" -eq 2 ] && grep -q "^validate_awkward: could not register the warps: the lobe table could not be read" \
  "$work/broken_main.txt" || { cat "$work/broken_main.txt"; fail "validate_awkward does not say its own name"; }
status=0
"$b/validate_power_warps" --filter powr > "$work/typo.txt" 2>&1 || status=$?
[ "$status" -eq 2 ] && grep -q "^validate_power_warps: no warp case matches 'powr' (did you mean 'power'" "$work/typo.txt" ||
  { cat "$work/typo.txt"; fail "validate_power_warps does not suggest 'power' under its own name"; }

# A wrong warp added: the gtest binary fails, with the complete failure text.
status=0
WARPCHECK_EVIDENCE_DIR="$work/evidence" "$b/power_warps_test_wrong" --gtest_filter='*power_wrong*' \
  > "$work/wrong.txt" 2>&1 || status=$?
echo "--- the failure text of the wrong warp (power_warps_test_wrong --gtest_filter='*power_wrong*'):"
sed -n '/warpcheck: chi2 failed/,/evidence:/p' "$work/wrong.txt"
echo "---"
[ "$status" -ne 0 ] || fail "the wrong warp passed its gtest tests"
for line in "warpcheck: chi2 failed on power_wrong\[n=2\]" "^FAIL  *chi2  *power_wrong\[n=2\]  *[^ ]*x level  *chi2 " \
            "FAIL chi2 power_wrong\[n=2\]: " "p-value .* is below the corrected level" \
            "chi2 power_wrong\[n=2\]: p-value .* at level " \
            "rerun: WARPCHECK_SEED=1 WARPCHECK_SAMPLES=200000 WARPCHECK_ALPHA=0.01 .*power_warps_test_wrong --gtest_filter='warpcheck/PowerWarps.Passes/power_wrong_n_2__chi2'" \
            "evidence: $work/evidence/gtest/warpcheck_PowerWarps/power_wrong_n_2__chi2.html"; do
  grep -q -- "$line" "$work/wrong.txt" || fail "the failure text lacks: $line"
done
grep -q "power_wrong\[n=2\]" "$work/evidence/gtest/warpcheck_PowerWarps/power_wrong_n_2__chi2.html" || fail "no HTML evidence"
# Located at the user's WARPCHECK_TEST_SUITE line, never in warpcheck's own source.
grep -q "power_warps_test.cpp:$suite_line: Failure" "$work/wrong.txt" || fail "the failure is not at power_warps_test.cpp:$suite_line"
! grep -q "warpcheck_gtest.cpp" "$work/wrong.txt" || fail "a failure names warpcheck's own source"
# A failure that no p-value decided has no p-value line.
"$b/power_warps_test_wrong" --gtest_filter='*power_wrong_n_2__tabulated' > "$work/wrong_tabulated.txt" 2>&1 &&
  fail "the wrong warp passed tabulated"
grep -q "FAIL tabulated power_wrong\[n=2\]: " "$work/wrong_tabulated.txt" || { cat "$work/wrong_tabulated.txt"; fail "no tabulated failure"; }
! grep -Eq "p-value|level" "$work/wrong_tabulated.txt" || { cat "$work/wrong_tabulated.txt"; fail "a p-value line where no test was done"; }
# The same through EXPECT_WARP_PASSES on a warp object with its case info.
WARPCHECK_EVIDENCE_DIR="$work/evidence" "$b/power_warps_test_wrong" --gtest_filter='PowerWarp.WrongLobe' \
  > "$work/wrong_lobe.txt" 2>&1 && fail "EXPECT_WARP_PASSES passed the wrong warp"
for line in "warpcheck: warpcheck::make_warp_case(lobe(2), WrongPowerWarp{}) (power_lobe\[n=2\]) failed checks:" \
            "FAIL chi2 power_lobe\[n=2\]: p-value" "rerun: .*--gtest_filter='PowerWarp.WrongLobe'" \
            "evidence: $work/evidence/gtest/PowerWarp/power_lobe_n_2.html"; do
  grep -q -- "$line" "$work/wrong_lobe.txt" || { cat "$work/wrong_lobe.txt"; fail "EXPECT_WARP_PASSES's text lacks: $line"; }
done
lobe_line=$(grep -n 'WrongPowerWarp{}' "$example_dir/power_warps_test.cpp" | cut -d: -f1)
grep -q "power_warps_test.cpp:$lobe_line: Failure" "$work/wrong_lobe.txt" || fail "EXPECT_WARP_PASSES's failure is not at its line"

# A wrong BSDF (wi uniform while pdf() says cos / pi, each weight agreeing with
# f() and pdf()): the suite's tests of where its samples go fail, and none of
# the checks of its weights; the evidence holds the maps of the sphere.
status=0
WARPCHECK_EVIDENCE_DIR="$work/evidence" "$b/power_warps_test_wrong" --gtest_filter='*diffuse_uniform_sampled*' \
  > "$work/wrong_bsdf.txt" 2>&1 || status=$?
[ "$status" -ne 0 ] || fail "the wrong BSDF passed its gtest tests"
for check in bsdf_chi2 bsdf_unbinned; do
  grep -q "warpcheck: $check failed on diffuse_uniform_sampled\[theta_o=60\]" "$work/wrong_bsdf.txt" ||
    { cat "$work/wrong_bsdf.txt"; fail "$check did not fail the wrong BSDF"; }
done
for check in bsdf_weight bsdf_albedo bsdf_reciprocity; do
  ! grep -q "warpcheck: $check failed on diffuse_uniform_sampled" "$work/wrong_bsdf.txt" ||
    fail "$check failed the wrong BSDF, whose weights agree with f() and pdf()"
done
chi2_evidence="$work/evidence/gtest/warpcheck_PowerWarps/diffuse_uniform_sampled_theta_o_60__bsdf_chi2.html"
grep -q "evidence: $chi2_evidence" "$work/wrong_bsdf.txt" && grep -q 'residual (obs - exp) / sqrt(exp)' "$chi2_evidence" ||
  fail "no map of the sphere in the wrong BSDF's bsdf_chi2 evidence"
# EXPECT_BSDF_PASSES on it: every BSDF check in one run, at the user's line,
# and the evidence of them all, the plots across its family included.
WARPCHECK_EVIDENCE_DIR="$work/evidence" "$b/power_warps_test_wrong" --gtest_filter='DiffuseBsdf.UniformlySampled' \
  > "$work/wrong_bsdf_assert.txt" 2>&1 && fail "EXPECT_BSDF_PASSES passed the wrong BSDF"
echo "--- the failure text of the wrong BSDF (power_warps_test_wrong --gtest_filter='DiffuseBsdf.UniformlySampled'):"
sed -n '/failed checks:/,/evidence:/p' "$work/wrong_bsdf_assert.txt"
echo "---"
for line in "warpcheck: wrong (diffuse_uniform_grazing\[theta_o=85\]) failed checks:" "FAIL bsdf_chi2 diffuse_uniform_grazing\[theta_o=85\]: " \
            "FAIL bsdf_unbinned diffuse_uniform_grazing\[theta_o=85\]: " \
            "evidence: $work/evidence/gtest/DiffuseBsdf/diffuse_uniform_grazing_theta_o_85.html"; do
  grep -q -- "$line" "$work/wrong_bsdf_assert.txt" || { cat "$work/wrong_bsdf_assert.txt"; fail "EXPECT_BSDF_PASSES's text lacks: $line"; }
done
bsdf_line=$(grep -n 'EXPECT_BSDF_PASSES(wrong)' "$example_dir/power_warps_test.cpp" | cut -d: -f1)
grep -q "power_warps_test.cpp:$bsdf_line: Failure" "$work/wrong_bsdf_assert.txt" ||
  fail "EXPECT_BSDF_PASSES's failure is not at its line"
grep -q "Across the family: albedo against theta_o" "$work/evidence/gtest/DiffuseBsdf/diffuse_uniform_grazing_theta_o_85.html" ||
  fail "no albedo against theta_o in EXPECT_BSDF_PASSES's evidence"

# A light and the MIS of the BSDF and the light (EXPECT_LIGHT_PASSES,
# EXPECT_MIS_PASSES) pass; the MIS whose sum takes the light's pdf per area
# fails mis_weights, at the user's line.
WARPCHECK_EVIDENCE_DIR="$work/evidence" "$b/power_warps_test_wrong" \
  --gtest_filter='SphereLight.SeenFromASurface:DirectLighting.DiffuseUnderASphere' > "$work/light.txt" 2>&1 ||
  { cat "$work/light.txt"; fail "EXPECT_LIGHT_PASSES or EXPECT_MIS_PASSES failed a correct light"; }
WARPCHECK_EVIDENCE_DIR="$work/evidence" "$b/power_warps_test_wrong" --gtest_filter='DirectLighting.AreaPdfInTheSum' \
  > "$work/wrong_mis.txt" 2>&1 && fail "EXPECT_MIS_PASSES passed an area pdf in the MIS sum"
grep -q "FAIL mis_weights direct_area_pdf: " "$work/wrong_mis.txt" || { cat "$work/wrong_mis.txt"; fail "mis_weights did not fail the area pdf"; }
mis_line=$(grep -n 'EXPECT_MIS_PASSES(direct_lighting("direct_area_pdf"' "$example_dir/power_warps_test.cpp" | cut -d: -f1)
grep -q "power_warps_test.cpp:$mis_line: Failure" "$work/wrong_mis.txt" || fail "EXPECT_MIS_PASSES's failure is not at its line"

# The same figures and level as the validate program of the same warps and seed,
# whose rerun line names that program.
status=0
# (--wide: whole figures, as the gtest text prints them; the BSDF names widen the case column.)
"$b/validate_power_warps_wrong" --all --samples "$WARPCHECK_SAMPLES" --color never --wide > "$work/validate_wrong.txt" 2>&1 || status=$?
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
# (The level printed after the suite test's failure: a shard may also run
# EXPECT_WARP_PASSES's test, whose family is its own case.)
shard_level=$(sed -n '/^FAIL  *chi2  *power_wrong/,/^Statistical tests:/p' "$(grep -l 'FAIL  *chi2  *power_wrong' "$work"/shard?.txt)" |
  grep '^Statistical tests:')
[ "$shard_level" = "$(level "$work/validate_wrong.txt")" ] || fail "a gtest shard's level is not the whole suite's: $shard_level"
echo "gtest example: built against the installed package; $jobs ctest tests, one per (case, check); passed"

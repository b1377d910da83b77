// warpcheck inside a GoogleTest suite (target warpcheck::gtest).
//
// One assertion for one case, with every check that applies:
//
//     TEST(MyWarps, Cone) {
//         EXPECT_WARP_PASSES(warpcheck::make_warp_case(info, MyCone(0.3f)));
//     }
//
// and for a BSDF at one outgoing direction, with every BSDF check:
//
//     EXPECT_BSDF_PASSES(warpcheck::make_bsdf_case(info, {.wo = warpcheck::bsdf_direction(60)}, MyDiffuse{0.7f}));
//
// and for a light seen from one reference point, or an MIS case (a BSDF and
// lights at one shading point), with every check that applies:
//
//     EXPECT_LIGHT_PASSES(warpcheck::make_light_case(info, {.ref = p, .normal = n}, MyLight{}));
//     EXPECT_MIS_PASSES(warpcheck::make_mis_case(info, claims, bsdf_case, light_case));
//
// and a family's parameters at their extremes (validate --fuzz: the ranges its
// axes declare, their ends first, through the cheap checks; each failure
// shrunk to the simplest parameters that still fail):
//
//     EXPECT_FUZZ_CLEAN((warpcheck::CaseFamily{info, {{"alpha", {0.3}, {{1e-4, 1}}}}, make_my_case}));
//
// and one test per (case, check) of everything a registration function adds:
//
//     WARPCHECK_TEST_SUITE(MyWarps, warpcheck_register);
//
// which gives tests named warpcheck/MyWarps.Passes/<case>__<check> (BSDF cases
// with the BSDF checks, e.g. my_diffuse_theta_o_60__bsdf_chi2), e.g.
// warpcheck/MyWarps.Passes/linear_a_1_b_3__chi2, for --gtest_filter and, through
// gtest_discover_tests, as ctest names (no "# GetParam() = ..." after them).
// A failure is reported at the line of the WARPCHECK_TEST_SUITE (or of the
// EXPECT_WARP_PASSES) in the user's file; it prints the lines `validate` prints
// for it (the row with its key figure, the message, the command that reruns
// it; the p-value and the level when the p-value is what failed) and writes
// the case's HTML evidence to a file it names. A check that does not apply to
// a case is a skipped test (GTEST_SKIP) that says why. The figures are
// `validate`'s for the same seed and sample count: each job draws from the
// stream of its names and the seed, and the Šidák level is that of the whole
// suite (every job of the registry, whatever --gtest_filter or
// GTEST_SHARD_INDEX selects).
//
// Settings come from the environment, so that a test binary needs no flags:
//   WARPCHECK_SEED (default 1), WARPCHECK_SAMPLES (default 1000000; 1e6, 10M
//   and 1_000_000 are read), WARPCHECK_ALPHA (family-wise, default 0.01),
//   WARPCHECK_TIME_BUDGET (CPU seconds per check, as validate --time-budget),
//   WARPCHECK_MEMORY_LIMIT (MiB the workers share, as --memory-limit),
//   WARPCHECK_EVIDENCE_DIR (default warpcheck-evidence, in the working
//   directory; the files go in its gtest/<test suite>/ folder).
// An invalid value fails every test of the suite with its name and the reason;
// so does a registration function that throws (and a run in which, for that
// reason, no test at all is selected).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "validate/api/registry.h"
#include "validate/api/warp_case.h"

namespace warpcheck::gtest {

/// Success when every default check that applies to `warp` passes (the BSDF
/// checks for a BSDF case), judged as one run (the Šidák family: those
/// checks). Otherwise the failure lines and the path of the evidence. For EXPECT_PRED_FORMAT1; see EXPECT_WARP_PASSES.
::testing::AssertionResult WarpCasePasses(const char* expression, const WarpCase& warp);
::testing::AssertionResult WarpCasePasses(const char* expression, const std::unique_ptr<WarpCase>& warp);

/// The same for a BSDF or phase function case (make_bsdf_case, make_phase_case):
/// every BSDF check that applies to it passes (bsdf_chi2, bsdf_unbinned,
/// bsdf_weight, ...); a case that is not a BSDF's is a failure that says so.
/// For EXPECT_PRED_FORMAT1; see EXPECT_BSDF_PASSES.
::testing::AssertionResult BsdfCasePasses(const char* expression, const WarpCase& bsdf);
::testing::AssertionResult BsdfCasePasses(const char* expression, const std::unique_ptr<WarpCase>& bsdf);

/// The same for a light seen from a reference point (make_light_case): every
/// check that applies to it passes (the warp checks on its directions and
/// light_radiance, light_support, light_irradiance); a case that is not a
/// light's is a failure that says so. For EXPECT_PRED_FORMAT1; see EXPECT_LIGHT_PASSES.
::testing::AssertionResult LightCasePasses(const char* expression, const WarpCase& light);
::testing::AssertionResult LightCasePasses(const char* expression, const std::unique_ptr<WarpCase>& light);

/// The same for an MIS case (make_mis_case): every check that applies to it
/// passes (mis_weights, mis_estimator, consistency, sample_pdf); a case that
/// is not an MIS case is a failure that says so. See EXPECT_MIS_PASSES.
::testing::AssertionResult MisCasePasses(const char* expression, const WarpCase& mis);
::testing::AssertionResult MisCasePasses(const char* expression, const std::unique_ptr<WarpCase>& mis);

/// Success when `validate --fuzz` finds nothing in `family` (a CaseFamily:
/// the base info, axes with the ranges to draw from, the maker): every point
/// passes the cheap checks, and the maker makes every point inside the ranges.
/// Otherwise each finding, shrunk, with its rerun line. WARPCHECK_SAMPLES
/// sets the samples per check where set (else --fuzz's 20,000).
::testing::AssertionResult FamilyFuzzesClean(const char* expression, const CaseFamily& family);

/// Registers one GoogleTest test per (case, check) job of `register_cases`
/// (called with a registry that has the built-in checks), in suite
/// "warpcheck/<suite_name>", located at `file`:`line`. Called by
/// WARPCHECK_TEST_SUITE while GoogleTest initialises (after main() has begun,
/// so a registration function may rely on any static object); returns no
/// parameters.
std::vector<int> register_job_tests(const char* suite_name, void (*register_cases)(Registry&), const char* file,
                                    int line);

/// The hook of WARPCHECK_TEST_SUITE: a value-parameterised suite that is never
/// instantiated, whose (empty) generator registers the real tests.
class SuiteRegistrar : public ::testing::TestWithParam<int> {};

}  // namespace warpcheck::gtest

/// EXPECT_WARP_PASSES(warp_case): every default check that applies to the case
/// passes. The argument is a WarpCase or the std::unique_ptr that
/// make_warp_case returns (a warp object plus its case info).
#define EXPECT_WARP_PASSES(warp_case) EXPECT_PRED_FORMAT1(::warpcheck::gtest::WarpCasePasses, warp_case)
#define ASSERT_WARP_PASSES(warp_case) ASSERT_PRED_FORMAT1(::warpcheck::gtest::WarpCasePasses, warp_case)

/// EXPECT_BSDF_PASSES(bsdf_case): every BSDF check that applies to the case
/// passes (one case is one outgoing direction: bsdf_direction(theta_o)). The
/// argument is a BsdfCase or the std::unique_ptr that make_bsdf_case and
/// make_phase_case return. EXPECT_WARP_PASSES takes a BSDF case as well; this
/// one also fails when the case is not a BSDF's.
#define EXPECT_BSDF_PASSES(bsdf_case) EXPECT_PRED_FORMAT1(::warpcheck::gtest::BsdfCasePasses, bsdf_case)
#define ASSERT_BSDF_PASSES(bsdf_case) ASSERT_PRED_FORMAT1(::warpcheck::gtest::BsdfCasePasses, bsdf_case)

/// EXPECT_LIGHT_PASSES(light_case): every check that applies to a light case
/// (make_light_case: one reference point) passes.
#define EXPECT_LIGHT_PASSES(light_case) EXPECT_PRED_FORMAT1(::warpcheck::gtest::LightCasePasses, light_case)
#define ASSERT_LIGHT_PASSES(light_case) ASSERT_PRED_FORMAT1(::warpcheck::gtest::LightCasePasses, light_case)

/// EXPECT_FUZZ_CLEAN(family): `validate --fuzz` over the ranges the family's
/// axes declare finds nothing (FamilyFuzzesClean). Put a braced CaseFamily in
/// parentheses: the macro's argument must not contain a bare comma.
#define EXPECT_FUZZ_CLEAN(family) EXPECT_PRED_FORMAT1(::warpcheck::gtest::FamilyFuzzesClean, family)
#define ASSERT_FUZZ_CLEAN(family) ASSERT_PRED_FORMAT1(::warpcheck::gtest::FamilyFuzzesClean, family)

/// EXPECT_MIS_PASSES(mis_case): every check that applies to an MIS case
/// (make_mis_case: a BSDF and lights at one shading point) passes.
#define EXPECT_MIS_PASSES(mis_case) EXPECT_PRED_FORMAT1(::warpcheck::gtest::MisCasePasses, mis_case)
#define ASSERT_MIS_PASSES(mis_case) ASSERT_PRED_FORMAT1(::warpcheck::gtest::MisCasePasses, mis_case)

/// One gtest test per (case, check) of the cases `register_cases` adds, e.g.
///   WARPCHECK_TEST_SUITE(MyWarps, warpcheck_register);
/// at namespace scope. GoogleTest evaluates a parameter generator when it
/// initialises; this one registers the tests (GoogleTest's RegisterTest, so
/// that they carry no parameter text) and yields nothing.
#define WARPCHECK_TEST_SUITE(suite_name, register_cases)                                                       \
    class suite_name : public ::warpcheck::gtest::SuiteRegistrar {};                                           \
    TEST_P(suite_name, Registrar) {}                                                                           \
    INSTANTIATE_TEST_SUITE_P(warpcheck, suite_name,                                                            \
                             ::testing::ValuesIn(::warpcheck::gtest::register_job_tests(                      \
                                 #suite_name, register_cases, __FILE__, __LINE__)));                           \
    GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(suite_name)

// warpcheck inside a GoogleTest suite (target warpcheck::gtest).
//
// One assertion for one case, with every check that applies:
//
//     TEST(MyWarps, Cone) {
//         EXPECT_WARP_PASSES(warpcheck::make_warp_case(info, MyCone(0.3f)));
//     }
//
// and one test per (case, check) of everything a registration function adds:
//
//     WARPCHECK_TEST_SUITE(MyWarps, warpcheck_register);
//
// which gives tests named warpcheck/MyWarps.Passes/<case>__<check>, e.g.
// warpcheck/MyWarps.Passes/linear_a_1_b_3__chi2, for --gtest_filter. A failure
// prints the lines `validate` prints for it (the row with its key figure, the
// message, the p-value and the level, the command that reruns it) and writes
// the case's HTML evidence to a file it names. The figures are `validate`'s
// for the same seed and sample count: each job draws from the stream of its
// names and the seed, and the Šidák level is that of the whole suite (every
// job of the registry, whatever --gtest_filter or GTEST_SHARD_INDEX selects).
//
// Settings come from the environment, so that a test binary needs no flags:
//   WARPCHECK_SEED (default 1), WARPCHECK_SAMPLES (default 1000000),
//   WARPCHECK_ALPHA (family-wise, default 0.01),
//   WARPCHECK_EVIDENCE_DIR (default warpcheck-evidence, in the working directory).
#pragma once

#include <cstddef>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "validate/registry.h"
#include "validate/runner.h"

namespace warpcheck::gtest {

/// How the checks run inside a test.
struct Settings {
    RunOptions run;                                 ///< seed, samples, alpha, as in `validate`
    std::string evidence_dir = "warpcheck-evidence";  ///< where failing cases' HTML goes
};

/// The defaults with the WARPCHECK_* variables applied; throws
/// std::invalid_argument naming a variable whose value is not valid.
Settings settings_from_environment();

/// Success when every default check that applies to `warp` passes, judged as
/// one run (the Šidák family: those checks). Otherwise the failure lines and
/// the path of the evidence. For EXPECT_PRED_FORMAT1; see EXPECT_WARP_PASSES.
::testing::AssertionResult WarpCasePasses(const char* expression, const WarpCase& warp);
::testing::AssertionResult WarpCasePasses(const char* expression, const std::unique_ptr<WarpCase>& warp);

/// The whole run a registration function defines: its cases with the built-in
/// checks, the jobs `validate --all` would run, and their Šidák family.
struct Suite {
    Registry registry;
    std::vector<Job> jobs;
    int family_tests = 0;
    Settings settings;
    std::string error;  ///< why the suite could not be built (then every test fails with it)
};

/// One (case, check) job of a suite: the parameter of WARPCHECK_TEST_SUITE's tests.
struct JobParam {
    std::shared_ptr<const Suite> suite;
    std::size_t index = 0;
};

/// The jobs of `register_cases` (called with a registry that has the built-in
/// checks), one parameter each; one parameter carrying the error if the
/// registration throws or a setting is invalid.
std::vector<JobParam> jobs_of(void (*register_cases)(Registry&));

/// "<case>__<check>" with every character but letters and digits as '_'.
std::string job_test_name(const ::testing::TestParamInfo<JobParam>& info);

/// How gtest shows a parameter (instead of its bytes).
void PrintTo(const JobParam& param, std::ostream* out);

/// The fixture of WARPCHECK_TEST_SUITE: runs the parameter's job.
class JobTest : public ::testing::TestWithParam<JobParam> {
protected:
    void run_job() const;
};

}  // namespace warpcheck::gtest

/// EXPECT_WARP_PASSES(warp_case): every default check that applies to the case
/// passes. The argument is a WarpCase or the std::unique_ptr that
/// make_warp_case returns (a warp object plus its case info).
#define EXPECT_WARP_PASSES(warp_case) EXPECT_PRED_FORMAT1(::warpcheck::gtest::WarpCasePasses, warp_case)
#define ASSERT_WARP_PASSES(warp_case) ASSERT_PRED_FORMAT1(::warpcheck::gtest::WarpCasePasses, warp_case)

/// One gtest test per (case, check) of the cases `register_cases` adds, e.g.
///   WARPCHECK_TEST_SUITE(MyWarps, warpcheck_register);
#define WARPCHECK_TEST_SUITE(suite_name, register_cases)                                              \
    class suite_name : public ::warpcheck::gtest::JobTest {};                                         \
    TEST_P(suite_name, Passes) { run_job(); }                                                         \
    INSTANTIATE_TEST_SUITE_P(warpcheck, suite_name, ::testing::ValuesIn(::warpcheck::gtest::jobs_of(register_cases)), \
                             ::warpcheck::gtest::job_test_name)

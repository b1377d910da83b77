#include "validate/gtest/warpcheck_gtest.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <map>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "reports/outputs.h"
#include "reports/terminal_table.h"
#include "sampling/hash.h"
#include "validate/api/light_case.h"
#include "validate/cli/cli_input.h"
#include "validate/gtest/job_tests.h"
#include "validate/run/fuzz.h"
#include "validate/run/runner.h"
#include "warpcheck/version.h"

namespace warpcheck::gtest {
namespace {

/// Letters and digits kept, everything else '_', trailing '_' dropped: a gtest
/// name and a file name.
std::string identifier(const std::string& text) {
    std::string id;
    for (char c : text) id += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    while (!id.empty() && id.back() == '_') id.pop_back();
    return id;
}

/// The command that reruns the current gtest test with these settings, or
/// empty outside a test.
std::string gtest_rerun_command(const Settings& settings) {
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    if (!test) return {};
    std::error_code ec;
    std::string program = std::filesystem::read_symlink("/proc/self/exe", ec).string();
    if (ec) program = "<this test program>";
    return fmt::format("WARPCHECK_SEED={} WARPCHECK_SAMPLES={} WARPCHECK_ALPHA={} {} --gtest_filter='{}.{}'",
                       settings.run.seed, settings.run.samples, settings.run.alpha, program, test->test_suite_name(),
                       test->name());
}

/// The gtest test suite running now ("warpcheck/MyWarps", "MyWarps"), or empty outside a test.
std::string current_test_suite() {
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    return test ? test->test_suite_name() : "";
}

/// Writes the run's HTML report as evidence_path(settings, current suite,
/// stem); says where, or why it could not.
std::string write_evidence(const RunResult& run, const Settings& settings, const std::string& stem) {
    try {
        const std::filesystem::path path = evidence_path(settings, current_test_suite(), stem);
        std::filesystem::create_directories(path.parent_path());
        write_html_report(run, path.string());
        return "evidence: " + path.string();
    } catch (const std::exception& e) {
        return fmt::format("evidence: not written ({})", e.what());
    }
}

/// The jobs run as part of a run whose Šidák family is `family_tests`, in
/// worker processes as `validate` runs them.
RunResult run_part(const std::vector<Job>& jobs, int family_tests, const Settings& settings) {
    RunOptions options = settings.run;
    options.family_tests = family_tests;
    Isolation isolation;
    isolation.enabled = true;
    if (settings.memory_limit_mib) isolation.memory_budget = *settings.memory_limit_mib << 20;
    RunResult run = run_jobs(jobs, options, {}, isolation);
    run.info.tool_version = WARPCHECK_VERSION;
    run.info.command_line = "GoogleTest: " + gtest_rerun_command(settings);
    return run;
}

/// Success, or the lines `validate` prints for the failures, the p-value and
/// level of each failure that the p-value decided (none where no test was
/// done), and the evidence written under the name `evidence_stem`.
::testing::AssertionResult judge(RunResult run, const Settings& settings, const std::string& evidence_stem) {
    if (run.all_passed()) return ::testing::AssertionSuccess();
    if (const std::string rerun = gtest_rerun_command(settings); !rerun.empty())
        for (CheckResult& r : run.results) r.rerun_command = rerun;
    // The level of the run's statistical tests, only if a p-value is among the failures.
    if (std::none_of(run.results.begin(), run.results.end(),
                     [](const CheckResult& r) { return r.verdict != Verdict::Pass && r.p_value; }))
        run.info.statistical_tests = 0;
    std::ostringstream text;
    TableStyle style;
    style.failures_only = true;
    style.width = 0;  // whole names and figures: a test log has no columns to fit
    style.families = false;
    style.weakest = 0;
    print_table(run, text, style);
    for (const CheckResult& r : run.results)
        if (r.verdict != Verdict::Pass && r.p_value && r.level && !(*r.p_value >= *r.level))
            text << fmt::format("{} {}: p-value {:.4g} at level {:.4g}\n", r.check_name, r.case_name, *r.p_value,
                                *r.level);
    text << write_evidence(run, settings, evidence_stem) << "\n";
    return ::testing::AssertionFailure() << text.str();
}

const Registry& builtin_checks() {
    static const Registry registry = [] {
        Registry r;
        register_builtin_checks(r);
        return r;
    }();
    return registry;
}

/// The whole run a registration function defines: its cases with the
/// built-in checks, the jobs `validate --all` would run, and their Šidák family.
struct Suite {
    Registry registry;
    std::vector<Job> jobs;
    int family_tests = 0;
    Settings settings;
    std::string settings_error;  ///< an invalid WARPCHECK_* value: every test fails with it
    std::string error;           ///< why the suite could not be built: its one test fails with it
};

/// One (case, check) job of a suite, or the suite's failure to build.
class JobTest : public ::testing::Test {
public:
    JobTest(std::shared_ptr<const Suite> suite, std::size_t index, std::string name, const char* file, int line)
        : suite_(std::move(suite)), index_(index), name_(std::move(name)), file_(file), line_(line) {}

    void TestBody() override {
        if (!suite_->error.empty()) return fail("warpcheck: could not build the suite: " + suite_->error);
        if (!suite_->settings_error.empty()) return fail("warpcheck: " + suite_->settings_error + "; no check ran");
        const Job& job = suite_->jobs[index_];
        if (!job.not_applicable.empty())
            return report(fmt::format("warpcheck: {} does not apply to {}: {}", job.check->name(), job.warp->name(),
                                      job.not_applicable),
                          ::testing::TestPartResult::kSkip);
        const ::testing::AssertionResult verdict =
            judge(run_part({job}, suite_->family_tests, suite_->settings), suite_->settings, name_);
        if (!verdict)
            fail(fmt::format("warpcheck: {} failed on {}:\n{}", job.check->name(), job.warp->name(), verdict.message()));
    }

private:
    // At the user's WARPCHECK_TEST_SUITE line: the location ADD_FAILURE_AT and
    // GTEST_SKIP report through, without ADD_FAILURE_AT's "Failed" line.
    void report(const std::string& message, ::testing::TestPartResult::Type type) const {
        GTEST_MESSAGE_AT_(file_, line_, message.c_str(), type);
    }
    void fail(const std::string& message) const { report(message, ::testing::TestPartResult::kNonFatalFailure); }

    std::shared_ptr<const Suite> suite_;
    std::size_t index_;
    std::string name_;
    const char* file_;
    int line_;
};

/// A suite that could not be built has one test, which names the reason; a
/// run that selects no test at all (a filter naming one of the tests the
/// suite would have had, as ctest does) fails with the reason too, instead of
/// passing with nothing run.
class BrokenSuiteListener : public ::testing::EmptyTestEventListener {
public:
    BrokenSuiteListener(std::string suite, std::string error, const char* file, int line)
        : suite_(std::move(suite)), error_(std::move(error)), file_(file), line_(line) {}

    void OnTestIterationStart(const ::testing::UnitTest& unit_test, int) override {
        if (unit_test.test_to_run_count() == 0) {
            const std::string message =
                fmt::format("warpcheck: no test was selected, and the suite {} could not be built: {}", suite_, error_);
            GTEST_MESSAGE_AT_(file_, line_, message.c_str(), ::testing::TestPartResult::kNonFatalFailure);
        }
    }

private:
    std::string suite_, error_;
    const char* file_;
    int line_;
};

/// The suite of `register_cases`: jobs listed with the default settings if the
/// environment's are invalid (the test names do not depend on them).
std::shared_ptr<Suite> build_suite(void (*register_cases)(Registry&)) {
    auto suite = std::make_shared<Suite>();
    try {
        suite->settings = settings_from_environment();
    } catch (const std::exception& e) {
        suite->settings_error = e.what();
    }
    try {
        register_builtin_checks(suite->registry);
        register_cases(suite->registry);
        suite->jobs = select_jobs(suite->registry, {}, {}, suite->settings.run);
        suite->family_tests = statistical_tests(suite->jobs);
    } catch (const std::exception& e) {
        suite->error = e.what();
    } catch (...) {  // registration is foreign code
        suite->error = "an exception that is not a std::exception";
    }
    if (suite->error.empty() && suite->jobs.empty())
        suite->error = "the registration function added no case that a check applies to";
    if (!suite->error.empty()) suite->jobs.clear();
    return suite;
}

}  // namespace

Settings settings_from_environment() {
    Settings s;
    if (const std::string problem = apply_environment_settings(s.run, &s.memory_limit_mib); !problem.empty())
        throw std::invalid_argument(problem);
    if (const char* dir = std::getenv("WARPCHECK_EVIDENCE_DIR"); dir && *dir) s.evidence_dir = dir;
    return s;
}

::testing::AssertionResult WarpCasePasses(const char* expression, const WarpCase& warp) {
    Settings settings;
    try {
        settings = settings_from_environment();
    } catch (const std::exception& e) {
        return ::testing::AssertionFailure() << "warpcheck: " << e.what() << "; no check ran";
    }
    if (const std::vector<std::string> problems = case_problems(warp); !problems.empty())
        return ::testing::AssertionFailure() << "warpcheck: " << expression << ": "
                                             << declaration_error("warp case " + warp.name(), problems).what();
    std::vector<Job> jobs;
    for (const auto& check : builtin_checks().checks())
        if (check->runs_by_default(settings.run) && check_is_for(*check, warp) && check->applicability(warp).applies())
            jobs.push_back({&warp, check.get()});
    const ::testing::AssertionResult verdict =
        judge(run_part(jobs, statistical_tests(jobs), settings), settings, identifier(warp.name()));
    if (verdict) return verdict;
    return ::testing::AssertionFailure() << "warpcheck: " << expression << " (" << warp.name()
                                         << ") failed checks:\n" << verdict.message();
}

::testing::AssertionResult WarpCasePasses(const char* expression, const std::unique_ptr<WarpCase>& warp) {
    if (!warp) return ::testing::AssertionFailure() << "warpcheck: " << expression << " is a null warp case";
    return WarpCasePasses(expression, *warp);
}

namespace {

/// Every check that applies passes, for a case of one kind; otherwise a
/// failure saying that it is not `a_kind_case` (its article, kind and maker).
::testing::AssertionResult KindPasses(const char* expression, const WarpCase& warp, bool of_kind,
                                      const char* a_kind_case) {
    if (!of_kind)
        return ::testing::AssertionFailure() << "warpcheck: " << expression << " (" << warp.name() << ") is not "
                                             << a_kind_case;
    return WarpCasePasses(expression, warp);
}

::testing::AssertionResult NullCase(const char* expression, const char* kind) {
    return ::testing::AssertionFailure() << "warpcheck: " << expression << " is a null " << kind << " case";
}

}  // namespace

::testing::AssertionResult BsdfCasePasses(const char* expression, const WarpCase& bsdf) {
    return KindPasses(expression, bsdf, bsdf.sample_returns() == SampleReturns::Bsdf,
                      "a BSDF case (make_bsdf_case, make_phase_case): EXPECT_WARP_PASSES checks a warp");
}

::testing::AssertionResult BsdfCasePasses(const char* expression, const std::unique_ptr<WarpCase>& bsdf) {
    return bsdf ? BsdfCasePasses(expression, *bsdf) : NullCase(expression, "BSDF");
}

::testing::AssertionResult LightCasePasses(const char* expression, const WarpCase& light) {
    return KindPasses(expression, light, as_light(light) != nullptr, "a light case (make_light_case)");
}

::testing::AssertionResult LightCasePasses(const char* expression, const std::unique_ptr<WarpCase>& light) {
    return light ? LightCasePasses(expression, *light) : NullCase(expression, "light");
}

::testing::AssertionResult MisCasePasses(const char* expression, const WarpCase& mis) {
    return KindPasses(expression, mis, as_mis(mis) != nullptr, "an MIS case (make_mis_case)");
}

::testing::AssertionResult MisCasePasses(const char* expression, const std::unique_ptr<WarpCase>& mis) {
    return mis ? MisCasePasses(expression, *mis) : NullCase(expression, "MIS");
}

::testing::AssertionResult FamilyFuzzesClean(const char* expression, const CaseFamily& family) {
    Settings settings;
    try {
        settings = settings_from_environment();
    } catch (const std::exception& e) {
        return ::testing::AssertionFailure() << "warpcheck: " << e.what() << "; no check ran";
    }
    Registry registry;
    FuzzOptions options;
    try {
        register_builtin_checks(registry);
        registry.add_family(family);
    } catch (const std::exception& e) {
        return ::testing::AssertionFailure() << "warpcheck: " << expression << ": " << e.what();
    }
    if (!family.fuzzable())
        return ::testing::AssertionFailure() << "warpcheck: " << expression << " (" << family.base.family
                                             << ") declares no parameter range (GridAxis::ranges): nothing to fuzz";
    options.run = settings.run;
    if (std::getenv("WARPCHECK_SAMPLES") == nullptr) options.run.samples = 20'000;
    options.isolation.enabled = true;
    if (settings.memory_limit_mib) options.isolation.memory_budget = *settings.memory_limit_mib << 20;
    const FuzzReport report = run_fuzz(registry, options);
    if (report.clean()) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "warpcheck --fuzz of " << expression << " (" << family.base.family
                                         << "):\n"
                                         << fuzz_report_text(report);
}

std::filesystem::path evidence_path(const Settings& settings, const std::string& test_suite, const std::string& stem) {
    std::filesystem::path dir = std::filesystem::absolute(settings.evidence_dir) / "gtest";
    if (const std::string folder = identifier(test_suite); !folder.empty()) dir /= folder;
    // A file name has at most 255 bytes: a longer stem keeps its start and
    // ends with 16 hex digits of a hash of the whole, before its last part
    // (the check, after "__"), so that names stay distinct and say their check.
    constexpr std::size_t kMaxName = 255, kExtension = 5;  // ".html"
    std::string name = stem;
    if (name.size() + kExtension > kMaxName) {
        const std::size_t check_at = name.rfind("__");
        const std::string check = check_at == std::string::npos ? "" : name.substr(check_at);
        const std::string hash = fmt::format("_{:016x}", hash_string(stem));
        const std::size_t keep = kMaxName - kExtension - hash.size() - std::min(check.size(), std::size_t{64});
        name = name.substr(0, keep) + hash + check.substr(0, 64);
    }
    return dir / (name + ".html");
}

std::vector<std::string> job_test_names(const std::vector<Job>& jobs) {
    const auto plain = [](const Job& job) { return identifier(job.warp->name()) + "__" + identifier(job.check->name()); };
    std::map<std::string, std::size_t> uses;
    for (const Job& job : jobs) ++uses[plain(job)];
    std::vector<std::string> names;
    std::map<std::string, std::size_t> taken;
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        std::string name = plain(jobs[i]);
        if (uses[name] > 1)
            name = fmt::format("{}_{:08x}__{}", identifier(jobs[i].warp->name()),
                               hash_string(jobs[i].warp->name()) & 0xFFFFFFFFu, identifier(jobs[i].check->name()));
        // Two names equal even so (a 32-bit hash collision): the job's position settles it.
        if (taken[name]++ > 0) name += fmt::format("_{}", i);
        names.push_back(std::move(name));
    }
    return names;
}

std::vector<int> register_job_tests(const char* suite_name, void (*register_cases)(Registry&), const char* file,
                                    int line) {
    const std::shared_ptr<const Suite> suite = build_suite(register_cases);
    const std::string test_suite = std::string("warpcheck/") + suite_name;
    if (!suite->error.empty()) {
        ::testing::RegisterTest(test_suite.c_str(), "Passes/registration", nullptr, nullptr, file, line,
                                [=]() -> ::testing::Test* { return new JobTest(suite, 0, "registration", file, line); });
        ::testing::UnitTest::GetInstance()->listeners().Append(
            new BrokenSuiteListener(test_suite, suite->error, file, line));
        return {};
    }
    const std::vector<std::string> names = job_test_names(suite->jobs);
    for (std::size_t i = 0; i < names.size(); ++i) {
        const std::string name = names[i];
        ::testing::RegisterTest(test_suite.c_str(), ("Passes/" + name).c_str(), nullptr, nullptr, file, line,
                                [=]() -> ::testing::Test* { return new JobTest(suite, i, name, file, line); });
    }
    return {};
}

}  // namespace warpcheck::gtest

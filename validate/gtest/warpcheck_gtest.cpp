#include "validate/gtest/warpcheck_gtest.h"

#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "reports/outputs.h"
#include "reports/terminal_table.h"
#include "warpcheck/version.h"

namespace warpcheck::gtest {
namespace {

/// The variable's value if it is set and not empty.
const char* variable(const char* name) {
    const char* value = std::getenv(name);
    return value && *value ? value : nullptr;
}

uint64_t unsigned_variable(const char* name, uint64_t fallback, uint64_t min, uint64_t max) {
    const char* text = variable(name);
    if (!text) return fallback;
    errno = 0;
    char* end = nullptr;
    const unsigned long long v = std::strtoull(text, &end, 10);
    if (!std::isdigit(static_cast<unsigned char>(*text)) || *end || errno == ERANGE || v < min || v > max)
        throw std::invalid_argument(fmt::format("{}='{}' is not an integer from {} to {}", name, text, min, max));
    return v;
}

double alpha_variable(const char* name, double fallback) {
    const char* text = variable(name);
    if (!text) return fallback;
    char* end = nullptr;
    const double v = std::strtod(text, &end);
    if (*end || !(v >= 1e-12 && v <= 0.5))
        throw std::invalid_argument(fmt::format("{}='{}' is not a number from 1e-12 to 0.5", name, text));
    return v;
}

/// Letters and digits kept, everything else '_': a gtest name and a file name.
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

/// Writes the run's HTML report as `file` in the evidence folder; says where,
/// or why it could not.
std::string write_evidence(const RunResult& run, const Settings& settings, const std::string& file) {
    try {
        const std::filesystem::path dir = std::filesystem::absolute(settings.evidence_dir);
        std::filesystem::create_directories(dir);
        const std::string path = (dir / file).string();
        write_html_report(run, path);
        return "evidence: " + path;
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
    RunResult run = run_jobs(jobs, options, {}, isolation);
    run.info.tool_version = WARPCHECK_VERSION;
    run.info.command_line = "GoogleTest: " + gtest_rerun_command(settings);
    return run;
}

/// Success, or the lines `validate` prints for the failures, each failure's
/// p-value and level, and the evidence written to `evidence_file`.
::testing::AssertionResult judge(RunResult run, const Settings& settings, const std::string& evidence_file) {
    if (run.all_passed()) return ::testing::AssertionSuccess();
    if (const std::string rerun = gtest_rerun_command(settings); !rerun.empty())
        for (CheckResult& r : run.results) r.rerun_command = rerun;
    std::ostringstream text;
    TableStyle style;
    style.failures_only = true;
    print_table(run, text, style);
    for (const CheckResult& r : run.results)
        if (r.verdict != Verdict::Pass && r.p_value)
            text << fmt::format("{} {}: p-value {:.4g} at level {:.4g}\n", r.check_name, r.case_name, *r.p_value,
                                r.level.value_or(std::nan("")));
    text << write_evidence(run, settings, evidence_file) << "\n";
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

}  // namespace

Settings settings_from_environment() {
    Settings s;
    s.run.seed = unsigned_variable("WARPCHECK_SEED", s.run.seed, 0, UINT64_MAX);
    s.run.samples = unsigned_variable("WARPCHECK_SAMPLES", s.run.samples, 1000, 10'000'000'000);
    s.run.alpha = alpha_variable("WARPCHECK_ALPHA", s.run.alpha);
    if (const char* dir = variable("WARPCHECK_EVIDENCE_DIR")) s.evidence_dir = dir;
    return s;
}

::testing::AssertionResult WarpCasePasses(const char* expression, const WarpCase& warp) {
    Settings settings;
    try {
        settings = settings_from_environment();
    } catch (const std::exception& e) {
        return ::testing::AssertionFailure() << "warpcheck: " << e.what();
    }
    std::vector<Job> jobs;
    for (const auto& check : builtin_checks().checks())
        if (check->runs_by_default(settings.run) && check->applies_to(warp)) jobs.push_back({&warp, check.get()});
    const ::testing::AssertionResult verdict =
        judge(run_part(jobs, statistical_tests(jobs), settings), settings, identifier(warp.name()) + ".html");
    if (verdict) return verdict;
    return ::testing::AssertionFailure() << "warpcheck: " << expression << " (" << warp.name()
                                         << ") failed checks:\n" << verdict.message();
}

::testing::AssertionResult WarpCasePasses(const char* expression, const std::unique_ptr<WarpCase>& warp) {
    if (!warp) return ::testing::AssertionFailure() << "warpcheck: " << expression << " is a null warp case";
    return WarpCasePasses(expression, *warp);
}

std::vector<JobParam> jobs_of(void (*register_cases)(Registry&)) {
    auto suite = std::make_shared<Suite>();
    try {
        suite->settings = settings_from_environment();
        register_builtin_checks(suite->registry);
        register_cases(suite->registry);
        suite->jobs = select_jobs(suite->registry, {}, {}, suite->settings.run);
        suite->family_tests = statistical_tests(suite->jobs);
    } catch (const std::exception& e) {
        suite->error = e.what();
    } catch (...) {  // registration is foreign code
        suite->error = "an exception that is not a std::exception";
    }
    if (!suite->error.empty() || suite->jobs.empty()) {
        if (suite->error.empty()) suite->error = "the registration function added no case that a check applies to";
        suite->jobs.clear();
        return {JobParam{suite, 0}};
    }
    std::vector<JobParam> params;
    for (std::size_t i = 0; i < suite->jobs.size(); ++i) params.push_back({suite, i});
    return params;
}

std::string job_test_name(const ::testing::TestParamInfo<JobParam>& info) {
    const Suite& suite = *info.param.suite;
    if (suite.jobs.empty()) return "registration";
    const Job& job = suite.jobs[info.param.index];
    return identifier(job.warp->name()) + "__" + identifier(job.check->name());
}

void PrintTo(const JobParam& param, std::ostream* out) {
    const Suite& suite = *param.suite;
    if (suite.jobs.empty()) *out << "(no jobs: " << suite.error << ")";
    else *out << suite.jobs[param.index].check->name() << " on " << suite.jobs[param.index].warp->name();
}

void JobTest::run_job() const {
    const Suite& suite = *GetParam().suite;
    if (suite.jobs.empty()) {
        ADD_FAILURE() << "warpcheck: could not build the suite: " << suite.error;
        return;
    }
    const Job& job = suite.jobs[GetParam().index];
    const std::string file = identifier(job.warp->name()) + "__" + identifier(job.check->name()) + ".html";
    const ::testing::AssertionResult verdict = judge(run_part({job}, suite.family_tests, suite.settings), suite.settings, file);
    if (!verdict) ADD_FAILURE() << "warpcheck: " << job.check->name() << " failed on " << job.warp->name() << ":\n"
                                << verdict.message();
}

}  // namespace warpcheck::gtest

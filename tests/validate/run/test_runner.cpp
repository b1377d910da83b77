// The runner: multiple-test correction, errors from throwing warps, determinism.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <cstring>
#include <map>
#include <set>
#include <stdexcept>

#include "chi2/multiple_testing.h"
#include "sampling/hemisphere.h"
#include "support/check_harness.h"
#include "validate/checks/checks.h"
#include "validate/api/registry.h"
#include "validate/lanes/lane_sampling.h"
#include "validate/run/runner.h"
#include "validate/run/thread_pool.h"

namespace warpcheck {
namespace {

TEST(Sidak, LevelKeepsTheFamilyWiseRate) {
    EXPECT_DOUBLE_EQ(chi2::sidak_level(0.01, 1), 0.01);
    const double level = chi2::sidak_level(0.01, 100);
    EXPECT_NEAR(1.0 - std::pow(1.0 - level, 100), 0.01, 1e-15);
    EXPECT_GT(level, 0.01 / 100);  // Sidak is slightly less strict than Bonferroni
    EXPECT_LT(level, 0.01 / 99);
    // Tiny levels keep their digits (no cancellation in 1 - (1 - alpha)^(1/m)).
    EXPECT_NEAR(chi2::sidak_level(1e-9, 1000) / 1e-12, 1.0, 1e-6);
}

TEST(Sidak, NaNAndLowPValuesFail) {
    RunResult run;
    for (double p : {0.5, 1e-6, std::numeric_limits<double>::quiet_NaN()}) {
        CheckResult r;
        r.verdict = Verdict::Pass;
        r.p_value = p;
        run.results.push_back(r);
    }
    CheckResult no_p;
    no_p.verdict = Verdict::Pass;
    run.results.push_back(no_p);
    apply_multiple_test_correction(run, 0.01);
    EXPECT_EQ(run.info.statistical_tests, 3);
    EXPECT_EQ(run.results[0].verdict, Verdict::Pass);
    EXPECT_EQ(run.results[1].verdict, Verdict::Fail);
    EXPECT_EQ(run.results[2].verdict, Verdict::Fail);
    EXPECT_NE(run.results[2].message.find("NaN"), std::string::npos);
    EXPECT_EQ(run.results[3].verdict, Verdict::Pass);
    EXPECT_FALSE(run.results[3].level.has_value());
}

// A run's timings are read beside the machine that made them: its description
// names the chi-square lanes' vector path, the one this processor runs (an
// AVX2 machine ran chi2 1.56x faster per core than the scalar chunks).
TEST(Runner, TheMachineDescriptionNamesTheChiSquareVectorPath) {
    const std::string path = chi2_vector_path();
    EXPECT_TRUE(path == "avx512" || path == "avx2" || path == "scalar") << path;
    EXPECT_EQ(path == "scalar", !vector_lane_path_available()) << path;
    const std::string machine = machine_description();
    EXPECT_NE(machine.find(", chi-square lanes: " + path), std::string::npos) << machine;
    EXPECT_NE(machine.find("hardware threads"), std::string::npos) << machine;
}

TEST(Runner, ThrowingWarpIsAnErrorAndTheRunGoesOn) {
    auto thrower = make_warp_case(
        {"thrower", {}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()},
        warp_of([](Point2f u) {
                    if (u.x > 0.99f) throw std::runtime_error("boom");
                    return UniformHemisphere{}.sample(u);
                })
            .with_pdf([](Vector3f x) { return UniformHemisphere{}.pdf(x); })
            .with_invert([](Vector3f x) { return UniformHemisphere{}.invert(x); }));
    auto fine = make_warp_case({"fine", {}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()}, UniformHemisphere{});
    const auto check = make_roundtrip_check();
    RunOptions options;
    options.samples = 100'000;
    options.threads = 2;
    const RunResult run = run_jobs({{thrower.get(), check.get()}, {fine.get(), check.get()}}, options);
    ASSERT_EQ(run.results.size(), 2u);
    EXPECT_EQ(run.results[0].verdict, Verdict::Error);
    EXPECT_NE(run.results[0].message.find("boom"), std::string::npos);
    EXPECT_EQ(run.results[1].verdict, Verdict::Pass);
    EXPECT_EQ(run.results[0].case_name, "thrower");
    EXPECT_NE(run.results[0].rerun_command.find("--filter 'thrower' --check roundtrip"), std::string::npos);
}

/// A check that counts its prepare calls and reports, in each job, how many
/// it has seen: a worker inherits the count of the process that forked it.
class PreparedCheck final : public Check {
public:
    std::string name() const override { return "prepared"; }
    std::string description() const override { return "counts prepare calls"; }
    Applicability applicability(const WarpCase&) const override { return Applicability::runs(); }
    void prepare(const RunOptions&) const override { ++prepared; }
    CheckResult run(const WarpCase&, const CheckContext&) const override {
        CheckResult r;
        r.verdict = Verdict::Pass;
        r.figures.push_back({"prepared", static_cast<double>(prepared)});
        return r;
    }
    mutable int prepared = 0;
};

TEST(Runner, PreparesEachCheckOnceBeforeItsJobsInEveryWorker) {
    auto a = make_warp_case({"a", {}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()}, UniformHemisphere{});
    auto b = make_warp_case({"b", {}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()}, UniformHemisphere{});
    for (const bool isolated : {false, true}) {
        const PreparedCheck check;
        RunOptions options;
        options.threads = 2;
        Isolation isolation;
        isolation.enabled = isolated;
        const RunResult run = run_jobs({{a.get(), &check}, {b.get(), &check}}, options, {}, isolation);
        ASSERT_EQ(run.results.size(), 2u);
        for (const CheckResult& r : run.results) EXPECT_EQ(r.figure("prepared"), 1.0) << "isolated " << isolated;
        EXPECT_EQ(check.prepared, 1);
    }
}

// Figures must be bit-identical for any thread count, and for a case run alone
// or among others. One case of each family, so every check type takes part:
// consistency, roundtrip, chi2, tabulated, exhaustive, binade.
TEST(Runner, ResultsDoNotDependOnThreadsOrSelection) {
    Registry registry;
    register_builtin_cases(registry);
    register_builtin_checks(registry);
    const std::vector<std::string> subset = {"cosine_hemisphere",
                                             "uniform_cone[cos_theta_max=0.3]",
                                             "trowbridge_reitz_visible[ax=0.3,ay=0.05,theta_o=60]",
                                             "trowbridge_reitz_normals[ax=0.3,ay=0.3]",
                                             "exponential[a=1]",
                                             "piecewise_constant_2d*",
                                             "unit_float_24bit",
                                             "unit_float_walker"};
    RunOptions options;
    options.samples = 150'000;
    options.check_time_budget = testing::kTestTimeBudget;
    Isolation isolation;  // in-process unless a test below turns it on
    using Figures = std::map<std::string, std::vector<Figure>>;
    auto figures_of = [&](unsigned threads, const std::vector<std::string>& filter) {
        options.threads = threads;
        const RunResult run = run_jobs(select_jobs(registry, filter, {}, options), options, {}, isolation);
        Figures out;
        for (const auto& r : run.results) {
            auto& v = out[r.case_name + "/" + r.check_name];
            v = r.figures;
            if (r.p_value) v.push_back({"p_value(raw)", *r.p_value});
        }
        return out;
    };
    // memcmp-equal: bit for bit, NaN included. The corrected level depends on how
    // many tests ran, so it is compared only between runs of the same selection.
    auto expect_identical = [](const Figures& a, const Figures& b, bool same_selection) {
        for (const auto& [key, values] : a) {
            ASSERT_TRUE(b.count(key)) << key;
            const auto& other = b.at(key);
            ASSERT_EQ(values.size(), other.size()) << key;
            for (std::size_t i = 0; i < values.size(); ++i) {
                EXPECT_EQ(values[i].name, other[i].name) << key;
                if (!same_selection && values[i].name == "level") continue;
                EXPECT_EQ(std::memcmp(&values[i].value, &other[i].value, sizeof(double)), 0)
                    << key << " " << values[i].name << ": " << values[i].value << " vs " << other[i].value;
            }
        }
    };
    const Figures one = figures_of(1, subset);
    std::set<std::string> checks_seen;
    for (const auto& [key, values] : one) checks_seen.insert(key.substr(key.rfind('/') + 1));
    for (const char* check : {"consistency", "roundtrip", "chi2", "tabulated", "exhaustive", "binade"})
        EXPECT_TRUE(checks_seen.count(check)) << check << " did not run";
    const Figures two = figures_of(2, subset);
    EXPECT_EQ(one.size(), two.size());
    expect_identical(one, two, true);
    expect_identical(one, figures_of(8, subset), true);
    const Figures alone = figures_of(2, {"trowbridge_reitz_visible[ax=0.3,ay=0.05,theta_o=60]"});
    ASSERT_FALSE(alone.empty());
    expect_identical(alone, one, false);
    // One worker process per check: the same figures, the level included.
    isolation.enabled = true;
    expect_identical(one, figures_of(1, subset), true);
    expect_identical(one, figures_of(3, subset), true);
}

TEST(Registry, NamesAndMatching) {
    EXPECT_EQ(case_name("uniform_cone", {{"cos_theta_max", 0.3}}), "uniform_cone[cos_theta_max=0.3]");
    EXPECT_EQ(case_name("tr", {{"ax", 0.05}, {"theta_o", 85}}), "tr[ax=0.05,theta_o=85]");
    EXPECT_EQ(case_name("e", {{"c", 1e-6}}), "e[c=1e-06]");
    EXPECT_TRUE(name_matches("uniform_cone[cos_theta_max=0.3]", "cone"));
    EXPECT_TRUE(name_matches("uniform_cone[cos_theta_max=0.3]", "uniform_*[*0.3]"));
    EXPECT_FALSE(name_matches("uniform_cone[cos_theta_max=0.3]", "uniform_*[*0.5]"));
    EXPECT_TRUE(name_matches("abc", "a?c"));
    EXPECT_FALSE(name_matches("abc", "sphere"));
    // A case whose own name holds '*' or '?': a part of its name finds it, as
    // for any other case (read as a glob alone, 'star*name' missed it).
    EXPECT_TRUE(name_matches("star*name[a=1]", "star*name"));
    EXPECT_TRUE(name_matches("what?[a=1]", "what?"));
    EXPECT_TRUE(name_matches("star*name[a=1]", "st*e[a=1]"));
    EXPECT_FALSE(name_matches("star*name[a=1]", "star*names"));
    Registry r;
    r.add_case(make_warp_case({"w", {}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()}, UniformHemisphere{}));
    EXPECT_THROW(r.add_case(make_warp_case({"w", {}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()},
                                           UniformHemisphere{})),
                 std::invalid_argument);
}

TEST(ThreadPool, NestedLoopsAndExceptions) {
    ThreadPool pool(3);
    std::vector<int> hits(100, 0);
    pool.parallel_for(10, [&](std::size_t i) { pool.parallel_for(10, [&](std::size_t j) { hits[i * 10 + j]++; }); });
    for (int h : hits) EXPECT_EQ(h, 1);
    EXPECT_THROW(pool.parallel_for(50, [](std::size_t i) { if (i == 17) throw std::runtime_error("x"); }),
                 std::runtime_error);
}

}  // namespace
}  // namespace warpcheck

// The kinds of warp a renderer has besides sample/pdf/invert: samplers that
// return their pdf (with or without a pdf function), weighted samplers (a
// mixture of lobes), discrete samplers (an alias table), parameter grids, and
// the declarations refused at registration. Each correct warp passes its
// checks; each wrong twin fails the check meant to catch it.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>
#include <vector>

#include "support/check_harness.h"
#include "validate/api/case_grid.h"
#include "validate/checks/checks.h"
#include "validate/api/registry.h"
#include "sampling/math.h"

namespace warpcheck {
namespace {

using testing::run_check;

std::vector<std::unique_ptr<Check>> checks(std::initializer_list<std::unique_ptr<Check> (*)()> makers) {
    std::vector<std::unique_ptr<Check>> out;
    for (auto make : makers) out.push_back(make());
    return out;
}

// ---- a sample that returns its pdf -------------------------------------------

Vector3f direction(float cos_theta, float phi) {
    const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
    return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

// Cosine-weighted hemisphere returning its pdf, computed from u as renderers
// do; `pdf_scale` != 1 makes the returned pdf disagree with pdf(x).
PdfSample<Vector3f> cosine_sample(Point2f u, float pdf_scale) {
    const float cos_theta = std::sqrt(u.x);
    return {direction(cos_theta, 2 * kPi * u.y), pdf_scale * cos_theta / kPi};
}
float cosine_pdf(Vector3f w) { return w.z > 0 ? w.z / kPi : 0; }

WarpCaseInfo hemisphere_info(const char* family) {
    return {.family = family, .domain = chi2::Domain::hemisphere()};
}

TEST(SamplePdf, ReturnedPdfEqualToPdfPasses) {
    auto warp = make_warp_case(hemisphere_info("cosine_pdf"),
        warp_of([](Point2f u) { return cosine_sample(u, 1.0f); }).with_pdf(cosine_pdf));
    EXPECT_EQ(warp->sample_returns(), SampleReturns::PointAndPdf);
    const CheckResult r = run_check(*make_sample_pdf_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
    EXPECT_LT(*r.figure("max_relative_difference"), 1e-5);
    EXPECT_EQ(run_check(*make_chi2_check(), *warp).verdict, Verdict::Pass);
}

// Off by 1% only: the samples are right, the returned pdf is not.
TEST(SamplePdf, ReturnedPdfOffByOnePercentFails) {
    auto warp = make_warp_case(hemisphere_info("cosine_pdf_scaled"),
        warp_of([](Point2f u) { return cosine_sample(u, 1.01f); }).with_pdf(cosine_pdf));
    const CheckResult r = run_check(*make_sample_pdf_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_NEAR(*r.figure("max_relative_difference"), 0.01 / 1.01, 1e-4);
    EXPECT_NE(r.message.find("differs from pdf(x)"), std::string::npos) << r.message;
    ASSERT_FALSE(r.tables.empty());
    EXPECT_EQ(r.tables[0].rows.size(), 10u);
    // The samples themselves are right: the chi-square test cannot see it.
    EXPECT_EQ(run_check(*make_chi2_check(), *warp).verdict, Verdict::Pass);
}

TEST(SamplePdf, NaNReturnedPdfFails) {
    auto warp = make_warp_case(hemisphere_info("cosine_pdf_nan"),
        warp_of([](Point2f u) {
            auto s = cosine_sample(u, 1.0f);
            if (u.x > 0.999f) s.pdf = std::nanf("");
            return s;
        })
            .with_pdf(cosine_pdf));
    EXPECT_EQ(run_check(*make_sample_pdf_check(), *warp).verdict, Verdict::Fail);
}

// A table-driven sampler with no pdf function: piecewise constant on [0, 2)
// over four cells; `forget_cells` returns w_i / W instead of 4 w_i / (2 W).
PdfSample<float> table_sample(float u, bool forget_cells) {
    static constexpr float w[4] = {1, 3, 2, 0.5f}, total = 6.5f;
    float cdf = 0;
    int i = 0;
    while (i < 3 && u >= (cdf + w[i]) / total) cdf += w[i++];
    const float t = std::min((u * total - cdf) / w[i], 0x1.fffffep-1f);
    const float pdf = forget_cells ? w[i] / total : w[i] / total * 2.0f;
    return {(static_cast<float>(i) + t) * 0.5f, pdf};
}

WarpCaseInfo table_info(const char* family) {
    return {.family = family, .domain = chi2::Domain::interval(0, 2)};
}

TEST(SamplePdf, WithoutPdfFunctionTheReturnedPdfIsUsed) {
    auto warp = make_warp_case(table_info("table"), warp_of([](float u) { return table_sample(u, false); }));
    EXPECT_FALSE(warp->has_pdf());
    EXPECT_EQ(run_check(*make_consistency_check(), *warp).verdict, Verdict::Pass);
    const CheckResult r = run_check(*make_inverse_pdf_mean_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
    EXPECT_NEAR(*r.figure("mean"), 2.0, 0.01);
    ASSERT_TRUE(r.p_value.has_value());
    // The checks that need the pdf away from the samples do not apply.
    EXPECT_FALSE(make_chi2_check()->applies_to(*warp));
    EXPECT_FALSE(make_unbinned_check()->applies_to(*warp));
    EXPECT_FALSE(make_tabulated_check()->applies_to(*warp));
    EXPECT_FALSE(make_sample_pdf_check()->applies_to(*warp));
}

TEST(SamplePdf, WithoutPdfFunctionAWrongReturnedPdfFailsTheMeanOfItsInverse) {
    auto warp = make_warp_case(table_info("table_unscaled"), warp_of([](float u) { return table_sample(u, true); }));
    const CheckResult r = run_check(*make_inverse_pdf_mean_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_NEAR(*r.figure("mean"), 4.0, 0.02);
}

// ---- weighted samplers: a mixture of a diffuse and a power-cosine lobe -------

// eval = (kd / pi + ks (n + 2) / (2 pi) cos^n) cos theta; its integral over the
// hemisphere is kd + ks. sample picks the power lobe with probability 0.4; the
// pdf says `pdf_select` (0.4 when correct). The weight is eval / pdf.
struct Mixture {
    float kd = 0.5f, ks = 0.3f, n = 20.0f, select = 0.4f, pdf_select = 0.4f;
    float eval(Vector3f w) const {
        if (!(w.z > 0)) return 0;
        return (kd / kPi + ks * (n + 2) / (2 * kPi) * std::pow(w.z, n)) * w.z;
    }
    float pdf(Vector3f w) const {
        if (!(w.z > 0)) return 0;
        return (1 - pdf_select) * w.z / kPi + pdf_select * (n + 1) / (2 * kPi) * std::pow(w.z, n);
    }
    WeightedSample<Vector3f> sample(Point2f u) const {
        const bool power = u.x < select;
        const float v = power ? u.x / select : (u.x - select) / (1 - select);
        const float cos_theta = power ? std::pow(1 - v, 1 / (n + 1)) : std::sqrt(1 - v);
        const Vector3f w = direction(cos_theta, 2 * kPi * u.y);
        return {w, eval(w) / pdf(w)};
    }
};

std::unique_ptr<WarpCase> mixture_case(const char* family, Mixture m) {
    return make_warp_case(hemisphere_info(family),
        warp_of([m](Point2f u) { return m.sample(u); })
            .with_pdf([m](Vector3f w) { return m.pdf(w); })
            .with_eval([m](Vector3f w) { return m.eval(w); }));
}

TEST(Weighted, CorrectMixturePassesEveryCheck) {
    auto warp = mixture_case("mixture", {});
    for (const auto& check : checks({make_weight_check, make_weight_mean_check, make_chi2_check, make_consistency_check})) {
        ASSERT_TRUE(check->applies_to(*warp)) << check->name();
        const CheckResult r = run_check(*check, *warp);
        EXPECT_EQ(r.verdict, Verdict::Pass) << check->name() << ": " << r.message;
    }
    const CheckResult mean = run_check(*make_weight_mean_check(), *warp);
    EXPECT_NEAR(*mean.figure("reference"), 0.8, 1e-6);
}

// The pdf's lobe-selection probability (0.5) is not sample's (0.4): the weight
// still equals eval / pdf, but the estimator is biased and the samples do not
// follow the pdf.
TEST(Weighted, SelectionProbabilityMismatchFailsTheMeanWeight) {
    Mixture wrong;
    wrong.pdf_select = 0.5f;
    auto warp = mixture_case("mixture_wrong_select", wrong);
    EXPECT_EQ(run_check(*make_weight_check(), *warp).verdict, Verdict::Pass);
    const CheckResult mean = run_check(*make_weight_mean_check(), *warp);
    EXPECT_EQ(mean.verdict, Verdict::Fail) << mean.summary;
    EXPECT_GT(std::abs(*mean.figure("t")), 10.0);
    EXPECT_EQ(run_check(*make_chi2_check(), *warp).verdict, Verdict::Fail);
}

// The weight forgets the cosine: per-sample mismatch.
TEST(Weighted, WeightWithoutCosineFails) {
    const Mixture m;
    auto warp = make_warp_case(hemisphere_info("mixture_no_cos"),
        warp_of([m](Point2f u) {
            auto s = m.sample(u);
            s.weight /= s.x.z;
            return s;
        })
            .with_pdf([m](Vector3f w) { return m.pdf(w); })
            .with_eval([m](Vector3f w) { return m.eval(w); }));
    const CheckResult r = run_check(*make_weight_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    ASSERT_FALSE(r.tables.empty());
    EXPECT_EQ(r.tables[0].columns.size(), 7u);
}

// ---- discrete samplers: an alias table ----------------------------------------

// Vose's alias table over weights; sample returns the index and u remapped.
struct AliasTable {
    std::vector<float> q, pmf;
    std::vector<uint32_t> alias;
    bool remap_wrong = false;

    explicit AliasTable(std::vector<float> w) : q(w.size()), pmf(w.size()), alias(w.size()) {
        const float total = std::accumulate(w.begin(), w.end(), 0.0f);
        const std::size_t n = w.size();
        std::vector<std::size_t> small, large;
        std::vector<double> scaled(n);
        for (std::size_t i = 0; i < n; ++i) {
            pmf[i] = w[i] / total;
            scaled[i] = static_cast<double>(w[i]) * static_cast<double>(n) / total;
            (scaled[i] < 1 ? small : large).push_back(i);
        }
        while (!small.empty() && !large.empty()) {
            const std::size_t s = small.back(), l = large.back();
            small.pop_back();
            q[s] = static_cast<float>(scaled[s]);
            alias[s] = static_cast<uint32_t>(l);
            scaled[l] -= 1 - scaled[s];
            if (scaled[l] < 1) large.pop_back(), small.push_back(l);
        }
        for (std::size_t i : small) q[i] = 1, alias[i] = static_cast<uint32_t>(i);
        for (std::size_t i : large) q[i] = 1, alias[i] = static_cast<uint32_t>(i);
    }
    DiscreteSample sample(float u) const {
        const float scaled = u * static_cast<float>(q.size());
        const auto i = std::min(static_cast<uint32_t>(scaled), static_cast<uint32_t>(q.size() - 1));
        const float up = scaled - static_cast<float>(i);
        constexpr float kBelowOne = 0x1.fffffep-1f;
        if (up < q[i]) return {i, std::min(remap_wrong ? up : up / q[i], kBelowOne)};
        return {alias[i], std::min((up - q[i]) / (1 - q[i]), kBelowOne)};
    }
};

WarpCaseInfo discrete_info(const char* family, std::size_t n) {
    return {.family = family, .categories = n};
}

std::unique_ptr<WarpCase> alias_case(const char* family, const AliasTable& t) {
    return make_warp_case(discrete_info(family, t.q.size()),
        warp_of([t](float u) { return t.sample(u); }).with_pdf([t](uint32_t i) { return t.pmf[i]; }));
}

TEST(Discrete, AliasTablePassesEveryCheck) {
    auto warp = alias_case("alias", AliasTable({1, 0, 3, 2, 0.5f, 7, 0.01f}));
    EXPECT_TRUE(warp->is_discrete());
    for (const auto& check : checks({make_pmf_check, make_discrete_chi2_check, make_remapped_u_check})) {
        ASSERT_TRUE(check->applies_to(*warp)) << check->name();
        const CheckResult r = run_check(*check, *warp);
        EXPECT_EQ(r.verdict, Verdict::Pass) << check->name() << ": " << r.message;
    }
    for (const auto& check : checks({make_consistency_check, make_chi2_check, make_unbinned_check, make_roundtrip_check}))
        EXPECT_FALSE(check->applies_to(*warp)) << check->name();
}

TEST(Discrete, RemappedUNotRescaledFails) {
    AliasTable t({1, 0, 3, 2, 0.5f, 7, 0.01f});
    t.remap_wrong = true;
    auto warp = alias_case("alias_remap", t);
    EXPECT_EQ(run_check(*make_discrete_chi2_check(), *warp).verdict, Verdict::Pass);
    const CheckResult r = run_check(*make_remapped_u_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Fail) << r.summary;
}

TEST(Discrete, ZeroWeightCategoryChosenFails) {
    const AliasTable t({1, 0, 3});
    auto warp = make_warp_case(discrete_info("alias_zero", 3),
        warp_of([t](float u) {
            return u > 0.99f ? DiscreteSample{1, 0.5f} : t.sample(u);
        })
            .with_pdf([t](uint32_t i) { return t.pmf[i]; }));
    const CheckResult r = run_check(*make_discrete_chi2_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_NE(r.message.find("chose a category of pmf 0"), std::string::npos) << r.message;
}

TEST(Discrete, IndexOutsideTheCategoriesFails) {
    auto warp = make_warp_case(discrete_info("index_out", 4),
        warp_of([](float u) { return static_cast<int>(u * 5); }).with_pdf([](int) { return 0.25f; }));
    const CheckResult r = run_check(*make_discrete_chi2_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_NE(r.message.find("not a category"), std::string::npos) << r.message;
}

TEST(Discrete, CountsThatDoNotFitThePmfFail) {
    // Uniform picks, while the pmf says 0.3, 0.2, 0.3, 0.2.
    auto warp = make_warp_case(discrete_info("pick_uniform", 4),
                               warp_of([](float u) { return std::min(static_cast<int>(u * 4), 3); })
                                   .with_pdf([](int i) { return i % 2 == 0 ? 0.3f : 0.2f; }));
    EXPECT_EQ(run_check(*make_discrete_chi2_check(), *warp).verdict, Verdict::Fail);
    EXPECT_EQ(run_check(*make_pmf_check(), *warp).verdict, Verdict::Pass);
}

TEST(Discrete, PmfThatDoesNotSumToOneFails) {
    auto warp = make_warp_case(discrete_info("pmf_unnormalised", 4),
                               warp_of([](float u) { return std::min(static_cast<int>(u * 4), 3); })
                                   .with_pdf([](int) { return 0.2501f; }));
    const CheckResult r = run_check(*make_pmf_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_NE(r.message.find("sums to"), std::string::npos) << r.message;
}

// ---- determinism ----------------------------------------------------------------

// Every figure of the new checks is the same bit for bit on 1 and 3 threads.
TEST(Kinds, FiguresDoNotDependOnTheThreadCount) {
    AliasTable t({1, 0, 3, 2, 0.5f, 7, 0.01f});
    auto alias = alias_case("alias_threads", t);
    auto mixture = mixture_case("mixture_threads", {});
    auto table = make_warp_case(table_info("table_threads"), warp_of([](float u) { return table_sample(u, false); }));
    const std::pair<const WarpCase*, std::unique_ptr<Check>> jobs[] = {
        {alias.get(), make_discrete_chi2_check()}, {alias.get(), make_remapped_u_check()},
        {mixture.get(), make_weight_mean_check()}, {mixture.get(), make_weight_check()},
        {table.get(), make_inverse_pdf_mean_check()}};
    for (const auto& [warp, check] : jobs) {
        const CheckResult one = run_check(*check, *warp, 300'000, 1), three = run_check(*check, *warp, 300'000, 3);
        ASSERT_EQ(one.figures.size(), three.figures.size()) << check->name();
        for (std::size_t i = 0; i < one.figures.size(); ++i)
            EXPECT_EQ(std::bit_cast<uint64_t>(one.figures[i].value), std::bit_cast<uint64_t>(three.figures[i].value))
                << check->name() << " " << one.figures[i].name;
    }
}

// ---- parameter grids -----------------------------------------------------------

TEST(CaseGrid, OneCasePerPointWithStableNames) {
    Registry registry;
    add_case_grid(registry, {.family = "lobe", .params = {{"kd", 0.5}}, .domain = chi2::Domain::hemisphere()},
                  {{"ks", {0.1, 0.3}}, {"n", {2, 20, 200}}}, [](WarpCaseInfo info, const GridPoint& p) {
                      Mixture m;
                      m.ks = static_cast<float>(p["ks"]);
                      m.n = static_cast<float>(p["n"]);
                      return make_warp_case(std::move(info),
                          warp_of([m](Point2f u) { return m.sample(u); })
                              .with_pdf([m](Vector3f w) { return m.pdf(w); })
                              .with_eval([m](Vector3f w) { return m.eval(w); }));
                  });
    ASSERT_EQ(registry.cases().size(), 6u);
    EXPECT_EQ(registry.cases()[0]->name(), "lobe[kd=0.5,ks=0.1,n=2]");
    EXPECT_EQ(registry.cases()[1]->name(), "lobe[kd=0.5,ks=0.1,n=20]");
    EXPECT_EQ(registry.cases()[5]->name(), "lobe[kd=0.5,ks=0.3,n=200]");
}

TEST(CaseGrid, BadGridsAreRefusedNamingTheFamily) {
    Registry registry;
    const GridCaseMaker make = [](WarpCaseInfo info, const GridPoint&) {
        return make_warp_case(std::move(info),
            warp_of([](Point2f u) { return u; }).with_pdf([](Point2f) { return 1.0f; }));
    };
    const WarpCaseInfo base{.family = "square"};
    EXPECT_THROW(add_case_grid(registry, base, {{"a", {}}}, make), std::invalid_argument);
    EXPECT_THROW(add_case_grid(registry, base, {{"a", {1, NAN}}}, make), std::invalid_argument);
    EXPECT_THROW(add_case_grid(registry, base, {{"a", {1}}, {"a", {2}}}, make), std::invalid_argument);
    const GridCaseMaker renames = [](WarpCaseInfo, const GridPoint&) {
        return make_warp_case({.family = "other"},
            warp_of([](Point2f u) { return u; }).with_pdf([](Point2f) { return 1.0f; }));
    };
    try {
        add_case_grid(registry, base, {{"a", {1}}}, renames);
        FAIL() << "a maker that drops the grid's parameters must be refused";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("square[a=1]"), std::string::npos) << e.what();
    }
}

// ---- declarations refused at registration ---------------------------------------

/// The message of the std::invalid_argument that `make` throws, or "".
template <typename F>
std::string kind_refusal(F make) {
    try {
        make();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

/// Whether `make` is refused as a declaration of case `name` with `problem` among its problems.
template <typename F>
::testing::AssertionResult refused(F make, const std::string& name, const std::string& problem) {
    const std::string message = kind_refusal(make);
    if (message.find("warp case " + name + " is declared inconsistently:") != std::string::npos &&
        message.find("\n  - " + problem) != std::string::npos)
        return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "refusal of " << name << ": '" << message << "'";
}

TEST(Declaration, InconsistentCasesAreRefusedNamingTheCase) {
    const Mixture m;
    const AliasTable t({1, 2});
    auto pmf = [t](uint32_t i) { return t.pmf[i]; };
    auto choose = [t](float u) { return t.sample(u); };
    // A discrete case with a continuous domain, and one without its number of categories.
    EXPECT_TRUE(refused(
        [&] {
            make_warp_case({.family = "d1", .domain = chi2::Domain::interval(0, 2), .categories = 2},
                           warp_of(choose).with_pdf(pmf));
        },
        "d1", "a discrete case has no continuous domain"));
    EXPECT_TRUE(refused([&] { make_warp_case({.family = "d2"}, warp_of(choose).with_pdf(pmf)); }, "d2",
                        "its sample returns an index, so it needs .categories"));
    // Categories on a continuous case.
    EXPECT_TRUE(refused(
        [&] {
            make_warp_case({.family = "c1", .categories = 3},
                           warp_of([](Point2f u) { return u; }).with_pdf([](Point2f) { return 1.0f; }));
        },
        "c1", "it declares .categories"));
    // A weight without eval, and an eval without a weight.
    EXPECT_TRUE(refused(
        [&] {
            make_warp_case(hemisphere_info("w1"),
                warp_of([m](Point2f u) { return m.sample(u); }).with_pdf([m](Vector3f w) { return m.pdf(w); }));
        },
        "w1", "its sample returns a weight but there is no eval"));
    EXPECT_TRUE(refused(
        [&] {
            make_warp_case(hemisphere_info("w2"),
                warp_of([](Point2f u) { return cosine_sample(u, 1.0f).x; }).with_pdf(cosine_pdf).with_eval(cosine_pdf));
        },
        "w2", "it has an eval but its sample returns no weight"));
    // Points of the wrong dimension.
    EXPECT_TRUE(refused(
        [&] {
            make_warp_case(table_info("p1"),
                warp_of([](float u) { return Point2f{u, u}; }).with_pdf([](Point2f) { return 1.0f; }));
        },
        "p1", "its points have 2 coordinates, but the interval"));
    EXPECT_TRUE(refused(
        [&] {
            make_warp_case({.family = "p2"},
                           warp_of([](float u) { return u; }).with_pdf([](float) { return 1.0f; }));
        },
        "p2", "its points have 1 coordinates, but the box"));
    // An input kind stated that its sample does not take.
    EXPECT_TRUE(refused(
        [&] {
            make_warp_case({.family = "p3", .input = InputKind::Uniform1D, .domain = chi2::Domain::interval(0, 2)},
                           warp_of([](Point2f u) { return u.x; }).with_pdf([](float) { return 0.5f; }));
        },
        "p3", "its sample takes Uniform2D (a Point2f) but .input is Uniform1D"));
    // No pdf at all.
    EXPECT_TRUE(refused([&] { make_warp_case(table_info("n1"), warp_of([](float u) { return u; })); }, "n1",
                        "it has no pdf"));
}

// Every problem of a declaration is listed, under one heading that names the case.
TEST(Declaration, EveryProblemIsListed) {
    MonotoneMarginal view;
    view.label = "x";
    view.lo = 0.0;
    view.hi = 5.0;
    const std::string message = kind_refusal([&] {
        make_warp_case({.family = "many", .domain = chi2::Domain::interval(0, 2), .roundtrip_tolerance = 2.0,
                        .views = {view}},
                       warp_of([](float u) { return u; }).with_pdf([](float) { return 0.5f; }));
    });
    EXPECT_EQ(message,
              "warp case many is declared inconsistently:\n"
              "  - roundtrip_tolerance 2 is not in (0, 1)\n"
              "  - view 'x': [0, 5] lies outside the domain interval [0.000000, 2.000000]");
}

// The input is read off sample's argument; an .input that agrees with it is accepted.
TEST(Declaration, TheInputIsReadOffSample) {
    const auto uniform = [](float) { return 1.0f; };
    EXPECT_EQ(make_warp_case(table_info("f"), warp_of([](float u) { return 2 * u; }).with_pdf(uniform))
                  ->input_kind(),
              InputKind::Uniform1D);
    EXPECT_EQ(make_warp_case({.family = "p"},
        warp_of([](Point2f u) { return u; }).with_pdf([](Point2f) { return 1.0f; }))
                  ->input_kind(),
              InputKind::Uniform2D);
    EXPECT_EQ(make_warp_case(table_info("b32"), warp_of([](uint32_t b) { return float(b >> 31); }).with_pdf(uniform))
                  ->input_kind(),
              InputKind::Bits32);
    EXPECT_EQ(make_warp_case(table_info("b64"), warp_of([](uint64_t b) { return float(b >> 63); }).with_pdf(uniform))
                  ->input_kind(),
              InputKind::Bits64);
    const auto stated = make_warp_case(
        {.family = "stated", .input = InputKind::Uniform1D, .domain = chi2::Domain::interval(0, 2)},
        warp_of([](float u) { return 2 * u; }).with_pdf(uniform));
    EXPECT_EQ(stated->input_kind(), InputKind::Uniform1D);
}

// Eval and pdf are named: each part of a Warp, and each member of a warp
// object, is called as what its name says, whatever the order of the members.
struct NamedParts {
    WeightedSample<float> sample(float u) const { return {u, 3.0f / 2.0f}; }
    float eval(float) const { return 3.0f; }
    float pdf(float) const { return 2.0f; }
};

TEST(Declaration, EvalAndPdfAreCalledByTheirNames) {
    const WarpCaseInfo info{.family = "named", .domain = chi2::Domain::interval(0, 1)};
    const auto by_object = make_warp_case(info, NamedParts{});
    const auto by_callables = make_warp_case(info,
        warp_of([](float u) { return NamedParts{}.sample(u); })
            .with_pdf([](float) { return 2.0f; })
            .with_eval([](float) { return 3.0f; }));
    for (const WarpCase* warp : {by_object.get(), by_callables.get()}) {
        const std::vector<WarpOutput> x = {{0.5f, 0.0f, 0.0f}};
        std::vector<double> pdf(1), eval(1);
        warp->pdf(x, pdf);
        warp->eval(x, eval);
        EXPECT_EQ(pdf[0], 2.0);
        EXPECT_EQ(eval[0], 3.0);
        EXPECT_EQ(warp->sample_returns(), SampleReturns::PointAndWeight);
        EXPECT_FALSE(warp->has_inverse());
    }
}

// Every check whose results carry a p-value is judged at the run's corrected
// level, so it must count in the Sidak family (Check::statistical), which the
// runner sizes before anything runs: one that did not would make every test
// of the run anti-conservative. Each built-in check is run on one case of each
// kind; a p-value from a check that is not statistical fails.
TEST(Kinds, EveryCheckThatReturnsAPValueCountsInTheFamily) {
    Registry registry;
    register_builtin_checks(registry);
    std::vector<std::unique_ptr<WarpCase>> cases;
    cases.push_back(make_warp_case(hemisphere_info("returned_pdf"),
        warp_of([](Point2f u) { return cosine_sample(u, 1.0f); }).with_pdf(cosine_pdf)));
    cases.push_back(make_warp_case(table_info("table"), warp_of([](float u) { return table_sample(u, false); })));
    cases.push_back(mixture_case("mixture", Mixture{}));
    cases.push_back(alias_case("alias", AliasTable({1, 0, 3, 2, 0.5f, 7, 0.01f})));
    int with_p_value = 0;
    for (const auto& warp : cases)
        for (const auto& check : registry.checks()) {
            if (!check->applies_to(*warp)) continue;
            const CheckResult r = run_check(*check, *warp);
            if (!r.p_value) continue;
            ++with_p_value;
            EXPECT_TRUE(check->statistical()) << check->name() << " returns a p-value on " << warp->name()
                                              << " but is not counted in the family";
        }
    EXPECT_GE(with_p_value, 8) << "the kinds' statistical checks should have run";
}

}  // namespace
}  // namespace warpcheck

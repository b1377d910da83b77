// Issue 22, class 3: densities whose support is smaller than the domain. A
// triangle (as a domain of its own, and inside the unit square), pbrt-style
// tables with empty buckets and rows: the correct warps pass on several seeds,
// and each wrong twin of the same hardness fails.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "support/check_harness.h"
#include "support/support_warps.h"
#include "sampling/hemisphere.h"
#include "validate/checks/checks.h"
#include "validate/checks/shared/float_probe.h"

namespace warpcheck {
namespace {

using testing::FloatTriangle;
using testing::PbrtTable1D;
using testing::PbrtTable2D;
using testing::run_check;
using testing::run_default_suite;

constexpr uint64_t kSeeds[] = {1, 2, 3, 4};

std::unique_ptr<WarpCase> triangle_case(const std::string& family, const FloatTriangle& t, chi2::Domain domain) {
    return make_warp_case({.family = family, .domain = domain},
                          warp_of([t](Point2f u) { return t.sample(u); })
                              .with_pdf([t](Point2f p) { return t.pdf(p); })
                              .with_invert([t](Point2f p) { return t.invert(p); }));
}

chi2::Domain triangle_domain(const FloatTriangle& t) {
    return chi2::Domain::triangle({t.a.x, t.a.y}, {t.b.x, t.b.y}, {t.c.x, t.c.y});
}

std::string failed_checks(const RunResult& run) {
    std::string out;
    for (const CheckResult& r : run.results)
        if (r.verdict != Verdict::Pass && r.verdict != Verdict::NotApplicable)
            out += r.check_name + " (" + r.summary + ": " + r.message + ") ";
    return out;
}

// ---- the triangle domain -------------------------------------------------------

TEST(TriangleDomain, UniformTrianglePassesEveryDefaultCheckOnSeveralSeeds) {
    const FloatTriangle t;
    for (uint64_t seed : kSeeds) {
        const RunResult run = run_default_suite(triangle_case("triangle", t, triangle_domain(t)), seed, 300'000);
        EXPECT_EQ(failed_checks(run), "") << "seed " << seed;
        int ran = 0;
        for (const CheckResult& r : run.results) ran += r.check_name == "chi2" || r.check_name == "unbinned";
        EXPECT_EQ(ran, 2) << "chi2 and unbinned should both run on a triangle";
    }
}

TEST(TriangleDomain, TriangleWithoutTheSquareRootFailsOnEverySeed) {
    FloatTriangle t;
    t.wrong_radius = true;
    for (uint64_t seed : kSeeds) {
        const RunResult run = run_default_suite(triangle_case("triangle_r", t, triangle_domain(t)), seed, 300'000);
        for (const CheckResult& r : run.results) {
            if (r.check_name == "chi2" || r.check_name == "unbinned") {
                EXPECT_EQ(r.verdict, Verdict::Fail) << r.check_name << " seed " << seed << ": " << r.summary;
            }
        }
    }
}

// ---- consistency: zero pdf next to a positive one ---------------------------------

// The triangle in the unit square: edge inputs (u.y = 0, u.x = 1 - 2^-24, ...)
// put samples on its edges, where the float edge functions round either way.
// Before issue 22: "558 samples with pdf 0 inside the domain".
TEST(ConsistencySupport, TriangleInTheSquarePassesWithItsRoundedSamplesCounted) {
    const FloatTriangle t;
    for (uint64_t seed : kSeeds) {
        const CheckResult r = run_check(*make_consistency_check(),
                                        *triangle_case("triangle_in_square", t, chi2::Domain::unit_square()),
                                        1'000'000, 2, seed);
        EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
        EXPECT_EQ(*r.figure("zero_pdf"), 0.0);
        EXPECT_GT(*r.figure("zero_pdf_rounded_edge_inputs"), 0.0);
        EXPECT_LE(*r.figure("zero_pdf_rounded_random"), *r.figure("zero_pdf_rounded_bound"));
        EXPECT_NE(r.summary.find("zero at the support's edge"), std::string::npos) << r.summary;
    }
}

TEST(ConsistencySupport, StrictFailsTheRoundedSamples) {
    const FloatTriangle t;
    const RunResult run = run_default_suite(triangle_case("triangle_in_square", t, chi2::Domain::unit_square()), 1,
                                            200'000, true);
    for (const CheckResult& r : run.results) {
        if (r.check_name != "consistency") continue;
        EXPECT_EQ(r.verdict, Verdict::Fail);
        EXPECT_NE(r.message.find("--strict"), std::string::npos) << r.message;
    }
}

// Zero densities on the domain's boundary from random inputs: the cosine
// hemisphere's pdf z / pi is 0 on its rim, which the float warp reaches from
// random inputs only by rounding (edge inputs reach it 456 times, counted
// apart); a twin that clamps 0.01% of its samples onto the rim (100 per 10^6,
// against a bound of 44) puts mass where its pdf is 0 and fails.
TEST(ConsistencySupport, RimZerosOfRandomInputsAreBounded) {
    for (bool clamps : {false, true}) {
        auto warp = make_warp_case({.family = clamps ? "cosine_rim_clamped" : "cosine_rim", .domain = chi2::Domain::hemisphere()},
                                   warp_of([clamps](Point2f u) {
                                               Vector3f w = CosineHemisphere{}.sample(u);
                                               if (clamps && u.y < 1e-4f) {
                                                   const float r = std::sqrt(w.x * w.x + w.y * w.y);
                                                   if (r > 0) w = Vector3f{w.x / r, w.y / r, 0.0f};
                                               }
                                               return w;
                                           })
                                       .with_pdf([](Vector3f w) { return CosineHemisphere{}.pdf(w); }));
        for (uint64_t seed : kSeeds) {
            const CheckResult r = run_check(*make_consistency_check(), *warp, 1'000'000, 2, seed);
            if (!clamps) {
                EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
                EXPECT_GT(*r.figure("zero_pdf_on_boundary"), 0.0);
                EXPECT_LE(*r.figure("zero_pdf_on_boundary_random"), *r.figure("zero_pdf_rounded_bound"));
            } else {
                EXPECT_EQ(r.verdict, Verdict::Fail) << "seed " << seed;
                EXPECT_GT(*r.figure("zero_pdf_on_boundary_random"), *r.figure("zero_pdf_rounded_bound"));
                EXPECT_NE(r.message.find("on the domain's boundary with pdf 0"), std::string::npos) << r.message;
            }
        }
    }
}

// 1% of the samples mirrored across the edge bc: mass where the pdf is 0, far
// from any positive pdf.
TEST(ConsistencySupport, MassOutsideTheTriangleFails) {
    const FloatTriangle t;
    auto warp = make_warp_case({.family = "triangle_leaks", .domain = chi2::Domain::unit_square()},
                               warp_of([t](Point2f u) {
                                           const Point2f p = t.sample(u);
                                           if (u.x < 0.99f) return p;
                                           const Point2f m{0.5f * (t.b.x + t.c.x), 0.5f * (t.b.y + t.c.y)};
                                           return Point2f{2 * m.x - p.x, 2 * m.y - p.y};
                                       })
                                   .with_pdf([t](Point2f p) { return t.pdf(p); }));
    const CheckResult r = run_check(*make_consistency_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_GT(*r.figure("zero_pdf"), 1000.0);
    EXPECT_NE(r.message.find("pdf 0 inside the domain"), std::string::npos) << r.message;
}

// pbrt-style tables, 1024 rows with every other one empty: samples of a full
// row round onto the edge of the empty one above (at 512 row boundaries),
// where the pdf is 0: 9 to 12 random samples per 10^6 (bound 44), the hardest
// correct case for the count bound.
TEST(ConsistencySupport, StripedTableRoundsOntoEmptyRowsWithinTheBound) {
    const PbrtTable2D table(testing::striped_table(8, 1024), 8, 1024);
    for (uint64_t seed : kSeeds) {
        auto warp = make_warp_case({.family = "striped_1024"},
            warp_of([&table](Point2f u) { return table.sample(u).x; })
                .with_pdf([&table](Point2f p) { return table.pdf(p); }));
        const CheckResult r = run_check(*make_consistency_check(), *warp, 1'000'000, 2, seed);
        EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
        EXPECT_GT(*r.figure("zero_pdf_rounded_random"), 0.0) << "seed " << seed;
    }
}

// The twin sends the top 1% of each row's share of u.y onto the row's upper
// edge: mass on the edge itself, every sample within float resolution of a
// positive pdf, far more of them than rounding explains.
TEST(ConsistencySupport, MassClampedOntoTheEdgesFails) {
    PbrtTable2D table(testing::striped_table(8, 1024), 8, 1024);
    table.edge_clamp = true;
    for (uint64_t seed : kSeeds) {
        auto warp = make_warp_case({.family = "striped_1024_clamped"},
                                   warp_of([&table](Point2f u) { return table.sample(u).x; })
                                       .with_pdf([&table](Point2f p) { return table.pdf(p); }));
        const CheckResult r = run_check(*make_consistency_check(), *warp, 1'000'000, 2, seed);
        EXPECT_EQ(r.verdict, Verdict::Fail);
        EXPECT_GT(*r.figure("zero_pdf_rounded_random"), *r.figure("zero_pdf_rounded_bound"));
        EXPECT_NE(r.message.find("puts mass on the edge"), std::string::npos) << r.message;
    }
}

// ---- an environment map with empty rows passes every check --------------------------

TEST(EnvironmentMap, TableWithEmptyRowsPassesEveryDefaultCheckOnSeveralSeeds) {
    const auto table = std::make_shared<const PbrtTable2D>(testing::striped_table(8, 16), 8, 16);
    for (uint64_t seed : kSeeds) {
        auto warp = make_warp_case({.family = "env_map_empty_rows"},
            warp_of([table](Point2f u) { return table->sample(u).x; })
                .with_pdf([table](Point2f p) { return table->pdf(p); }));
        const RunResult run = run_default_suite(std::move(warp), seed, 300'000);
        EXPECT_EQ(failed_checks(run), "") << "seed " << seed;
        EXPECT_GE(run.results.size(), 3u);
    }
}

// The same map returning its pdf, with no pdf function: consistency and the
// mean of 1/pdf, which estimates the support's area (5/16 of the square).
// Before issue 22 it failed against the square's area, 1.
TEST(EnvironmentMap, ReturnedPdfWithEmptyRowsPassesAgainstItsSupport) {
    const auto table = std::make_shared<const PbrtTable2D>(testing::striped_table(8, 16), 8, 16);
    for (double support : {table->support_area(), 0.0}) {
        for (uint64_t seed : kSeeds) {
            auto warp = make_warp_case({.family = "env_map_returned_pdf", .support_measure = support},
                                       warp_of([table](Point2f u) { return table->sample(u); }));
            const RunResult run = run_default_suite(std::move(warp), seed, 300'000);
            EXPECT_EQ(failed_checks(run), "") << "seed " << seed << " support " << support;
            bool tested = false;
            for (const CheckResult& r : run.results) {
                if (r.check_name != "inverse_pdf_mean") continue;
                tested = true;
                EXPECT_NEAR(*r.figure("mean"), 0.375, 0.01);
                EXPECT_EQ(*r.figure("one_sided"), support > 0 ? 0.0 : 1.0);
            }
            EXPECT_TRUE(tested);
        }
    }
}

// ---- inverse_pdf_mean: a 1D table with an empty bucket ------------------------------------

// Eight buckets on [0, 4], one empty: the support is 3.5 long. `pdf_scale`
// makes the returned pdf wrong by a factor (the twins).
std::unique_ptr<WarpCase> bucket_table(const std::string& family, double support, float pdf_scale) {
    const auto table = std::make_shared<const PbrtTable1D>(std::vector<float>{1, 2, 0, 4, 1, 3, 2, 0.5f});
    return make_warp_case(
        {.family = family, .domain = chi2::Domain::interval(0, 4),
         .support_measure = support},
        warp_of([table, pdf_scale](float u) {
                    float pdf = 0;
                    std::size_t bucket = 0;
                    const float x = 4 * table->sample(u, pdf, bucket);
                    return PdfSample<float>{x, pdf_scale * pdf / 4};
                }));
}

TEST(InversePdfMean, EmptyBucketPassesAgainstTheDeclaredSupport) {
    for (uint64_t seed : kSeeds) {
        const CheckResult r = run_check(*make_inverse_pdf_mean_check(), *bucket_table("bucket_table", 3.5, 1.0f),
                                        200'000, 2, seed);
        EXPECT_EQ(r.verdict, Verdict::Pass) << r.summary;
        EXPECT_NEAR(*r.figure("mean"), 3.5, 0.02);
        EXPECT_EQ(*r.figure("reference"), 3.5);
    }
}

// Before issue 22: "mean 1/pdf 3.5 vs 4" failed.
TEST(InversePdfMean, EmptyBucketPassesOneSidedWithoutADeclaration) {
    for (uint64_t seed : kSeeds) {
        const CheckResult r = run_check(*make_inverse_pdf_mean_check(), *bucket_table("bucket_table", 0.0, 1.0f),
                                        200'000, 2, seed);
        EXPECT_EQ(r.verdict, Verdict::Pass) << r.summary;
        EXPECT_EQ(*r.figure("reference"), 4.0);
        EXPECT_NE(r.summary.find("<= 4"), std::string::npos) << r.summary;
        EXPECT_NE(r.summary.find("one-sided"), std::string::npos) << r.summary;
    }
}

// Against a declared support, a returned pdf 2% off either way fails. Without
// a declaration the test is one-sided and sees only a pdf too small by more
// than the support's share of the domain (here 3.5 / 4): 15% too small fails,
// 2% too large passes (the row says "one-sided").
TEST(InversePdfMean, ReturnedPdfOffByAFactorFails) {
    for (uint64_t seed : kSeeds) {
        for (float scale : {0.98f, 1.02f}) {
            const CheckResult r = run_check(*make_inverse_pdf_mean_check(),
                                            *bucket_table("bucket_table_off", 3.5, scale), 200'000, 2, seed);
            EXPECT_EQ(r.verdict, Verdict::Fail) << scale << ": " << r.summary;
        }
        const CheckResult low = run_check(*make_inverse_pdf_mean_check(), *bucket_table("bucket_table_low", 0.0, 0.85f),
                                          200'000, 2, seed);
        EXPECT_EQ(low.verdict, Verdict::Fail) << low.summary;
    }
}

TEST(InversePdfMean, ASupportLargerThanTheDomainIsRefused) {
    EXPECT_THROW(
        {
            Registry registry;
            registry.add_case(bucket_table("too_large", 5.0, 1.0f));
        },
        std::invalid_argument);
}

// The probes that measure the edge band (float_probe.h): on the sphere, a
// step along one coordinate moves a unit vector off the sphere by a float
// step, inside the domain's tolerance on length, so all six probes stand
// (they were all thrown away, and no band was ever measured on a direction);
// on the hemisphere, a probe below the horizon is beyond the domain's own
// boundary and is left out; on the square, probes past its side likewise.
TEST(EdgeBandProbes, DirectionsKeepTheirProbesAndABoundaryDropsThem) {
    const WarpOutput w{0.6f, 0.0f, 0.8f};
    EXPECT_EQ(axis_probes(chi2::Domain::sphere(), w).size(), 6u);
    const WarpOutput horizon{1.0f, 0.0f, 0.0f};
    const auto probes = axis_probes(chi2::Domain::spherical_cap(0.0), horizon);
    EXPECT_EQ(probes.size(), 5u);
    for (const WarpOutput& p : probes) EXPECT_GE(p[2], 0.0f);
    EXPECT_EQ(axis_probes(chi2::Domain::unit_square(), WarpOutput{0.0f, 0.5f, 0.0f}).size(), 3u);
}

// The bound follows the measured share: none measured, the fixed rate; a
// share measured, the Poisson bound at the share's upper bound.
TEST(EdgeBandProbes, TheBoundUsesTheMeasuredShareWhereItIsLarger) {
    EdgeBand none;
    none.probed = 10'000;
    EXPECT_EQ(rounded_across_edge_bound(1'000'000, none), rounded_across_edge_bound(1'000'000));
    EdgeBand band;
    for (int i = 0; i < 10'000; ++i) band.add(i % 100 == 0);  // a share of 1%
    const double root = std::sqrt(101.0) + 3.5;  // above the Poisson 1e-9 upper limit of 100 seen
    EXPECT_NEAR(band.share(), root * root / 10'000.0, 1e-12);
    EXPECT_GT(rounded_across_edge_bound(1'000'000, band), 18'360u);
    EXPECT_LT(rounded_across_edge_bound(1'000'000, band), 19'600u);
}

}  // namespace
}  // namespace warpcheck

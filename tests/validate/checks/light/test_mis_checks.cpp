// MIS cases (validate/api/light_case.h, MisCase) and their checks
// (validate/checks/light/mis_weights.cpp, mis_estimator.cpp): the built-in
// pairs pass on several seeds, the one-sample model's pdf is the mean of the
// MIS pdfs, a declaration whose parts do not fit is refused, and the weight
// rule is shown on a correct case that is hard for it (an MIS pdf computed
// along another path, a float step apart at the silhouette) beside its wrong
// twin of the same hardness (the same path without the area-to-solid-angle
// conversion). The known-bad MIS cases are caught in the light catalogue's
// test (test_light_checks.cpp, LightFlawed).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "sampling/bsdf_dielectric.h"
#include "sampling/bsdf_diffuse.h"
#include "sampling/light.h"
#include "support/flawed_catalogue.h"
#include "validate/api/light_case.h"
#include "validate/api/registry.h"
#include "validate/checks/shared/float_probe.h"
#include "validate/run/runner.h"

namespace warpcheck {
namespace {

Registry mis_registry() {
    Registry registry;
    register_builtin_cases(registry);
    register_builtin_checks(registry);
    return registry;
}

std::vector<std::string> mis_cases(const Registry& registry) {
    std::vector<std::string> names;
    for (const auto& c : registry.cases())
        if (as_mis(*c) != nullptr) names.push_back(c->name());
    return names;
}

constexpr LightClaims kAtOrigin{.ref = {0.0f, 0.0f, 0.0f}, .normal = {0.0f, 0.0f, 1.0f}};
const Vector3f kWo{-0.6f, 0.0f, 0.8f};

std::unique_ptr<WarpCase> diffuse_under_sphere(MisClaims claims = {}) {
    return make_mis_case({.family = "test_mis"}, std::move(claims),
                         make_bsdf_case({.family = "bsdf"}, {.wo = kWo}, Lambertian(0.5f)),
                         make_light_case({.family = "light"}, kAtOrigin, SphereLight({2.0f, 0.0f, 3.4641016f}, 1.0f, 2.0f)));
}

// Every built-in MIS case (a diffuse surface under a sphere, two lights and a
// sky; rough gold at a spherical triangle; sharp gold holding a light 1e-3 rad
// across; a triangle whose MIS pdf takes another path) passes every check on
// three seeds at a tenth of the default count; ten seeds at the default count
// are `for s in $(seq 10); do validate --filter 'mis_*' --seed $s; done`, and
// seed 1 runs in validate --all.
TEST(MisBuiltins, PassEveryCheckOnSeveralSeeds) {
    const Registry registry = mis_registry();
    const std::vector<std::string> cases = mis_cases(registry);
    ASSERT_GE(cases.size(), 6u);
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        const RunResult r = testing::run_including_flawed(registry, cases, {}, seed, 100'000);
        EXPECT_GE(r.results.size(), cases.size() * 4) << "an MIS case lost its checks";
        EXPECT_EQ(r.count(Verdict::Fail) + r.count(Verdict::Error), 0) << "seed " << seed << testing::failures_of(r);
        for (const CheckResult& c : r.results) {
            if (c.check_name == "mis_estimator") {
                EXPECT_TRUE(std::isfinite(c.figure("power_relative_bias").value_or(NAN))) << c.case_name;
            }
        }
    }
}

// The one-sample model: u[0] picks a strategy; the pdf is the mean of the
// strategies' MIS pdfs, and the returned pdf uses the sampled strategy's own.
TEST(MisCase, TheOneSampleModelsPdfIsTheMeanOfTheMisPdfs) {
    const auto c = diffuse_under_sphere();
    const MisCase& mis = *as_mis(*c);
    ASSERT_EQ(mis.strategy_count(), 2u);
    const std::vector<WarpInput> in = {{{0.25f, 0.3f, 0.7f}, 0}, {{0.75f, 0.3f, 0.7f}, 0}};
    std::vector<WarpOutput> x(2);
    std::vector<double> returned(2), pdf(2), bsdf(2), light(2);
    c->sample_with_value(in, x, returned);
    c->pdf(x, pdf);
    mis.strategy_pdf(0, x, bsdf);
    mis.strategy_pdf(1, x, light);
    for (int i = 0; i < 2; ++i) {
        EXPECT_NEAR(pdf[i], 0.5 * (bsdf[i] + light[i]), 1e-12 * pdf[i]);
        EXPECT_NEAR(returned[i], pdf[i], 1e-5 * pdf[i]);
    }
    EXPECT_GT(light[1], 0.0) << "u[0] = 0.75 chooses the light: its sample is on the light";
}

// The batch form of an MIS pdf is what mis_pdf returns, called once per
// batch with the strategy's origin (the BSDF's wo, the light's ref).
TEST(MisCase, ABatchMisPdfIsCalledOncePerBatchWithItsOrigin) {
    int calls = 0;
    Vector3f seen_wo{}, seen_ref{};
    MisClaims claims;
    claims.pdfs.bsdf_batch = [&](Vector3f wo, std::span<const WarpOutput> wi, std::span<double> out) {
        ++calls, seen_wo = wo;
        for (std::size_t i = 0; i < wi.size(); ++i) out[i] = 0.25 + wi[i][2];
    };
    claims.pdfs.lights_batch = {[&](Vector3f ref, std::span<const WarpOutput> wi, std::span<double> out) {
        ++calls, seen_ref = ref;
        std::fill(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(wi.size()), 7.0);
    }};
    const auto c = diffuse_under_sphere(std::move(claims));
    const MisCase& mis = *as_mis(*c);
    EXPECT_TRUE(mis.has_mis_pdf(0));
    EXPECT_TRUE(mis.has_mis_pdf(1));
    const std::vector<WarpOutput> wi = {{0.0f, 0.0f, 1.0f}, {0.6f, 0.0f, 0.8f}, {0.0f, 0.6f, -0.8f}};
    std::vector<double> b(wi.size()), l(wi.size());
    mis.mis_pdf(0, wi, b);
    mis.mis_pdf(1, wi, l);
    EXPECT_EQ(calls, 2);
    EXPECT_EQ(b, (std::vector<double>{1.25, 0.25 + double{0.8f}, 0.25 - double{0.8f}}));
    EXPECT_EQ(l, std::vector<double>(3, 7.0));
    EXPECT_EQ(seen_wo, kWo);
    EXPECT_EQ(seen_ref, mis.light(0).ref());
    mis.mis_pdf(0, {}, std::span<double>{});
    EXPECT_EQ(calls, 2) << "no call with no directions";
}

TEST(MisCase, HeuristicsWeighAsVeach) {
    const auto balance = diffuse_under_sphere({.heuristic = MisHeuristic::Balance});
    const auto power = diffuse_under_sphere({.heuristic = MisHeuristic::Power});
    const std::vector<double> others = {3.0};
    EXPECT_DOUBLE_EQ(as_mis(*balance)->weight(1.0, others), 0.25);
    EXPECT_DOUBLE_EQ(as_mis(*power)->weight(1.0, others), 0.1);
    EXPECT_DOUBLE_EQ(as_mis(*power)->weight(2.0, std::vector<double>{0.0}), 1.0);
}

TEST(MisCaseDeclaration, PartsThatDoNotFitAreRefused) {
    const SphereLight sphere({0.0f, 0.0f, 4.0f}, 1.0f, 1.0f);
    // Delta lobes: a light sample never hits them.
    EXPECT_THROW((void)make_mis_case({.family = "glass"}, {},
                                     make_bsdf_case({.family = "b"}, {.wo = kWo}, SmoothDielectric(1.5f)),
                                     make_light_case({.family = "l"}, kAtOrigin, sphere)),
                 std::invalid_argument);
    // A light seen with another normal than the BSDF's +z.
    EXPECT_THROW((void)make_mis_case({.family = "tilted"}, {},
                                     make_bsdf_case({.family = "b"}, {.wo = kWo}, Lambertian(0.5f)),
                                     make_light_case({.family = "l"}, {.ref = {}, .normal = {1.0f, 0.0f, 0.0f}}, sphere)),
                 std::invalid_argument);
    // More MIS pdfs than lights.
    MisClaims two;
    two.pdfs.lights = {[](Vector3f, Vector3f) { return 1.0f; }, [](Vector3f, Vector3f) { return 1.0f; }};
    EXPECT_THROW((void)make_mis_case({.family = "extra"}, std::move(two),
                                     make_bsdf_case({.family = "b"}, {.wo = kWo}, Lambertian(0.5f)),
                                     make_light_case({.family = "l"}, kAtOrigin, sphere)),
                 std::invalid_argument);
    // One strategy's MIS pdf in both forms (per direction and batch).
    const auto batch = [](Vector3f, std::span<const WarpOutput>, std::span<double> out) {
        std::fill(out.begin(), out.end(), 1.0);
    };
    MisClaims both;
    both.pdfs.bsdf = [](Vector3f, Vector3f) { return 1.0f; };
    both.pdfs.bsdf_batch = batch;
    EXPECT_THROW((void)make_mis_case({.family = "both"}, std::move(both),
                                     make_bsdf_case({.family = "b"}, {.wo = kWo}, Lambertian(0.5f)),
                                     make_light_case({.family = "l"}, kAtOrigin, sphere)),
                 std::invalid_argument);
    MisClaims both_light;
    both_light.pdfs.lights = {[](Vector3f, Vector3f) { return 1.0f; }};
    both_light.pdfs.lights_batch = {batch};
    EXPECT_THROW((void)make_mis_case({.family = "both_light"}, std::move(both_light),
                                     make_bsdf_case({.family = "b"}, {.wo = kWo}, Lambertian(0.5f)),
                                     make_light_case({.family = "l"}, kAtOrigin, sphere)),
                 std::invalid_argument);
    // A light where the BSDF belongs.
    EXPECT_THROW((void)make_mis_case({.family = "swapped"}, {}, make_light_case({.family = "l"}, kAtOrigin, sphere),
                                     make_light_case({.family = "l2"}, kAtOrigin, sphere)),
                 std::invalid_argument);
}

CheckResult weights_of(const char* case_name, uint64_t seed) {
    Registry registry = mis_registry();
    register_flawed_light_cases(registry);
    const RunResult r = testing::run_including_flawed(registry, {case_name}, {"mis_weights"}, seed, 200'000);
    return r.results.at(0);
}

// The weight rule on a correct case that is hard for it: the triangle's MIS
// pdf computed through its plane in double finds the silhouette a float step
// from where the sampler's float intersection does (edge inputs land there,
// excused and counted, never more random ones than the bound); its twin of
// the same path without the conversion to solid angle fails on every seed.
TEST(MisWeights, AnotherPathToTheSamePdfPassesAndItsAreaTwinFailsOnSeveralSeeds) {
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        const CheckResult correct = weights_of("mis_diffuse_triangle_plane_pdf", seed);
        EXPECT_EQ(correct.verdict, Verdict::Pass) << correct.summary << " " << correct.message;
        EXPECT_GT(correct.figure("agree_at_neighbour_edge_inputs").value_or(0.0), 0.0)
            << "no edge input reaches the silhouette: the rule is untested there";
        EXPECT_LE(correct.figure("agree_at_neighbour_random").value_or(1e9),
                  correct.figure("agree_at_neighbour_bound").value_or(0.0));
        const CheckResult twin = weights_of("mis_triangle_area_measure", seed);
        EXPECT_EQ(twin.verdict, Verdict::Fail) << twin.summary;
        EXPECT_GT(twin.figure("wrong_sums").value_or(0.0), 1000.0) << twin.summary;
    }
}

/// A triangle light `across` radians wide at distance 1000, theta 30, facing
/// the origin, sampled by area, whose MIS pdf the renderer computes through
/// its plane in double (correct), or (its twin) with a hit test that
/// rejects barycentrics under `epsilon`, as a ray-tracing epsilon would: a
/// silhouette moved inwards by a few micro-radians.
std::unique_ptr<WarpCase> far_triangle_through_plane(double across, double epsilon) {
    const double d = 1000.0, h = 0.5 * across * d, t = std::numbers::pi / 6.0;
    const detail::Vec3d c{d * std::sin(t), 0.0, d * std::cos(t)}, up{-std::cos(t), 0.0, std::sin(t)}, side{0.0, 1.0, 0.0};
    const auto point = [&](double a, double b) {
        const detail::Vec3d p = c + (a * h) * up + (b * h) * side;
        return Vector3f{static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
    };
    const Vector3f p0 = point(-1.0, -1.0), p1 = point(-1.0, 1.0), p2 = point(1.2, 0.1);
    MisClaims claims{.heuristic = MisHeuristic::Power};
    claims.pdfs.lights.push_back([=](Vector3f, Vector3f wi) {
        using namespace detail;
        const Vec3d a = to_double(p0), e1 = to_double(p1) - a, e2 = to_double(p2) - a, n = cross(e1, e2);
        const Vec3d w = to_double(wi);
        const double wn = dot(w, n), twice = length(n);
        if (wn == 0.0) return 0.0f;
        const double s = dot(a, n) / wn;
        if (!(s > 0.0)) return 0.0f;
        const Vec3d q = s * w - a;
        const double b1 = dot(cross(q, e2), n) / (twice * twice), b2 = dot(cross(e1, q), n) / (twice * twice);
        if (!(b1 >= epsilon && b2 >= epsilon && b1 + b2 <= 1.0 - epsilon)) return 0.0f;
        const double dist2 = s * s * dot(w, w), cos_light = std::abs(wn) / (length(w) * twice);
        return static_cast<float>(dist2 / (0.5 * twice * cos_light));
    });
    return make_mis_case({.family = epsilon == 0.0 ? "far_triangle_plane_pdf" : "far_triangle_plane_pdf_epsilon"},
                         std::move(claims), make_bsdf_case({.family = "bsdf"}, {.wo = kWo}, Lambertian(0.8f)),
                         make_light_case({.family = "light"}, kAtOrigin, TriangleLight(p0, p1, p2, 2.0f)));
}

CheckResult far_triangle_weights(double across, double epsilon, uint64_t seed) {
    Registry registry;
    register_builtin_checks(registry);
    registry.add_case(far_triangle_through_plane(across, epsilon));
    const RunResult r = testing::run_including_flawed(registry, {}, {"mis_weights"}, seed, 200'000);
    return r.results.at(0);
}

// The silhouette's band on a light 10^-4 radians across: the float
// intersection and the plane in double disagree for a share of the light's
// samples far above the fixed rate's bound (the rule before measured no band
// and failed this correct case); the bound at the share measured near a
// jump of a pdf holds them, while the twin whose MIS hit test drops
// barycentrics under 0.05 (a silhouette ~5e-6 rad, 80 float steps, in: wider
// than the float neighbours that excuse a sample) fails on every seed.
TEST(MisWeights, ASilhouetteOfATinyLightIsHeldToItsMeasuredBandAndAnEpsilonInTheHitTestFailsOnSeveralSeeds) {
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        const CheckResult correct = far_triangle_weights(1e-4, 0.0, seed);
        EXPECT_EQ(correct.verdict, Verdict::Pass) << correct.summary << " " << correct.message;
        const double random = correct.figure("agree_at_neighbour_random").value_or(1e9);
        EXPECT_GT(random, static_cast<double>(rounded_across_edge_bound(200'000)))
            << "the hardness: more random directions at the silhouette than the fixed rate allows";
        EXPECT_LE(random, correct.figure("agree_at_neighbour_bound").value_or(0.0));
        EXPECT_GT(correct.figure("edge_band_near").value_or(0.0), 0.0);
        const CheckResult twin = far_triangle_weights(1e-4, 5e-2, seed);
        EXPECT_EQ(twin.verdict, Verdict::Fail) << twin.summary;
        EXPECT_GT(twin.figure("wrong_sums").value_or(0.0), 100.0) << twin.summary;
    }
}

// Without an MIS pdf of its own, the weights sum to 1 by construction: the
// row says so instead of passing.
TEST(MisWeights, NotApplicableWhereTheSumUsesTheCasesOwnPdfs) {
    const Registry registry = mis_registry();
    const RunResult r = testing::run_including_flawed(registry, {"mis_diffuse_sphere"}, {"mis_weights"}, 1, 10'000);
    ASSERT_EQ(r.results.size(), 1u);
    EXPECT_EQ(r.results[0].verdict, Verdict::NotApplicable);
    EXPECT_NE(r.results[0].summary.find("by construction"), std::string::npos) << r.results[0].summary;
}

// A NaN from the renderer's MIS pdf fails the weights, never passes them.
TEST(MisWeights, ANanMisPdfFails) {
    Registry registry;
    register_builtin_checks(registry);
    MisClaims claims;
    claims.pdfs.bsdf = [](Vector3f, Vector3f wi) { return wi.x > 0.3f ? NAN : std::abs(wi.z) * 0.31830988f; };
    registry.add_case(diffuse_under_sphere(std::move(claims)));
    const RunResult r = testing::run_including_flawed(registry, {}, {"mis_weights"}, 1, 20'000);
    ASSERT_EQ(r.results.size(), 1u);
    EXPECT_EQ(r.results[0].verdict, Verdict::Fail) << r.results[0].summary;
}

}  // namespace
}  // namespace warpcheck

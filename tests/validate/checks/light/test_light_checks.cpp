// Light cases and checks (issue 37): every built-in light, seen from every
// reference point of its grid, passes every check that applies on several seeds,
// judged as validate judges them (Sidak over the run); each known-bad light of
// the catalogue (validate/cases/light_flawed.cpp) fails the check meant to
// catch it and passes every check its bug does not touch; and the rule that
// excuses samples rounded across a light's silhouette holds a correct light's
// edge inputs, while a cone a fifth of a percent too wide, whose misses lie a
// band wider than a float step beyond the silhouette, still fails.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "chi2/multiple_testing.h"
#include "sampling/light.h"
#include "sampling/light_set.h"
#include "support/flawed_catalogue.h"
#include "validate/api/light_case.h"
#include "validate/api/registry.h"
#include "validate/cases/light_cases.h"
#include "validate/run/runner.h"

namespace warpcheck {
namespace {

RunResult run_lights(const Registry& registry, const std::vector<std::string>& cases, uint64_t seed, uint64_t samples) {
    return testing::run_including_flawed(registry, cases, {}, seed, samples);
}

using testing::failures_of;

Registry light_registry() {
    Registry registry;
    register_builtin_cases(registry);
    register_builtin_checks(registry);
    return registry;
}

/// The names of the built-in light cases.
std::vector<std::string> light_cases(const Registry& registry) {
    std::vector<std::string> names;
    for (const auto& c : registry.cases())
        if (as_light(*c) != nullptr) names.push_back(c->name());
    return names;
}

// Every built-in light over its grid (near, far and 1e-3 rad across, grazing,
// below the reference surface, edge-on, inside a sphere; environment maps with
// a bright pixel, black rows, one lit pixel, one pixel; light sets) on four
// seeds at a twentieth of the default sample count (~20 s: the quadrature's
// cost barely shrinks with the count). Ten seeds at the default count (about
// 13 s each) are the command `for s in $(seq 10); do validate --filter light
// --filter environment_ --seed $s; done`, run for issue 37; seed 1 at the
// default count runs in validate --all (ctest validate_all).
TEST(LightBuiltins, PassEveryCheckOnEverySeed) {
    const Registry registry = light_registry();
    const std::vector<std::string> cases = light_cases(registry);
    ASSERT_GE(cases.size(), 18u);
    for (uint64_t seed = 1; seed <= 4; ++seed) {
        const RunResult r = run_lights(registry, cases, seed, 50'000);
        EXPECT_GE(r.results.size(), cases.size() * 6) << "a light lost its checks";
        EXPECT_EQ(r.count(Verdict::Fail) + r.count(Verdict::Error), 0) << "seed " << seed << failures_of(r);
    }
}

// Every light check runs on a light case, and only there; the unbinned check
// says why it does not apply.
TEST(LightBuiltins, LightChecksApplyToLightsOnly) {
    const Registry registry = light_registry();
    RunOptions options;
    const auto jobs = select_jobs(registry, {"sphere_light[distance=4,theta=0]"}, {}, options);
    std::vector<std::string> checks;
    for (const auto& job : jobs) checks.push_back(job.check->name());
    for (const char* name : {"light_radiance", "light_support", "light_irradiance", "chi2", "sample_pdf", "consistency"})
        EXPECT_NE(std::find(checks.begin(), checks.end(), name), checks.end()) << name;
    const auto warp_jobs = select_jobs(registry, {"uniform_sphere"}, {}, options);
    ASSERT_FALSE(warp_jobs.empty());
    for (const auto& job : warp_jobs) EXPECT_EQ(job.check->name().rfind("light_", 0), std::string::npos);
    const RunResult r = run_lights(registry, {"sphere_light[distance=4,theta=0]"}, 1, 20'000);
    bool unbinned_said_why = false;
    for (const CheckResult& c : r.results)
        if (c.check_name == "unbinned")
            unbinned_said_why = c.verdict == Verdict::NotApplicable && c.summary.find("light") != std::string::npos;
    EXPECT_TRUE(unbinned_said_why);
}

// Each known-bad light (and MIS case) at the default sample count, in one run
// judged as `validate --include-flawed` judges it: its check fails, and so do
// only the checks its bug rightly moves; the others pass or do not apply. Not
// in the sanitizer run (CMakePresets.json), where it took 148 s of CI's 30
// minutes: there validate_all runs every light and MIS check on the built-in
// cases, at the same sample count.
TEST(LightFlawed, EachIsCaughtByItsCheckAndOnlyByTheChecksItsBugTouches) {
    Registry registry;
    register_builtin_checks(registry);
    register_flawed_light_cases(registry);
    testing::expect_each_caught(registry, light_flawed_catalogue(), run_lights(registry, {}, 1, 1'000'000));
}

// The catalogue runs only when asked for: validate --all stays green.
TEST(LightFlawed, LeftOutOfTheDefaultRun) {
    Registry registry;
    register_builtin_checks(registry);
    register_flawed_light_cases(registry);
    RunOptions options;
    EXPECT_TRUE(select_jobs(registry, {}, {}, options).empty());
    options.include_flawed = true;
    EXPECT_FALSE(select_jobs(registry, {}, {}, options).empty());
}

/// A sphere light sampled, pbrt-style, over a cone whose 1 - cos theta_max
/// is `widening` times the sphere's: with widening 1 it is the correct
/// SphereLight's sampler (rim samples whose rounded direction grazes past the
/// sphere included); above 1, samples in a thin band beyond the silhouette
/// return Le and the cone's pdf for directions that miss.
struct WidenedCone {
    SphereLight sphere;
    Vector3f centre;
    float radius;
    float widening;

    float one_minus_cos_max(Vector3f ref) const {
        const Vector3f oc = centre - ref;
        const float d = length(oc), s = radius / d;
        const float c = std::sqrt((d - radius) * (d + radius)) / d;
        return widening * s * s / (1.0f + c);
    }
    LightSample sample(Vector3f ref, Point2f u) const {
        const Vector3f oc = centre - ref;
        const float omc_max = one_minus_cos_max(ref);
        const float omc = u.x * omc_max;
        const float st = std::sqrt(omc * (2.0f - omc));
        const float phi = 6.2831853f * u.y;
        const Vector3f wi =
            Frame::around(normalize(oc)).to_world(st * std::cos(phi), st * std::sin(phi), 1.0f - omc);
        return {wi, 1.0f / (6.2831853f * omc_max), 2.0f, length(oc)};
    }
    float pdf(Vector3f ref, Vector3f wi) const { return sphere.pdf(ref, wi) > 0.0f ? 1.0f / (6.2831853f * one_minus_cos_max(ref)) : 0.0f; }
    float L(Vector3f ref, Vector3f wi) const { return sphere.L(ref, wi); }
};

CheckResult radiance_of(float widening, uint64_t seed) {
    Registry registry;
    register_builtin_checks(registry);
    const Vector3f c{2.0f, 0.0f, 3.4641016f};
    registry.add_case(make_light_case({.family = "widened_cone", .params = {{"widening", widening}}},
                                      {.ref = {}, .normal = {0.0f, 0.0f, 1.0f}},
                                      WidenedCone{SphereLight(c, 1.0f, 2.0f), c, 1.0f, widening}));
    RunOptions options;
    options.seed = seed;
    options.threads = 2;
    const RunResult r = run_jobs(select_jobs(registry, {}, {"light_radiance"}, options), options);
    return r.results.at(0);
}

// The silhouette rule on several seeds: the correct cone passes, with the
// edge inputs it maps onto the silhouette excused and counted; its twin 0.2%
// wider (misses within 1e-3 of the sphere's angular radius of the rim, far
// more than a float step) fails on every seed.
TEST(LightRadiance, SilhouetteMissesAreExcusedOnlyWithinAFloatStepOnSeveralSeeds) {
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        const CheckResult correct = radiance_of(1.0f, seed);
        EXPECT_EQ(correct.verdict, Verdict::Pass) << correct.summary << " " << correct.message;
        EXPECT_GT(correct.figure("agree_at_neighbour_edge_inputs").value_or(0.0), 0.0)
            << "the correct cone's edge inputs no longer reach the silhouette: the rule is untested";
        const CheckResult wide = radiance_of(1.002f, seed);
        EXPECT_EQ(wide.verdict, Verdict::Fail) << wide.summary;
        EXPECT_GT(wide.figure("misses").value_or(0.0), 100.0) << wide.summary;
    }
}

/// The rows of consistency, sample_pdf and light_radiance for the widened
/// cone of a sphere of radius 1 at distance 10^4 (an angular radius of
/// 10^-4 rad), seen from the origin at 30 degrees.
RunResult far_cone_rows(float widening, uint64_t seed) {
    Registry registry;
    register_builtin_checks(registry);
    const Vector3f c{5000.0f, 0.0f, 8660.254f};
    registry.add_case(make_light_case({.family = "far_widened_cone", .params = {{"widening", widening}}},
                                      {.ref = {}, .normal = {0.0f, 0.0f, 1.0f}},
                                      WidenedCone{SphereLight(c, 1.0f, 2.0f), c, 1.0f, widening}));
    RunOptions options;
    options.seed = seed;
    options.samples = 200'000;
    options.threads = 2;
    return run_jobs(select_jobs(registry, {}, {"consistency", "sample_pdf", "light_radiance"}, options), options);
}

// The edge band measured on directions (EdgeBand): a sphere light of angular
// radius 10^-4 has a few thousandths of its samples within four float steps
// of its silhouette, a hundred times the fixed rate, and a correct sampler rounds
// some of them across; consistency, sample_pdf and light_radiance measure
// that share (a probe off the unit sphere by a float step used to be thrown
// away, so no band was ever measured on a direction) and pass on every seed.
// The twin whose cone is 2% wider (its rim 1e-6 rad, 17 float steps, beyond
// the silhouette) misses in a band the probe does not reach and fails all
// three on every seed.
TEST(LightEdgeBand, AFarSphereLightPassesAndItsConeTwoPercentWideFailsOnSeveralSeeds) {
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        const RunResult correct = far_cone_rows(1.0f, seed);
        ASSERT_EQ(correct.results.size(), 3u);
        for (const CheckResult& row : correct.results) {
            EXPECT_EQ(row.verdict, Verdict::Pass) << "seed " << seed << ": " << row.summary << " " << row.message;
            const double near = row.figure("edge_band_near").value_or(row.figure("edge_band_near_edge").value_or(0.0));
            EXPECT_GT(near, 0.0) << "seed " << seed << ": no sample measured near the silhouette: the band is untested";
        }
        const RunResult wide = far_cone_rows(1.02f, seed);
        ASSERT_EQ(wide.results.size(), 3u);
        for (const CheckResult& row : wide.results)
            EXPECT_EQ(row.verdict, Verdict::Fail) << "seed " << seed << ": " << row.summary;
    }
}

/// The rows of the edge-on checks for a triangle light whose plane holds
/// the x direction turned by 0.3 rad and, tilted by `tilt` radians out of
/// the plane through the reference point (the origin), the z axis: at tilt 0
/// the plane passes through the origin, up to the rounding of the vertices.
TriangleLight turned_triangle(double tilt) {
    const double phi = 0.3;
    const double u[3] = {std::cos(phi), std::sin(phi), 0.0};
    const double v[3] = {-std::sin(phi) * std::sin(tilt), std::cos(phi) * std::sin(tilt), std::cos(tilt)};
    const auto at = [&](double a, double b) {
        return Vector3f{static_cast<float>(2.0 * u[0] + a * u[0] + b * v[0]),
                        static_cast<float>(2.0 * u[1] + a * u[1] + b * v[1]),
                        static_cast<float>(1.0 + a * u[2] + b * v[2])};
    };
    return TriangleLight(at(-0.5, -0.4), at(0.6, -0.3), at(0.0, 0.6), 2.0f);
}

/// The rows of consistency, sample_pdf, light_radiance and light_support for
/// a light seen from the origin (normal +z), at 20,000 samples.
template <typename Light>
RunResult edge_rows(Light light, uint64_t seed = 1) {
    Registry registry;
    register_builtin_checks(registry);
    registry.add_case(make_light_case({.family = "turned_light"}, {.ref = {}, .normal = {0.0f, 0.0f, 1.0f}},
                                      std::move(light)));
    RunOptions options;
    options.samples = 20'000;
    options.threads = 2;
    options.seed = seed;
    return run_jobs(
        select_jobs(registry, {}, {"consistency", "sample_pdf", "light_radiance", "light_support"}, options), options);
}

RunResult triangle_rows(double tilt) { return edge_rows(turned_triangle(tilt)); }

/// The turned triangle, but an edge input u.x = 0 (which the square-root
/// warp maps onto the first vertex for every u.y) is sent 0.1 off the
/// light along its normal: a jump at the edge, with the pdf and L of a
/// sample on the light.
struct JumpAtTheEdge {
    TriangleLight light;
    Vector3f off;
    LightSample sample(Vector3f ref, Point2f u) const {
        LightSample s = light.sample(ref, u);
        if (u.x == 0.0f && s.pdf > 0.0f) s.wi = normalize(s.distance * s.wi + off);
        return s;
    }
    float pdf(Vector3f ref, Vector3f wi) const { return light.pdf(ref, wi); }
    float L(Vector3f ref, Vector3f wi) const { return light.L(ref, wi); }
};

// A planar light seen edge-on within float rounding (its plane through the
// reference point up to the rounding of its vertices, so its float height
// there is a few ulps, not 0) is declined by the built-ins
// (detail::seen_edge_on): every check that compares samples says n/a, not a
// pass that tested nothing, and light_support says the light is not
// visible. Before, the sampler drew directions along the plane whose rays
// missed it, and all four checks failed. The same triangle turned 20
// degrees out of that plane is sampled, and passes.
TEST(LightEdgeOn, ATriangleSeenEdgeOnIsNotApplicableAndTurnedAwayIsTested) {
    const RunResult edge_on = triangle_rows(0.0);
    ASSERT_EQ(edge_on.results.size(), 4u);
    for (const CheckResult& row : edge_on.results)
        EXPECT_EQ(row.verdict, Verdict::NotApplicable) << row.summary << " " << row.message;
    const RunResult turned = triangle_rows(20.0 * 3.14159265358979 / 180.0);
    ASSERT_EQ(turned.results.size(), 4u);
    for (const CheckResult& row : turned.results) EXPECT_EQ(row.verdict, Verdict::Pass) << row.summary << " " << row.message;
}

// The inward ladder (float_probe.h) on a case hard for it: the triangle a
// tenth of a degree from edge-on, whose corners are thinner than a float
// direction for a stretch of their edges, so the edge inputs the
// square-root warp maps onto a vertex find no positive pdf (and no light)
// at any float neighbour; samples of inputs approaching them from inside
// converge to them and do, and all four checks pass on three seeds with
// the excused counted. Its wrong twin of the same hardness sends the edge
// inputs u.x = 0 a tenth of the light's size off it (a jump): they do not
// converge, and consistency, sample_pdf and light_radiance fail.
TEST(LightEdgeInputs, ACornerThinnerThanAFloatStepIsExcusedAndAJumpAtTheEdgeFailsOnSeveralSeeds) {
    const double tilt = 0.1 * 3.14159265358979 / 180.0;
    const TriangleLight light = turned_triangle(tilt);
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        const RunResult correct = edge_rows(light, seed);
        ASSERT_EQ(correct.results.size(), 4u);
        double excused = 0.0;
        for (const CheckResult& row : correct.results) {
            EXPECT_EQ(row.verdict, Verdict::Pass) << "seed " << seed << ": " << row.summary << " " << row.message;
            excused += row.figure("zero_pdf_below_resolution").value_or(0.0) +
                       row.figure("agree_below_resolution").value_or(0.0);
        }
        EXPECT_GT(excused, 0.0) << "seed " << seed << ": no edge input below float resolution: the rule is untested";
        // Along the light's normal (u x v of turned_triangle, to within its
        // tilt): 0.1, and 0.002 (a jump of 1e-3 rad, 1/16 of what the 2^-3
        // step's sample lies from the vertex: a rule that only asked the
        // nearest step to be 16 times nearer than the farthest let it pass).
        for (const float size : {0.1f, 0.002f}) {
            const Vector3f off{size * std::sin(0.3f), -size * std::cos(0.3f), 0.0f};
            const RunResult jump = edge_rows(JumpAtTheEdge{light, off}, seed);
            ASSERT_EQ(jump.results.size(), 4u);
            for (const CheckResult& row : jump.results) {
                if (row.check_name == "light_support") continue;  // it probes directions, not samples
                EXPECT_EQ(row.verdict, Verdict::Fail)
                    << "seed " << seed << ", jump " << size << ", " << row.check_name << ": " << row.summary;
            }
        }
    }
}

/// A sphere light whose samples return L (1 + bias): the irradiance
/// estimator's mean is off by exactly `bias`, relative, while L(ref, wi) and
/// the reference are the light's own.
struct BiasedSphere {
    SphereLight sphere;
    float bias;
    LightSample sample(Vector3f ref, Point2f u) const {
        LightSample s = sphere.sample(ref, u);
        s.L *= 1.0f + bias;
        return s;
    }
    float pdf(Vector3f ref, Vector3f wi) const { return sphere.pdf(ref, wi); }
    float L(Vector3f ref, Vector3f wi) const { return sphere.L(ref, wi); }
};

CheckResult irradiance_of(float bias, uint64_t seed, uint64_t samples) {
    Registry registry;
    register_builtin_checks(registry);
    registry.add_case(make_light_case({.family = "biased_sphere"}, {.ref = {}, .normal = {0.0f, 0.0f, 1.0f}},
                                      BiasedSphere{SphereLight({2.0f, 0.0f, 3.4641016f}, 1.0f, 2.0f), bias}));
    RunOptions options;
    options.seed = seed;
    options.samples = samples;
    options.threads = 2;
    return run_jobs(select_jobs(registry, {}, {"light_irradiance"}, options), options).results.at(0);
}

// The power light_irradiance states (and mis_estimator, by the same rule in
// light_integral.h) checked by simulation: a light whose estimate is biased
// by the stated 90%-power bias is detected, at the level the power is stated
// at, on about 90% of 40 seeds (at least 75%: 3.5 binomial standard
// deviations below 90%), and at half that bias on far fewer (about 9%
// expected; at most 35%), so the statement is neither optimistic nor vacuous.
TEST(LightIrradiancePower, TheStatedBiasIsSeenNineTimesInTenOnSeveralSeeds) {
    constexpr uint64_t kSamples = 20'000, kSeeds = 40;
    const double level = chi2::sidak_level(chi2::sidak_level(0.01, 140), 1);  // power_level.h's
    const double stated = irradiance_of(0.0f, 1, kSamples).figure("power_relative_bias").value_or(NAN);
    ASSERT_TRUE(stated > 0.0 && stated < 0.1) << stated;
    const auto detected = [&](double bias) {
        int hits = 0;
        for (uint64_t seed = 1; seed <= kSeeds; ++seed)
            hits += irradiance_of(static_cast<float>(bias), seed, kSamples).p_value < level;
        return static_cast<double>(hits) / kSeeds;
    };
    const double at_stated = detected(stated), at_half = detected(0.5 * stated);
    RecordProperty("stated_bias", std::to_string(stated));
    RecordProperty("detected_at_stated", std::to_string(at_stated));
    RecordProperty("detected_at_half", std::to_string(at_half));
    EXPECT_GE(at_stated, 0.75) << "stated 90% power against a bias of " << stated;
    EXPECT_LE(at_half, 0.35) << "at half the stated bias";
}

// A declaration that contradicts itself is refused with the reason.
TEST(LightCaseDeclaration, ANormalThatIsNotUnitIsRefused) {
    const SphereLight sphere({0.0f, 0.0f, 4.0f}, 1.0f, 1.0f);
    EXPECT_THROW(
        {
            try {
                (void)make_light_case({.family = "bad"}, {.ref = {}, .normal = {0.0f, 0.0f, 2.0f}}, sphere);
            } catch (const std::invalid_argument& e) {
                EXPECT_NE(std::string(e.what()).find("normal"), std::string::npos) << e.what();
                throw;
            }
        },
        std::invalid_argument);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW((void)make_light_case({.family = "bad"}, {.ref = {nan, 0.0f, 0.0f}}, sphere), std::invalid_argument);
    EXPECT_NO_THROW((void)make_light_case({.family = "medium"}, {.ref = {}, .normal = {}}, sphere));
}

using SkySet = LightSet<SphereLight, DiskLight, EnvironmentLight>;

/// light_set_sky drawn from a set whose sun is `brighter` times the claimed
/// one's, while its pdf and L (those it returns included) are the claimed set's.
struct SkySetDrawnBrighter {
    SkySet drawn, claimed;
    LightSample sample(Vector3f ref, Point2f u) const {
        LightSample s = drawn.sample(ref, u);
        if (s.pdf == 0.0f) return s;
        s.pdf = claimed.pdf(ref, s.wi);
        s.L = claimed.L(ref, s.wi);
        return s.pdf > 0.0f ? s : LightSample{};
    }
    float pdf(Vector3f ref, Vector3f wi) const { return claimed.pdf(ref, wi); }
    float L(Vector3f ref, Vector3f wi) const { return claimed.L(ref, wi); }
};

CheckResult sky_set_chi2(double brighter, uint64_t seed) {
    Registry registry;
    register_builtin_checks(registry);
    const ThreeLights l = three_lights();
    const auto set = [&](double sun) {
        return SkySet(kOverlappingLights, {0.25f, 0.25f, 0.5f}, l.sphere, l.disk, sky_light(sun));
    };
    registry.add_case(make_light_case({.family = "sky_set", .params = {{"brighter", brighter}}},
                                      {.ref = {}, .normal = {0.0f, 0.0f, 1.0f}},
                                      SkySetDrawnBrighter{set(500.0 * brighter), set(500.0)}));
    RunOptions options;
    options.seed = seed;
    options.threads = 2;
    return run_jobs(select_jobs(registry, {}, {"chi2"}, options), options).results.at(0);
}

// A sun pixel at a cell's edge (light_set_sky: the sky behind a sphere and a
// disk, its sun 500 times the sky): the first integral of a cell that holds
// a sliver of the sun misses the accuracy rule, and kept its bound where the
// pilot's pieces agreed within a far tighter one, so that the row's expected
// counts were uncertain by up to 18 sd (p 1, a tilt of 0.049 at 90% power,
// seed 1). Now the tighter bound is kept: on every seed the correct set
// passes, its bands' noncentrality a small part of its power's, and states
// about the power of a uniform sampler's rows (a tilt of 0.028; under 0.035,
// a quarter weaker, asserted); its twin, drawn with a sun 6% brighter than the
// pdf it returns and claims (2% of the set's mass moved), fails on every seed.
TEST(LightSets, TheSkySetKeepsItsPowerAndItsBrighterSunFailsOnSeveralSeeds) {
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        const CheckResult correct = sky_set_chi2(1.0, seed);
        EXPECT_EQ(correct.verdict, Verdict::Pass) << "seed " << seed << " " << correct.summary;
        // The bands' noncentrality under a quarter of what 90% power against
        // the stated tilt takes (power_noncentrality, ~264 at 1023 cells):
        // they cost the row little power, and the tilt it states shows it.
        EXPECT_LT(correct.figure("noncentrality").value_or(1e9),
                  0.25 * correct.figure("power_noncentrality").value_or(0.0))
            << "seed " << seed << " " << correct.summary;
        EXPECT_LT(correct.figure("power_tilt_eps").value_or(1.0), 0.035) << "seed " << seed << " " << correct.summary;
        const CheckResult brighter = sky_set_chi2(1.06, seed);
        EXPECT_EQ(brighter.verdict, Verdict::Fail) << "seed " << seed << " " << brighter.summary;
    }
}

}  // namespace
}  // namespace warpcheck

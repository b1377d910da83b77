// --fuzz (validate/run/fuzz.h): planted bugs at extreme parameters are found
// by the check their bug touches and shrunk to the simplest parameters that
// still fail; a correct twin over the same ranges comes out clean; the
// built-in families that the fuzz finds clean stay clean.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "sampling/bsdf_diffuse.h"
#include "sampling/bsdf_phase.h"
#include "sampling/light.h"
#include "sampling/light_set.h"
#include "validate/api/light_case.h"
#include "validate/api/bsdf_grid.h"
#include "validate/api/registry.h"
#include "validate/cases/light_cases.h"
#include "validate/run/fuzz.h"

namespace warpcheck {
namespace {

/// A Lambertian whose bug shows only at an extreme parameter: f is NaN for
/// R below 10^-3 (a division by the albedo, say), or its weight above 1 for
/// R above 0.999 (an energy term renormalised wrongly at the end of the range).
struct PlantedLambertian {
    float R;
    enum class Bug { None, NanWhenDark, EnergyWhenWhite, NegativeAtGrazing } bug;
    float wo_z = 1.0f;  ///< the case's wo.z, for the bug at grazing
    BsdfFlags flags() const { return BsdfFlags::Reflection | BsdfFlags::Continuous; }
    float scale() const { return bug == Bug::EnergyWhenWhite && R > 0.999f ? 1.2f : 1.0f; }
    float value() const {
        if (bug == Bug::NanWhenDark && R < 1e-3f) return std::numeric_limits<float>::quiet_NaN();
        // A sign lost within a milliradian of the horizon (a cosine taken
        // without its absolute value, say).
        if (bug == Bug::NegativeAtGrazing && wo_z < 1e-3f) return -R * 3.0f / 3.14159265f;
        return R * scale() / 3.14159265f;
    }
    BsdfSample sample(Vector3f wo, float uc, Point2f u) const {
        BsdfSample s = Lambertian(R).sample(wo, uc, u);
        if (s.pdf > 0.0f) s.f = value();
        return s;
    }
    float f(Vector3f wo, Vector3f wi) const { return Lambertian(R).f(wo, wi) > 0.0f || R == 0.0f ? value() : 0.0f; }
    float pdf(Vector3f wo, Vector3f wi) const { return Lambertian(R).pdf(wo, wi); }
};

void add_planted(Registry& registry, const std::string& family, PlantedLambertian::Bug bug) {
    add_case_grid(registry, {.family = family, .description = "a Lambertian with a bug planted at an end of R"},
                  {{"R", {0.5}, {{0, 1}}}, {"theta_o", {30}, {{0, 90, false, true}}}},
                  [bug](WarpCaseInfo info, const GridPoint& p) {
                      (void)Lambertian(static_cast<float>(p["R"]));  // refuses R outside [0, 1], as the built-in does
                      return make_bsdf_case(std::move(info), {.wo = grid_wo(p)},
                                            PlantedLambertian{static_cast<float>(p["R"]), bug, grid_wo(p).z});
                  });
}

/// A Henyey-Greenstein family whose g range claims the closed end 1, which the constructor refuses.
void add_overclaimed_hg(Registry& registry) {
    add_case_grid(registry, {.family = "hg_claims_g_one", .description = "g's range claims [-0.5, 1]"},
                  {{"g", {0.3}, {{-0.5, 1}}}, {"theta_o", {30}}}, [](WarpCaseInfo info, const GridPoint& p) {
                      return make_phase_case(std::move(info), grid_wo(p), HenyeyGreenstein(static_cast<float>(p["g"])));
                  });
}

FuzzReport fuzz(const std::vector<std::string>& families, uint64_t seed = 1) {
    static const Registry registry = [] {
        Registry r;
        register_builtin_checks(r);
        add_planted(r, "planted_none", PlantedLambertian::Bug::None);
        add_planted(r, "planted_nan_when_dark", PlantedLambertian::Bug::NanWhenDark);
        add_planted(r, "planted_energy_when_white", PlantedLambertian::Bug::EnergyWhenWhite);
        add_planted(r, "planted_negative_at_grazing", PlantedLambertian::Bug::NegativeAtGrazing);
        add_overclaimed_hg(r);
        return r;
    }();
    FuzzOptions o;
    o.families = families;
    o.run.seed = seed;
    o.run.samples = 20'000;
    o.random_points = 16;
    return run_fuzz(registry, o);
}

const FuzzFinding* finding(const FuzzReport& r, const std::string& check) {
    for (const FuzzFinding& f : r.findings)
        if (f.check == check) return &f;
    return nullptr;
}

TEST(Fuzz, TheCorrectTwinComesOutCleanOnSeveralSeeds) {
    for (uint64_t seed : {1, 2, 3}) {
        const FuzzReport r = fuzz({"planted_none"}, seed);
        EXPECT_TRUE(r.clean()) << fuzz_report_text(r);
        EXPECT_GT(r.points, 10u);
        EXPECT_GT(r.jobs, r.points);  // bsdf_weight and bsdf_energy at least, on every point
    }
}

TEST(Fuzz, NanAtTheDarkEndIsFoundAndShrunkToRZeroOnSeveralSeeds) {
    for (uint64_t seed : {1, 2, 3}) {
        const FuzzReport r = fuzz({"planted_nan_when_dark"}, seed);
        const FuzzFinding* f = finding(r, "bsdf_weight");
        ASSERT_NE(f, nullptr) << fuzz_report_text(r);
        // R = 0 is the simplest failing value (one digit, the range's end), and
        // so is theta_o = 0 (as simple as the grid's 30, and smaller).
        EXPECT_EQ(f->shrunk_case, "planted_nan_when_dark[R=0,theta_o=0]") << fuzz_report_text(r);
        EXPECT_NE(f->rerun.find("--fuzz-case 'planted_nan_when_dark[R=0,theta_o=0]' --check bsdf_weight"),
                  std::string::npos)
            << f->rerun;
        for (const FuzzFinding& other : r.findings) EXPECT_EQ(other.family, "planted_nan_when_dark");
    }
}

TEST(Fuzz, EnergyAtTheWhiteEndIsFoundByTheEnergyCheckAndShrunkToROne) {
    const FuzzReport r = fuzz({"planted_energy_when_white"});
    const FuzzFinding* f = finding(r, "bsdf_energy");
    ASSERT_NE(f, nullptr) << fuzz_report_text(r);
    EXPECT_EQ(f->shrunk_case, "planted_energy_when_white[R=1,theta_o=0]") << fuzz_report_text(r);
    EXPECT_EQ(finding(r, "bsdf_weight"), nullptr) << "the weight is consistent: only the energy is wrong";
}

TEST(Fuzz, ANegativeValueWithinAMilliradianOfTheHorizonIsFoundThere) {
    const FuzzReport r = fuzz({"planted_negative_at_grazing"});
    const FuzzFinding* f = finding(r, "bsdf_weight");
    ASSERT_NE(f, nullptr) << fuzz_report_text(r);
    std::string problem;
    Registry registry;
    add_planted(registry, "planted_negative_at_grazing", PlantedLambertian::Bug::NegativeAtGrazing);
    const auto shrunk = make_case_from_name(registry, f->shrunk_case, problem);
    ASSERT_NE(shrunk, nullptr) << problem;
    // No simpler theta_o fails: the shrunk point is still within the bug's milliradian.
    const double theta = shrunk->info().params[1].value;
    EXPECT_GT(theta, 89.94) << f->shrunk_case;
    EXPECT_LT(theta, 90.0) << f->shrunk_case;
    EXPECT_GT(shrunk->info().params[0].value, 0.0) << "R = 0 hides the sign: " << f->shrunk_case;
}

/// A sphere light of radius 1 seen from the origin, its centre `distance`
/// along +z; the planted twin returns twice its radiance from its samples
/// beyond distance 50 (a falloff applied twice, say).
struct FarDoubledSphere {
    SphereLight sphere;
    bool doubled;
    LightSample sample(Vector3f ref, Point2f u) const {
        LightSample s = sphere.sample(ref, u);
        if (doubled) s.L *= 2.0f;
        return s;
    }
    float pdf(Vector3f ref, Vector3f wi) const { return sphere.pdf(ref, wi); }
    float L(Vector3f ref, Vector3f wi) const { return sphere.L(ref, wi); }
};

CaseFamily sphere_family(const char* name, bool planted) {
    return {{.family = name, .description = "a sphere light over its distance"},
            {{"distance", {4}, {{2, 100}}}},
            [planted](WarpCaseInfo info, const GridPoint& p) {
                const float d = static_cast<float>(p["distance"]);
                return make_light_case(std::move(info), {.ref = {0, 0, 0}, .normal = {0, 0, 1}},
                                       FarDoubledSphere{SphereLight({0, 0, d}, 1.0f, 2.0f), planted && d > 50.0f});
            }};
}

TEST(Fuzz, ALightFamilyIsFuzzedByTheLightChecksAndItsFarBugIsFoundFar) {
    Registry registry;
    register_builtin_checks(registry);
    registry.add_family(sphere_family("fuzz_sphere", false));
    registry.add_family(sphere_family("fuzz_sphere_far_doubled", true));
    FuzzOptions o;
    o.run.samples = 20'000;
    o.random_points = 16;
    o.families = {"fuzz_sphere"};
    const FuzzReport clean = run_fuzz(registry, o);
    EXPECT_TRUE(clean.clean()) << fuzz_report_text(clean);
    std::set<std::string> checks;
    for (const CheckResult& r : clean.run.results) checks.insert(r.check_name);
    EXPECT_EQ(checks, (std::set<std::string>{"consistency", "sample_pdf", "light_radiance", "light_support"}));
    o.families = {"fuzz_sphere_far_doubled"};
    const FuzzReport r = run_fuzz(registry, o);
    const FuzzFinding* f = finding(r, "light_radiance");
    ASSERT_NE(f, nullptr) << fuzz_report_text(r);
    // The simplest failing distance: 100 (the range's end, one digit), not one of 50 or less.
    EXPECT_EQ(f->shrunk_case, "fuzz_sphere_far_doubled[distance=100]") << fuzz_report_text(r);
}

/// Fuzzes a correct family and its planted twin on seeds 1-3 (20,000 samples,
/// 8 random points): the correct one must come out clean and the twin found by
/// `check`; calls `expect_shrunk` with each seed's shrunk case and report.
template <class ExpectShrunk>
void expect_twin_found_on_seeds(const Registry& registry, const std::string& correct, const std::string& planted,
                                const std::string& check, ExpectShrunk expect_shrunk) {
    for (uint64_t seed : {1, 2, 3}) {
        FuzzOptions o;
        o.run.samples = 20'000;
        o.run.seed = seed;
        o.random_points = 8;
        o.families = {correct};
        const FuzzReport clean = run_fuzz(registry, o);
        EXPECT_TRUE(clean.clean()) << fuzz_report_text(clean);
        o.families = {planted};
        const FuzzReport r = run_fuzz(registry, o);
        const FuzzFinding* f = finding(r, check);
        ASSERT_NE(f, nullptr) << fuzz_report_text(r);
        expect_shrunk(f->shrunk_case, fuzz_report_text(r));
    }
}

/// An environment map of width x 4 pixels, a sky with one pixel `sun` times
/// brighter; the planted twin returns from its samples the radiance half a
/// texel further round in azimuth (a lookup at the pixel's corner where the
/// sampler used its centre), which matters only where neighbouring pixels
/// differ by much: the fuzz must find it toward the bright end of `sun`.
struct HalfTexelEnvironment {
    EnvironmentLight map;
    float half_texel;  // radians of azimuth; 0: the correct twin
    LightSample sample(Vector3f ref, Point2f u) const {
        LightSample s = map.sample(ref, u);
        const float c = std::cos(half_texel), n = std::sin(half_texel);
        s.L = map.L(ref, {c * s.wi.x - n * s.wi.y, n * s.wi.x + c * s.wi.y, s.wi.z});
        return s;
    }
    float pdf(Vector3f ref, Vector3f wi) const { return map.pdf(ref, wi); }
    float L(Vector3f ref, Vector3f wi) const { return map.L(ref, wi); }
};

CaseFamily environment_family(const char* name, bool planted) {
    return {{.family = name, .description = "a 16 x 4 environment map with a sun over its brightness"},
            {{"sun", {1}, {{1, 1e4}}}},
            [planted](WarpCaseInfo info, const GridPoint& p) {
                std::vector<float> pixels(64, 1.0f);
                pixels[16 + 5] = static_cast<float>(p["sun"]);
                const float half_texel = planted ? 3.14159265f / 16.0f : 0.0f;
                return make_light_case(std::move(info), {.ref = {0, 0, 0}, .normal = {0, 0, 1}},
                                       HalfTexelEnvironment{EnvironmentLight(16, 4, std::move(pixels)), half_texel});
            }};
}

// The environment map's classic bug, half a texel between the sampler and the
// lookup, is found by light_radiance wherever the sun stands out, and shrunk
// to the simplest such brightness; its correct twin is clean on three seeds.
TEST(Fuzz, AnEnvironmentMapHalfATexelOffIsFoundByItsRadianceOnSeveralSeeds) {
    Registry registry;
    register_builtin_checks(registry);
    registry.add_family(environment_family("fuzz_environment", false));
    registry.add_family(environment_family("fuzz_environment_half_texel", true));
    expect_twin_found_on_seeds(registry, "fuzz_environment", "fuzz_environment_half_texel", "light_radiance",
                               [](const std::string& shrunk, const std::string& report) {
                                   EXPECT_NE(shrunk, "fuzz_environment_half_texel[sun=1]") << report;
                               });
}

using ThreeLightSet = LightSet<SphereLight, TriangleLight, DiskLight>;

/// The built-in light set (a sphere, a triangle and a disk chosen by the
/// family's shares); the planted twin's pdf() weighs every light by 1/3
/// whatever the shares its sampler chose by (the pmf a renderer's MIS code
/// uses, left at uniform when sampling went by power): right at equal shares,
/// the family's default, and wrong by the shares' distance from 1/3 elsewhere.
struct UniformPdfSet {
    ThreeLightSet set, uniform;
    bool planted;
    LightSample sample(Vector3f ref, Point2f u) const { return set.sample(ref, u); }
    float pdf(Vector3f ref, Vector3f wi) const { return (planted ? uniform : set).pdf(ref, wi); }
    float L(Vector3f ref, Vector3f wi) const { return set.L(ref, wi); }
};

CaseFamily light_set_family(const char* name, bool planted) {
    return {{.family = name, .description = "three lights chosen by a pmf"},
            {{"p_sphere", {1.0 / 3.0}, {{0.01, 0.98}}}, {"p_triangle", {0.5}, {{0.01, 0.99}}}},
            [planted](WarpCaseInfo info, const GridPoint& at) {
                const ThreeLights t = three_lights();
                const auto ps = static_cast<float>(at["p_sphere"]);
                const auto pt = (1.0f - ps) * static_cast<float>(at["p_triangle"]);
                const float third = 1.0f / 3.0f;
                return make_light_case(
                    std::move(info), {.ref = {0, 0, 0}, .normal = {0, 0, 1}},
                    UniformPdfSet{ThreeLightSet({ps, pt, 1.0f - ps - pt}, t.sphere, t.triangle, t.disk),
                                  ThreeLightSet({third, third, third}, t.sphere, t.triangle, t.disk), planted});
            }};
}

// A light set whose pdf() keeps the uniform pmf while its sampler chooses by
// other shares is found by sample_pdf, away from the equal shares where the
// two agree; its correct twin, the same set with the same pmf in both, is
// clean on the same seeds.
TEST(Fuzz, ALightSetWhosePdfKeepsTheUniformPmfIsFoundAwayFromEqualSharesOnSeveralSeeds) {
    Registry registry;
    register_builtin_checks(registry);
    registry.add_family(light_set_family("fuzz_light_set", false));
    registry.add_family(light_set_family("fuzz_light_set_uniform_pdf", true));
    expect_twin_found_on_seeds(registry, "fuzz_light_set", "fuzz_light_set_uniform_pdf", "sample_pdf",
                               [](const std::string& shrunk, const std::string& report) {
                                   EXPECT_NE(shrunk.find("fuzz_light_set_uniform_pdf["), std::string::npos) << report;
                                   EXPECT_EQ(shrunk.find("p_sphere=0.333"), std::string::npos)
                                       << "shrunk to the equal shares, where the bug cannot show: " << report;
                               });
}

TEST(Fuzz, ARangeEndTheMakerRefusesIsAFinding) {
    const FuzzReport r = fuzz({"hg_claims_g_one"});
    ASSERT_FALSE(r.refusals.empty()) << fuzz_report_text(r);
    EXPECT_NE(r.refusals.front().find("hg_claims_g_one[g=1,"), std::string::npos) << r.refusals.front();
    EXPECT_NE(r.refusals.front().find("g must lie in (-1, 1)"), std::string::npos) << r.refusals.front();
    EXPECT_FALSE(r.clean());
}

TEST(Fuzz, PointsAreAFunctionOfTheFamilyAndTheSeedAndStayInTheirRanges) {
    Registry registry;
    add_planted(registry, "planted_none", PlantedLambertian::Bug::None);
    const CaseFamily& family = registry.families().front();
    const auto a = fuzz_points(family, 16, 7), b = fuzz_points(family, 16, 7), c = fuzz_points(family, 16, 8);
    ASSERT_EQ(a.size(), b.size());
    bool differs = a.size() != c.size();
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i][0].value, b[i][0].value);
        EXPECT_EQ(a[i][1].value, b[i][1].value);
        EXPECT_TRUE(a[i][0].value >= 0.0 && a[i][0].value <= 1.0) << a[i][0].value;
        EXPECT_TRUE(a[i][1].value >= 0.0 && a[i][1].value < 90.0) << a[i][1].value;  // 90 is open
        if (i < c.size()) differs = differs || a[i][0].value != c[i][0].value || a[i][1].value != c[i][1].value;
    }
    EXPECT_TRUE(differs);
    bool dark = false, white = false, grazing = false;
    for (const auto& p : a) {
        dark = dark || p[0].value == 0.0;
        white = white || p[0].value == 1.0;
        grazing = grazing || static_cast<float>(p[1].value) == std::nextafter(90.0f, 0.0f);
    }
    EXPECT_TRUE(dark && white && grazing) << "each end is among the points";
}

TEST(Fuzz, EveryPointIsTheCaseItsNameMakesAgain) {
    // A rerun line must make the case that failed: each point's values are
    // the decimals its name shows, so a maker that reads theta_o in double
    // (wo from bsdf_direction) sees the same wo from the name.
    Registry registry;
    add_planted(registry, "planted_none", PlantedLambertian::Bug::None);
    const CaseFamily& family = registry.families().front();
    for (const auto& params : fuzz_points(family, 64, 3)) {
        std::string refusal, problem;
        const auto made = make_family_case(family, params, refusal);
        ASSERT_NE(made, nullptr) << refusal;
        const auto again = make_case_from_name(registry, made->name(), problem);
        ASSERT_NE(again, nullptr) << problem;
        for (std::size_t k = 0; k < params.size(); ++k)
            EXPECT_EQ(again->info().params[k].value, made->info().params[k].value) << made->name();
        const auto* a = dynamic_cast<const BsdfCase*>(made.get());
        const auto* b = dynamic_cast<const BsdfCase*>(again.get());
        ASSERT_TRUE(a && b);
        EXPECT_EQ(a->wo().z, b->wo().z) << made->name();
    }
}

TEST(Fuzz, ACaseIsMadeFromItsNameAndBadNamesAreRefusedWithTheReason) {
    Registry registry;
    add_planted(registry, "planted_none", PlantedLambertian::Bug::None);
    std::string problem;
    const auto warp = make_case_from_name(registry, "planted_none[R=0.25,theta_o=89.5]", problem);
    ASSERT_NE(warp, nullptr) << problem;
    EXPECT_EQ(warp->name(), "planted_none[R=0.25,theta_o=89.5]");
    for (const auto& [name, reason] : std::vector<std::pair<std::string, std::string>>{
             {"nothing[R=1,theta_o=3]", "no family 'nothing'"},
             {"planted_none[R=1]", "no value for theta_o"},
             {"planted_none[R=1,theta_o=3,k=2]", "has no parameter k"},
             {"planted_none[R=x,theta_o=3]", "'R=x' is not name=number"},
             {"planted_none[R=nan,theta_o=3]", "is not name=number"},
             {"planted_none", "is not family[name=value,...]"},
             {"planted_none[R=2,theta_o=3]", "refuses these parameters"}}) {
        problem.clear();
        EXPECT_EQ(make_case_from_name(registry, name, problem), nullptr) << name;
        EXPECT_NE(problem.find(reason), std::string::npos) << name << ": " << problem;
    }
}

TEST(Fuzz, BuiltinFamiliesAreCleanOverTheirDeclaredRangesOnSeveralSeeds) {
    Registry registry;
    register_builtin_cases(registry);
    register_builtin_checks(registry);
    for (uint64_t seed : {1, 2, 3}) {
        FuzzOptions o;
        o.run.seed = seed;
        o.run.samples = 20'000;
        const FuzzReport r = run_fuzz(registry, o);
        EXPECT_EQ(r.families, 18u);  // the seven of issue 38, two coated (stochastic), two spectral, seven lights
        EXPECT_GT(r.points, 300u);
        EXPECT_TRUE(r.clean()) << fuzz_report_text(r);
    }
}

}  // namespace
}  // namespace warpcheck

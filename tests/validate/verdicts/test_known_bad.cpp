// Known-bad warps: deliberately wrong variants of real warps. Each runs through
// the default suite exactly as `validate` would run it (all default checks that
// apply, default sample count, Šidák level over the case's tests) and must be
// caught by at least one check. The test prints which checks caught each one.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "sampling/disk.h"
#include "sampling/hemisphere.h"
#include "sampling/linear.h"
#include "sampling/sphere.h"
#include "sampling/unit_float.h"
#include "support/verdict_twins.h"
#include "support/wrong_variants.h"
#include "validate/api/registry.h"
#include "support/check_harness.h"
#include "validate/run/runner.h"

namespace warpcheck {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

struct KnownBad {
    std::string name;
    std::string bug;
    std::function<std::unique_ptr<WarpCase>(const std::string& name)> make;
};

// How GoogleTest names a variant in its output (instead of the struct's bytes).
void PrintTo(const KnownBad& bad, std::ostream* os) { *os << bad.name; }

WarpCaseInfo info(const std::string& name, chi2::Domain domain, InputKind input = InputKind::Uniform2D) {
    return {name, {}, "known-bad variant", input, domain};
}

std::vector<KnownBad> known_bad_warps() {
    using chi2::Domain;
    std::vector<KnownBad> v;
    v.push_back({"cosine_hemisphere_pdf_3pct_high", "normalisation off by +3%", [](const std::string& n) {
                     return make_warp_case(
                         info(n, Domain::hemisphere()),
                             warp_of([](Point2f u) { return CosineHemisphere{}.sample(u); })
                                 .with_pdf([](Vector3f w) { return 1.03f * CosineHemisphere{}.pdf(w); })
                                 .with_invert([](Vector3f x) { return CosineHemisphere{}.invert(x); }));
                 }});
    v.push_back({"uniform_hemisphere_pdf_3pct_low", "normalisation off by -3%", [](const std::string& n) {
                     return make_warp_case(
                         info(n, Domain::hemisphere()),
                             warp_of([](Point2f u) { return UniformHemisphere{}.sample(u); })
                                 .with_pdf([](Vector3f w) { return 0.97f * UniformHemisphere{}.pdf(w); })
                                 .with_invert([](Vector3f x) { return UniformHemisphere{}.invert(x); }));
                 }});
    v.push_back({"cosine_hemisphere_pdf_cos_squared", "density cos^2/pi instead of cos/pi", [](const std::string& n) {
                     return make_warp_case(
                         info(n, Domain::hemisphere()),
                             warp_of([](Point2f u) { return CosineHemisphere{}.sample(u); })
                                 .with_pdf([](Vector3f w) { return w.z >= 0 ? w.z * w.z * kInvPi : 0.0f; })
                                 .with_invert([](Vector3f x) { return CosineHemisphere{}.invert(x); }));
                 }});
    v.push_back(
        {"cosine_hemisphere_2pct_half", "density 2% high on one half, 2% low on the other", [](const std::string& n) {
             return make_warp_case(
                 info(n, Domain::hemisphere()),
                     warp_of([](Point2f u) { return CosineHemisphere{}.sample(u); })
                         .with_pdf([](Vector3f w) { return (w.y >= 0 ? 1.02f : 0.98f) * CosineHemisphere{}.pdf(w); })
                         .with_invert([](Vector3f x) { return CosineHemisphere{}.invert(x); }));
         }});
    v.push_back({"disk_polar_inverse_missing_sqrt", "inverse returns r instead of r^2", [](const std::string& n) {
                     return make_warp_case(
                         info(n, Domain::unit_disk()),
                             warp_of([](Point2f u) { return UniformDiskPolar{}.sample(u); })
                                 .with_pdf([](Point2f x) { return UniformDiskPolar{}.pdf(x); })
                                 .with_invert([](Point2f p) {
                                     return Point2f{std::hypot(p.x, p.y), azimuth_to_unit(p.x, p.y)};
                                 }));
                 }});
    v.push_back({"disk_polar_sample_missing_sqrt", "sampler uses r = u instead of sqrt(u)", [](const std::string& n) {
                     return make_warp_case(
                         info(n, Domain::unit_disk()),
                         warp_of([](Point2f u) {
                                     return UniformDiskPolar{}.sample({u.x * u.x, u.y});
                                 })
                             .with_pdf([](Point2f x) { return UniformDiskPolar{}.pdf(x); })
                             .with_invert([](Point2f x) { return UniformDiskPolar{}.invert(x); }));
                 }});
    v.push_back({"disk_concentric_wrong_wedge", "concentric map with a/b in place of b/a in one wedge",
                 [](const std::string& n) {
                     return make_warp_case(
                         info(n, Domain::unit_disk()),
                         warp_of([](Point2f u) {
                                     const float a = 2 * u.x - 1, b = 2 * u.y - 1;
                                     if (std::abs(a) > std::abs(b)) {
                                         const float phi = kPiOver4 * (a / b);
                                         return Point2f{a * std::cos(phi), a * std::sin(phi)};
                                     }
                                     return UniformDiskConcentric{}.sample(u);
                                 })
                             .with_pdf([](Point2f x) { return UniformDiskConcentric{}.pdf(x); })
                             .with_invert([](Point2f x) { return UniformDiskConcentric{}.invert(x); }));
                 }});
    v.push_back({"disk_pdf_negative", "density negative on half of the disk", [](const std::string& n) {
                     return make_warp_case(
                         info(n, Domain::unit_disk()),
                             warp_of([](Point2f u) { return UniformDiskConcentric{}.sample(u); })
                                 .with_pdf([](Point2f p) { return p.x < 0 ? -kInvPi : kInvPi; })
                                 .with_invert([](Point2f x) { return UniformDiskConcentric{}.invert(x); }));
                 }});
    v.push_back({"disk_inverse_nan_at_edge", "inverse is NaN at one edge of the square", [](const std::string& n) {
                     return make_warp_case(
                         info(n, Domain::unit_disk()),
                             warp_of([](Point2f u) { return UniformDiskPolar{}.sample(u); })
                                 .with_pdf([](Point2f x) { return UniformDiskPolar{}.pdf(x); })
                                 .with_invert([](Point2f p) {
                                     Point2f u = UniformDiskPolar{}.invert(p);
                                     if (u.x == 0) u.x = kNaN;
                                     return u;
                                 }));
                 }});
    v.push_back({"cosine_power_swapped_angles", "sampler swaps u.x and u.y (theta from u.y, phi from u.x)",
                 [](const std::string& n) {
                     const CosinePowerHemisphere lobe(4.0f);
                     return make_warp_case(info(n, Domain::hemisphere()),
                                           warp_of([lobe](Point2f u) { return lobe.sample({u.y, u.x}); })
                                               .with_pdf([lobe](Vector3f w) { return lobe.pdf(w); })
                                               .with_invert([lobe](Vector3f w) { return lobe.invert(w); }));
                 }});
    v.push_back({"uniform_cone_inverse_half_cell", "inverse off by half a 1/64 cell in u.x", [](const std::string& n) {
                     const UniformCone cone(0.3f);
                     return make_warp_case(info(n, Domain::spherical_cap(cone.cos_theta_max())),
                                           warp_of([cone](Point2f u) { return cone.sample(u); })
                                               .with_pdf([cone](Vector3f w) { return cone.pdf(w); })
                                               .with_invert([cone](Vector3f w) {
                                                                Point2f u = cone.invert(w);
                                                                u.x = std::min(u.x + 1.0f / 128, kOneMinusEpsilon);
                                                                return u;
                                                            }));
                 }});
    v.push_back({"uniform_cone_pdf_wrong_normalisation", "pdf 1/(2 pi (1 + cos_theta_max)) instead of (1 - ...)",
                 [](const std::string& n) {
                     const UniformCone cone(0.3f);
                     return make_warp_case(info(n, Domain::spherical_cap(cone.cos_theta_max())),
                                           warp_of([cone](Point2f u) { return cone.sample(u); })
                                               .with_pdf([](Vector3f w) { return w.z >= 0.3f ? 1.0f / (kTwoPi * 1.3f) : 0.0f; })
                                               .with_invert([cone](Vector3f w) { return cone.invert(w); }));
                 }});
    v.push_back({"uniform_sphere_nonuniform_z", "z = 1 - 2 u^2 with its own inverse, uniform density claimed",
                 [](const std::string& n) {
                     return make_warp_case(
                         info(n, Domain::sphere()),
                         warp_of([](Point2f u) {
                                     return UniformSphere{}.sample({u.x * u.x, u.y});
                                 })
                             .with_pdf([](Vector3f x) { return UniformSphere{}.pdf(x); })
                             .with_invert([](Vector3f w) {
                                              const Point2f u = UniformSphere{}.invert(w);
                                              return Point2f{std::sqrt(u.x), u.y};
                                          }));
                 }});
    v.push_back({"uniform_sphere_half_turn", "phi = pi u.y: only half of the sphere", [](const std::string& n) {
                     return make_warp_case(
                         info(n, Domain::sphere()),
                         warp_of([](Point2f u) {
                                     return UniformSphere{}.sample({u.x, 0.5f * u.y});
                                 })
                             .with_pdf([](Vector3f x) { return UniformSphere{}.pdf(x); })
                             .with_invert([](Vector3f x) { return UniformSphere{}.invert(x); }));
                 }});
    v.push_back({"uniform_sphere_nan_for_small_u", "sampler returns NaN for u.x < 1e-3", [](const std::string& n) {
                     return make_warp_case(
                         info(n, Domain::sphere()),
                         warp_of([](Point2f u) {
                                     Vector3f w = UniformSphere{}.sample(u);
                                     if (u.x < 1e-3f) w.z = kNaN;
                                     return w;
                                 })
                             .with_pdf([](Vector3f x) { return UniformSphere{}.pdf(x); })
                             .with_invert([](Vector3f x) { return UniformSphere{}.invert(x); }));
                 }});
    v.push_back({"uniform_hemisphere_not_normalised", "direction built with r = 1 - z instead of sqrt(1 - z^2)",
                 [](const std::string& n) {
                     return make_warp_case(
                         info(n, Domain::hemisphere()),
                         warp_of([](Point2f u) {
                                     const float z = u.x, r = 1 - z, phi = kTwoPi * u.y;
                                     return Vector3f{r * std::cos(phi), r * std::sin(phi), z};
                                 })
                             .with_pdf([](Vector3f x) { return UniformHemisphere{}.pdf(x); })
                             .with_invert([](Vector3f x) { return UniformHemisphere{}.invert(x); }));
                 }});
    v.push_back(
        {"uniform_hemisphere_pdf_nan_near_pole", "pdf is NaN within 1e-3 of the pole", [](const std::string& n) {
             return make_warp_case(
                 info(n, Domain::hemisphere()),
                     warp_of([](Point2f u) { return UniformHemisphere{}.sample(u); })
                         .with_pdf([](Vector3f w) { return w.z > 0.999f ? kNaN : kInvTwoPi; })
                         .with_invert([](Vector3f x) { return UniformHemisphere{}.invert(x); }));
         }});
    v.push_back({"linear_mirrored_sampler", "density right, sampler mirrored (x -> 1 - x)", [](const std::string& n) {
                     return make_warp_case(
                         info(n, Domain::interval(0, 1), InputKind::Uniform1D),
                         warp_of([](float u) { return 1.0f - Linear(1.0f, 3.0f).sample(u); })
                             .with_pdf([](float x) { return Linear(1.0f, 3.0f).pdf(x); })
                             .with_invert([](float x) { return Linear(1.0f, 3.0f).invert(x); }));
                 }});
    v.push_back({"linear_pdf_unnormalised", "pdf lerp(x, a, b) without the 2 / (a + b)", [](const std::string& n) {
                     return make_warp_case(
                         info(n, Domain::interval(0, 1), InputKind::Uniform1D),
                         warp_of([](float u) { return Linear(1.0f, 3.0f).sample(u); })
                             .with_pdf([](float x) { return (1 - x) * 1.0f + x * 3.0f; })
                             .with_invert([](float x) { return Linear(1.0f, 3.0f).invert(x); }));
                 }});
    v.push_back({"bilinear_pdf_weights_swapped", "pdf swaps the (1,0) and (0,1) corner weights",
                 [](const std::string& n) {
                     const Bilinear patch(1, 4, 0.5f, 2), swapped(1, 0.5f, 4, 2);
                     return make_warp_case(info(n, Domain::unit_square()),
                         warp_of([=](Point2f u) { return patch.sample(u); })
                             .with_pdf([=](Point2f p) { return swapped.pdf(p); })
                             .with_invert([=](Point2f p) { return patch.invert(p); }));
                 }});
    v.push_back({"trowbridge_reitz_alpha_not_squared", "D with alpha in place of alpha^2",
                 [](const std::string&) { return testing::tr_normals(0.3f, true); }});
    v.push_back({"trimmed_exponential_untrimmed_norm", "trimmed exponential normalised as if untrimmed",
                 [](const std::string&) { return testing::trimmed(1.0f, 1.0f, true); }});
    v.push_back({"visible_normals_abs_dot", "visible-normal pdf with |wo.wm| instead of the mask",
                 [](const std::string&) { return testing::visible(0.3f, 85.0, true); }});
    v.push_back(
        {"unit_float_returns_one", "u * 2^-32 in float: 1.0 for the 128 largest inputs", [](const std::string& n) {
             return make_warp_case(
                 info(n, Domain::interval(0, 1), InputKind::Bits32),
                 warp_of([](uint32_t u) { return UnitFloatMul{}.sample(u); })
                     .with_pdf([](float x) { return x >= 0 && x < 1 ? 1.0f : 0.0f; })
                     .with_invert([](float x) { return UnitFloatMul{}.invert(x); }));
         }});
    v.push_back({"unit_float_rounding_biased",
                 "64 random bits, only 32 used, times 2^-32 with the clamp: 257/255 parity", [](const std::string& n) {
                     return make_warp_case(
                         info(n, Domain::interval(0, 1), InputKind::Bits64),
                         warp_of([](uint64_t u) { return UnitFloatMulClamped{}.sample(static_cast<uint32_t>(u >> 32)); })
                             .with_pdf([](float x) { return x >= 0 && x < 1 ? 1.0f : 0.0f; })
                             .with_invert([](float x) { return uint64_t{UnitFloatMulClamped{}.invert(x)} << 32; }));
                 }});
    v.push_back({"uniform_sphere_throws", "sampler throws for some inputs", [](const std::string& n) {
                     return make_warp_case(
                         info(n, Domain::sphere()),
                         warp_of([](Point2f u) {
                                     if (u.x > 0.9999f) throw std::domain_error("invalid input");
                                     return UniformSphere{}.sample(u);
                                 })
                             .with_pdf([](Vector3f x) { return UniformSphere{}.pdf(x); })
                             .with_invert([](Vector3f x) { return UniformSphere{}.invert(x); }));
                 }});
    // The wrong twins of tests/support/verdict_twins.h: warps that earlier
    // verdict rules let through (inverses outside [0,1), scale errors below
    // 1e-3, inputs below 2^-24, unreachable mass).
    for (const auto& twin : testing::verdict_twins()) v.push_back({twin.name, twin.bug, twin.wrong});
    return v;
}

class KnownBadWarp : public ::testing::TestWithParam<KnownBad> {};

TEST_P(KnownBadWarp, IsCaughtByTheDefaultSuite) {
    const KnownBad& bad = GetParam();
    Registry registry;
    register_builtin_checks(registry);
    registry.add_case(bad.make(bad.name));
    RunOptions options;  // the defaults of `validate`
    options.threads = 2;
    options.check_time_budget = testing::kTestTimeBudget;  // sanitizer builds are slow
    const RunResult run = run_jobs(select_jobs(registry, {}, {}, options), options);
    std::vector<std::string> caught;
    for (const auto& r : run.results) {
        // A check abandoned for its time budget has not caught anything.
        ASSERT_EQ(r.message.find("time budget"), std::string::npos) << r.check_name << ": " << r.message;
        if (r.verdict != Verdict::Pass) caught.push_back(r.check_name);
    }
    std::string list;
    for (const auto& c : caught) list += (list.empty() ? "" : ", ") + c;
    RecordProperty("caught_by", list);
    std::cout << fmt::format("known-bad {:<40} {:<60} caught by: {}\n", bad.name, bad.bug, list.empty() ? "-" : list);
    EXPECT_FALSE(caught.empty()) << bad.name << " (" << bad.bug << ") passed every check";
}

INSTANTIATE_TEST_SUITE_P(Catalogue, KnownBadWarp, ::testing::ValuesIn(known_bad_warps()),
                         [](const ::testing::TestParamInfo<KnownBad>& p) {
                             std::string n = p.param.name;  // GoogleTest names: letters, digits, '_'
                             for (char& c : n)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return n;
                         });

TEST(KnownBadCatalogue, HasAtLeastThirtyFiveVariants) { EXPECT_GE(known_bad_warps().size(), 35u); }

}  // namespace
}  // namespace warpcheck

// Built-in MIS cases (validate/api/light_case.h, MisCase): a BSDF and lights
// seen from one shading point at the origin, normal +z, combined as a
// renderer's direct lighting combines them: a diffuse surface under a sphere
// light, two lights and a sky; a rough conductor whose lobe points at a
// spherical triangle; a sharp conductor (alpha 0.05) whose lobe holds a
// sphere light a thousandth of a radian across, where one strategy carries
// nearly all of the estimate; and a triangle light whose MIS pdf the
// renderer computes along another path than its sampler (through the plane
// in double), the correct case mis_weights runs on.
//
// The known-bad twins (mis_flawed_catalogue) are registered with the light
// catalogue, only with --include-flawed.
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "sampling/bsdf_conductor.h"
#include "sampling/bsdf_diffuse.h"
#include "sampling/light.h"
#include "sampling/light_set.h"
#include "validate/api/bsdf_case.h"
#include "validate/api/light_case.h"
#include "validate/api/registry.h"
#include "validate/cases/light_cases.h"

namespace warpcheck {
namespace builtin_mis {
namespace {

constexpr LightClaims kShadingPoint{.ref = {0.0f, 0.0f, 0.0f}, .normal = {0.0f, 0.0f, 1.0f}};
constexpr float kRadiance = 2.0f;
// Gold at 600 nm, as the built-in conductor cases.
constexpr float kEta = 0.25f, kK = 3.0f;

Vector3f at(double distance, double theta_degrees) {
    const double t = theta_degrees * std::numbers::pi / 180.0;
    return {static_cast<float>(distance * std::sin(t)), 0.0f, static_cast<float>(distance * std::cos(t))};
}

WarpCaseInfo part(const char* family) { return {.family = family, .params = {}, .description = family}; }

template <typename Bsdf, typename... Lights>
std::unique_ptr<WarpCase> mis_of(WarpCaseInfo info, MisClaims claims, Vector3f wo, Bsdf bsdf, Lights... lights) {
    std::vector<std::unique_ptr<WarpCase>> parts;
    (parts.push_back(make_light_case(part("light"), kShadingPoint, std::move(lights))), ...);
    return make_mis_case(std::move(info), std::move(claims), make_bsdf_case(part("bsdf"), {.wo = wo}, std::move(bsdf)),
                         std::move(parts));
}

/// The triangle the area-route cases use: 2 from the origin at theta 30, facing it.
struct AreaTriangle {
    Vector3f a{0.5f, -0.5f, 1.9f}, b{1.6f, -0.3f, 1.1f}, c{1.0f, 0.7f, 1.6f};
};

}  // namespace

/// The solid-angle pdf of a triangle sampled by area as a renderer's MIS code
/// may compute it, along another path than the sampler's: the ray meets the
/// plane in double, the barycentrics decide the hit, and the area density
/// 1 / A becomes dist^2 / (A |cos|) (or stays 1 / A where `per_area`, the
/// bug of an area pdf in a solid-angle sum).
float triangle_pdf_through_plane(const AreaTriangle& tri, Vector3f wi, bool per_area) {
    using detail::Vec3d;
    const Vec3d a = detail::to_double(tri.a), e1 = detail::to_double(tri.b) - a, e2 = detail::to_double(tri.c) - a;
    const Vec3d n = detail::cross(e1, e2);
    const double twice_area = detail::length(n);
    const Vec3d w = detail::to_double(wi);
    const double wn = detail::dot(w, n);
    if (wn == 0.0) return 0.0f;
    const double t = detail::dot(a, n) / wn;  // the ray from the origin meets the plane at t w
    if (!(t > 0.0)) return 0.0f;
    const Vec3d p = t * w - a;
    // Barycentrics by areas: b1 = |p x e2| share, b2 = |e1 x p| share, signed against n.
    const double b1 = detail::dot(detail::cross(p, e2), n) / (twice_area * twice_area);
    const double b2 = detail::dot(detail::cross(e1, p), n) / (twice_area * twice_area);
    if (!(b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0)) return 0.0f;
    const double area = 0.5 * twice_area;
    if (per_area) return static_cast<float>(1.0 / area);
    const double cos_light = std::abs(wn) / (detail::length(w) * twice_area);
    return static_cast<float>(t * t * detail::dot(w, w) / (area * cos_light));
}

std::unique_ptr<WarpCase> triangle_mis_through_plane(bool per_area) {
    const AreaTriangle tri;
    MisClaims claims{.heuristic = MisHeuristic::Power};
    claims.pdfs.lights.push_back(
        [tri, per_area](Vector3f, Vector3f wi) { return triangle_pdf_through_plane(tri, wi, per_area); });
    return mis_of({.family = per_area ? "mis_triangle_area_measure" : "mis_diffuse_triangle_plane_pdf",
                   .params = {},
                   .description = per_area ? "the MIS sum takes the triangle's area pdf 1 / A as a solid-angle pdf"
                                           : "diffuse surface and a triangle light sampled by area, whose MIS pdf is "
                                             "computed through the plane in double"},
                  std::move(claims), bsdf_direction(40.0, 180.0), Lambertian(0.8f),
                  TriangleLight(tri.a, tri.b, tri.c, kRadiance));
}

namespace {

/// A light set of the three lights chosen uniformly whose MIS pdf leaves out
/// the pmf (three times the density its sampler draws from).
std::unique_ptr<WarpCase> set_without_pmf() {
    const ThreeLights l = three_lights();
    using Set = LightSet<SphereLight, TriangleLight, DiskLight>;
    const Set set({1.0f / 3.0f, 1.0f / 3.0f, 1.0f / 3.0f}, l.sphere, l.triangle, l.disk);
    MisClaims claims{.heuristic = MisHeuristic::Power};
    claims.pdfs.lights.push_back([set](Vector3f ref, Vector3f wi) { return 3.0f * set.pdf(ref, wi); });
    return mis_of({.family = "mis_set_without_pmf", .params = {},
                   .description = "the MIS sum evaluates a light set's pdf without the light's selection probability"},
                  std::move(claims), bsdf_direction(40.0, 180.0), Lambertian(0.8f), set);
}

/// The light's weight formed without the BSDF's pdf (as if it were 0).
std::unique_ptr<WarpCase> light_weight_without_bsdf() {
    MisClaims claims{.heuristic = MisHeuristic::Power};
    claims.pdfs.bsdf = [](Vector3f, Vector3f) { return 0.0f; };
    return mis_of({.family = "mis_light_weight_without_bsdf", .params = {},
                   .description = "the light sample's weight is formed without the BSDF's pdf"},
                  std::move(claims), bsdf_direction(40.0, 180.0), Lambertian(0.8f),
                  SphereLight(at(4.0, 30.0), 1.0f, kRadiance));
}

/// Rough gold (alpha 0.1) whose pdf, returned and evaluated alike, is 3% high
/// where wi.y > 0: consistent everywhere the weights look, wrong against
/// the density its sampler draws from.
std::unique_ptr<WarpCase> conductor_pdf_high_on_half() {
    const RoughConductor conductor(TrowbridgeReitz(0.1f, 0.1f), kEta, kK);
    const auto scale = [](Vector3f wi) { return wi.y > 0.0f ? 1.03f : 1.0f; };
    const auto sample = [conductor, scale](Vector3f wo, float uc, Point2f u) {
        BsdfSample s = conductor.sample(wo, uc, u);
        s.pdf *= scale(s.wi);
        return s;
    };
    auto bsdf = bsdf_of(sample)
                    .with_f([conductor](Vector3f wo, Vector3f wi) { return conductor.f(wo, wi); })
                    .with_pdf([conductor, scale](Vector3f wo, Vector3f wi) { return conductor.pdf(wo, wi) * scale(wi); });
    std::vector<std::unique_ptr<WarpCase>> lights;
    lights.push_back(make_light_case(part("light"), kShadingPoint, SphereLight(at(4.0, 30.0), 1.0f, kRadiance)));
    return make_mis_case({.family = "mis_conductor_pdf_high_on_half", .params = {{"alpha", 0.1}},
                          .description = "rough gold whose pdf is 3% high on half the sphere, its lobe in a sphere "
                                         "light"},
                         {.heuristic = MisHeuristic::Power},
                         make_bsdf_case(part("bsdf"), {.wo = bsdf_direction(30.0, 180.0),
                                                       .lobes = BsdfFlags::Reflection | BsdfFlags::Continuous},
                                        std::move(bsdf)),
                         std::move(lights));
}

void register_mis_cases(Registry& registry) {
    registry.add_case(mis_of({.family = "mis_diffuse_sphere", .params = {},
                              .description = "diffuse surface under a sphere light (radius 1, 4 away, theta 30)"},
                             {.heuristic = MisHeuristic::Power}, bsdf_direction(40.0, 180.0), Lambertian(0.8f),
                             SphereLight(at(4.0, 30.0), 1.0f, kRadiance)));
    {
        // A spherical triangle 2 away at theta 30 that the conductor's lobe (wo mirrored) points at.
        const AreaTriangle tri;
        registry.add_case(mis_of({.family = "mis_conductor_spherical_triangle", .params = {{"alpha", 0.3}},
                                  .description = "rough gold (alpha 0.3) whose lobe points at a spherical triangle "
                                                 "light; balance heuristic"},
                                 {.heuristic = MisHeuristic::Balance}, bsdf_direction(30.0, 180.0),
                                 RoughConductor(TrowbridgeReitz(0.3f, 0.3f), kEta, kK),
                                 SphericalTriangleLight(tri.a, tri.b, tri.c, kRadiance)));
    }
    registry.add_case(mis_of({.family = "mis_sharp_conductor_far_sphere", .params = {{"alpha", 0.05}},
                              .description = "sharp gold (alpha 0.05) whose lobe holds a sphere light 1e-3 rad "
                                             "across (1000 away)"},
                             {.heuristic = MisHeuristic::Power}, bsdf_direction(30.0, 180.0),
                             RoughConductor(TrowbridgeReitz(0.05f, 0.05f), kEta, kK),
                             SphereLight(at(1000.0, 30.0), 1.0f, kRadiance)));
    {
        const ThreeLights l = three_lights();
        registry.add_case(mis_of({.family = "mis_diffuse_two_lights", .params = {},
                                  .description = "diffuse surface, a sphere light and a disk light as two strategies"},
                                 {.heuristic = MisHeuristic::Power}, bsdf_direction(40.0, 180.0), Lambertian(0.8f),
                                 l.sphere, l.disk));
    }
    {
        std::vector<float> sky;
        for (int j = 0; j < 16; ++j)
            for (int i = 0; i < 32; ++i)
                sky.push_back(i == 9 && j == 3 ? 500.0f : j < 8 ? 1.0f + 0.5f * std::cos(0.19634954f * i) : 0.05f);
        registry.add_case(mis_of({.family = "mis_diffuse_sky", .params = {},
                                  .description = "diffuse surface under an equirectangular sky with a sun"},
                                 {.heuristic = MisHeuristic::Power}, bsdf_direction(40.0, 180.0), Lambertian(0.8f),
                                 EnvironmentLight(32, 16, std::move(sky))));
    }
    registry.add_case(triangle_mis_through_plane(false));
}

}  // namespace
}  // namespace builtin_mis

namespace {
void register_mis_cases(Registry& registry) { builtin_mis::register_mis_cases(registry); }
}  // namespace

WARPCHECK_BUILTIN_CASES(85, register_mis_cases);

std::vector<FlawedLight> mis_flawed_catalogue() {
    using namespace builtin_mis;
    return {
        // The sum's weights no longer add to 1, so the estimate moves; the
        // one-sample model returns the light's own pdf where its pdf() is the
        // sum's.
        {[] { return triangle_mis_through_plane(true); }, "mis_weights",
         "MIS: an area pdf in the solid-angle sum", {"sample_pdf", "mis_estimator"}},
        {set_without_pmf, "mis_weights", "MIS: a light set's pdf without its pmf", {"sample_pdf", "mis_estimator"}},
        // And the one-sample model's pdf is 0 where the BSDF alone samples.
        {light_weight_without_bsdf, "mis_weights", "MIS: the light's weight without the BSDF's pdf",
         {"consistency", "sample_pdf", "mis_estimator"}},
        // Consistent wherever the weights look: only the estimate sees it.
        {conductor_pdf_high_on_half, "mis_estimator", "MIS: the BSDF's pdf 3% high on half the sphere", {}},
    };
}

}  // namespace warpcheck

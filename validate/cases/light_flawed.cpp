// Known-bad lights, one per bug class renderers have shipped or users have
// reported, each made from a built-in (sampling/light.h) with the bug put in,
// and registered only with --include-flawed. Each names the check meant to
// catch it and the other checks its bug rightly moves (registry.h, FlawedLight).
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "sampling/light.h"
#include "sampling/light_set.h"
#include "validate/api/light_case.h"
#include "validate/api/registry.h"
#include "validate/cases/light_cases.h"

namespace warpcheck {
// A named namespace around the file's own names: the unity build compiles
// this file with validate/cases/light.cpp (kLe, kAtOrigin).
namespace flawed_lights {
namespace {

constexpr LightClaims kAtOrigin{.ref = {0.0f, 0.0f, 0.0f}, .normal = {0.0f, 0.0f, 1.0f}};
constexpr float kLe = 2.0f;

WarpCaseInfo flawed_info(const char* family, std::vector<Parameter> params, const char* description) {
    return {.family = family, .params = std::move(params), .description = description};
}

/// The triangle the flawed planar lights use: 2 from the origin, 45 degrees off the normal, facing it.
const Vector3f kTriangle[3] = {{1.0606602f, -0.4f, 1.767767f}, {1.8384776f, -0.3f, 0.98994949f}, {1.4142136f, 0.6f, 1.4142136f}};

/// A sphere light sampled over a cone twice as wide as the sphere (1 - cos
/// theta_max taken as r^2 / d^2, which is sin^2, not 1 - cos): half the
/// samples miss it, yet each returns Le and the cone's pdf.
struct SphereConeTooWide {
    SphereLight sphere;
    Vector3f centre;
    float radius;

    float one_minus_cos_max(Vector3f ref) const {
        const Vector3f oc = centre - ref;
        return radius * radius / dot(oc, oc);
    }
    LightSample sample(Vector3f ref, Point2f u) const {
        const Vector3f oc = centre - ref;
        const float omc_max = one_minus_cos_max(ref);
        const float omc = u.x * omc_max;
        const float s = std::sqrt(omc * (2.0f - omc));
        const SinCos phi = sin_cos(kTwoPi * u.y);
        const Vector3f wi = Frame::around(normalize(oc)).to_world(s * phi.cos, s * phi.sin, 1.0f - omc);
        return {wi, 1.0f / (kTwoPi * omc_max), kLe, length(oc)};
    }
    float pdf(Vector3f ref, Vector3f wi) const {
        const float omc_max = one_minus_cos_max(ref);
        return 1.0f - dot(normalize(centre - ref), wi) <= omc_max ? 1.0f / (kTwoPi * omc_max) : 0.0f;
    }
    float L(Vector3f ref, Vector3f wi) const { return sphere.L(ref, wi); }
};

std::unique_ptr<WarpCase> sphere_cone_too_wide() {
    const Vector3f c{2.0f, 0.0f, 3.4641016f};
    return make_light_case(flawed_info("sphere_light_cone_too_wide", {{"distance", 4}, {"theta", 30}},
                                       "sphere light sampled over a cone of 1 - cos = r^2 / d^2: twice too wide"),
                           kAtOrigin, SphereConeTooWide{SphereLight(c, 1.0f, kLe), c, 1.0f});
}

/// A triangle light whose sample converts its pdf to solid angle but whose
/// pdf() leaves it per area: the two measures MIS must not mix.
struct TrianglePdfPerArea {
    TriangleLight light;
    float area;
    LightSample sample(Vector3f ref, Point2f u) const { return light.sample(ref, u); }
    float pdf(Vector3f ref, Vector3f wi) const { return light.pdf(ref, wi) > 0.0f ? 1.0f / area : 0.0f; }
    float L(Vector3f ref, Vector3f wi) const { return light.L(ref, wi); }
};

std::unique_ptr<WarpCase> triangle_pdf_per_area() {
    const detail::Triangle t(kTriangle[0], kTriangle[1], kTriangle[2], "triangle");
    return make_light_case(flawed_info("triangle_light_pdf_per_area", {{"distance", 2}, {"theta", 45}},
                                       "pdf() returns the area density 1 / A, sample the solid-angle one"),
                           kAtOrigin,
                           TrianglePdfPerArea{TriangleLight(kTriangle[0], kTriangle[1], kTriangle[2], kLe), t.area()});
}

/// A triangle light whose pdf, returned and from pdf(), is scaled by `above`
/// on the part of the triangle with y > 0 (about 40% of it) and by `below`
/// elsewhere. The side is decided by the direction alone (the reference point
/// is the origin), so a sample and its float neighbours agree on it.
struct TrianglePdfScaled {
    TriangleLight light;
    float above, below;
    float factor(Vector3f wi) const { return wi.y > 0.0f ? above : below; }
    LightSample sample(Vector3f ref, Point2f u) const {
        LightSample s = light.sample(ref, u);
        s.pdf *= factor(s.wi);
        return s;
    }
    float pdf(Vector3f ref, Vector3f wi) const { return light.pdf(ref, wi) * factor(wi); }
    float L(Vector3f ref, Vector3f wi) const { return light.L(ref, wi); }
};

std::unique_ptr<WarpCase> triangle_pdf_scaled(const char* family, const char* description, float above,
                                              float below) {
    return make_light_case(flawed_info(family, {{"distance", 2}, {"theta", 45}}, description), kAtOrigin,
                           TrianglePdfScaled{TriangleLight(kTriangle[0], kTriangle[1], kTriangle[2], kLe), above,
                                             below});
}

std::unique_ptr<WarpCase> triangle_pdf_high_on_half() {
    return triangle_pdf_scaled("triangle_light_pdf_high_on_half",
                               "the pdf is 3% high on the part of the triangle with y > 0", 1.03f, 1.0f);
}

/// Tilted both ways: the density still integrates to within 1% of 1, and its shape is wrong.
std::unique_ptr<WarpCase> triangle_pdf_tilted() {
    return triangle_pdf_scaled("triangle_light_pdf_tilted", "the pdf is 3% high where y > 0 and 3% low elsewhere",
                               1.03f, 0.97f);
}

/// "Solid-angle sampling reverted to area sampling": the triangle drawn by
/// area while sample and pdf() still claim 1 / Omega.
struct SphericalTriangleByArea {
    TriangleLight by_area;
    SphericalTriangleLight by_solid_angle;
    LightSample sample(Vector3f ref, Point2f u) const {
        LightSample s = by_area.sample(ref, u);
        if (s.pdf > 0.0f) s.pdf = by_solid_angle.pdf(ref, s.wi);
        return s;
    }
    float pdf(Vector3f ref, Vector3f wi) const { return by_solid_angle.pdf(ref, wi); }
    float L(Vector3f ref, Vector3f wi) const { return by_solid_angle.L(ref, wi); }
};

std::unique_ptr<WarpCase> spherical_triangle_by_area() {
    return make_light_case(
        flawed_info("spherical_triangle_light_by_area", {{"distance", 2}, {"theta", 45}},
                    "draws the triangle by area but claims the solid-angle density 1 / Omega"),
        kAtOrigin,
        SphericalTriangleByArea{TriangleLight(kTriangle[0], kTriangle[1], kTriangle[2], kLe),
                                SphericalTriangleLight(kTriangle[0], kTriangle[1], kTriangle[2], kLe)});
}

/// A rectangle drawn by area while it claims the solid-angle density 1 /
/// Omega: the same reversion, on the spherical rectangle.
struct SphericalRectangleByArea {
    Vector3f corner, ex, ey;
    SphericalRectangleLight by_solid_angle;
    LightSample sample(Vector3f ref, Point2f u) const {
        const Vector3f d = (corner + u.x * ex + u.y * ey) - ref;
        const float dist = length(d);
        const Vector3f wi = (1.0f / dist) * d;
        return {wi, by_solid_angle.pdf(ref, wi), kLe, dist};
    }
    float pdf(Vector3f ref, Vector3f wi) const { return by_solid_angle.pdf(ref, wi); }
    float L(Vector3f ref, Vector3f wi) const { return by_solid_angle.L(ref, wi); }
};

std::unique_ptr<WarpCase> spherical_rectangle_by_area() {
    // 2 from the origin at theta 45, facing it: 1.1 along (cos 45, 0, -sin 45), 0.9 along y.
    const Vector3f corner{1.0606602f, -0.4f, 1.767767f}, ex{0.7778175f, 0.0f, -0.7778175f}, ey{0.0f, 0.9f, 0.0f};
    return make_light_case(
        flawed_info("spherical_rectangle_light_by_area", {{"distance", 2}, {"theta", 45}},
                    "draws the rectangle by area but claims the solid-angle density 1 / Omega"),
        kAtOrigin, SphericalRectangleByArea{corner, ex, ey, SphericalRectangleLight(corner, ex, ey, kLe)});
}

/// From inside a sphere light, the area density converted without the
/// cosine at the light: dist^2 / (4 pi r^2), returned and from pdf().
struct SphereInsideWithoutCosine {
    SphereLight light;
    Vector3f centre;
    float radius;
    float without_cosine(Vector3f ref, Vector3f wi, float pdf) const {
        if (!(pdf > 0.0f)) return pdf;
        // The hit point's distance t, from |cos| = t^2 / (pdf 4 pi r^2): the
        // correct density times |cos| at the light.
        const Vector3f oc = centre - ref;
        const float b = dot(oc, wi);
        const Vector3f perp = oc - b * wi;
        const float abs_cos = std::sqrt(std::max(0.0f, radius * radius - dot(perp, perp))) / radius;
        return pdf * abs_cos;
    }
    LightSample sample(Vector3f ref, Point2f u) const {
        LightSample s = light.sample(ref, u);
        s.pdf = without_cosine(ref, s.wi, s.pdf);
        return s;
    }
    float pdf(Vector3f ref, Vector3f wi) const { return without_cosine(ref, wi, light.pdf(ref, wi)); }
    float L(Vector3f ref, Vector3f wi) const { return light.L(ref, wi); }
};

std::unique_ptr<WarpCase> sphere_inside_without_cosine() {
    const Vector3f c{0.0f, 0.0f, 0.5f};
    return make_light_case(flawed_info("sphere_light_inside_without_cosine", {{"distance", 0.5}, {"theta", 0}},
                                       "from inside, the area density converted without |cos| at the light"),
                           kAtOrigin, SphereInsideWithoutCosine{SphereLight(c, 1.0f, kLe), c, 1.0f});
}

/// An environment map whose density omits the sin theta of the change from
/// (u, v) to solid angle: p(u, v) / (2 pi^2), returned and from pdf().
struct EnvironmentWithoutJacobian {
    EnvironmentLight env;
    static float sin_theta(Vector3f wi) { return std::hypot(wi.x, wi.y); }
    LightSample sample(Vector3f ref, Point2f u) const {
        LightSample s = env.sample(ref, u);
        s.pdf *= sin_theta(s.wi);
        return s;
    }
    float pdf(Vector3f ref, Vector3f wi) const { return env.pdf(ref, wi) * sin_theta(wi); }
    float L(Vector3f ref, Vector3f wi) const { return env.L(ref, wi); }
};

/// A smooth sky of 32 x 16 pixels, brighter towards +x.
std::vector<float> sky() {
    std::vector<float> pixels;
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 32; ++i)
            pixels.push_back(static_cast<float>(1.0 + 0.5 * std::cos(2.0 * std::numbers::pi * (i + 0.5) / 32.0)));
    return pixels;
}

std::unique_ptr<WarpCase> environment_without_jacobian() {
    return make_light_case(flawed_info("environment_without_jacobian", {{"width", 32}, {"height", 16}},
                                       "the density per solid angle omits 1 / sin theta"),
                           kAtOrigin, EnvironmentWithoutJacobian{EnvironmentLight(32, 16, sky())});
}

/// An environment map looked up half a texel off in phi from where its
/// distribution was built: a single lit pixel is drawn where it is not.
struct EnvironmentHalfTexel {
    EnvironmentLight env;
    int width;
    Vector3f shifted(Vector3f wi) const {
        const float a = std::numbers::pi_v<float> / static_cast<float>(width);
        const float c = std::cos(a), s = std::sin(a);
        return {c * wi.x - s * wi.y, s * wi.x + c * wi.y, wi.z};
    }
    LightSample sample(Vector3f ref, Point2f u) const {
        LightSample s = env.sample(ref, u);
        s.L = L(ref, s.wi);
        return s;
    }
    float pdf(Vector3f ref, Vector3f wi) const { return env.pdf(ref, wi); }
    float L(Vector3f ref, Vector3f wi) const { return env.L(ref, shifted(wi)); }
};

std::unique_ptr<WarpCase> environment_half_texel() {
    std::vector<float> pixels(64 * 32, 0.0f);
    pixels[10 * 64 + 40] = 1.0f;
    return make_light_case(flawed_info("environment_half_texel", {{"width", 64}, {"height", 32}},
                                       "radiance looked up half a texel off in phi from the sampling distribution"),
                           kAtOrigin, EnvironmentHalfTexel{EnvironmentLight(64, 32, std::move(pixels)), 64});
}

using ThreeLightSet = LightSet<SphereLight, TriangleLight, DiskLight>;

/// A light set whose sample returns pmf times pdf while pdf() leaves the pmf
/// out: the density MIS would use is the chosen light's, not the set's.
struct SetPdfWithoutPmf {
    ThreeLightSet set;
    ThreeLights lights;
    LightSample sample(Vector3f ref, Point2f u) const { return set.sample(ref, u); }
    float pdf(Vector3f ref, Vector3f wi) const {
        return lights.sphere.pdf(ref, wi) + lights.triangle.pdf(ref, wi) + lights.disk.pdf(ref, wi);
    }
    float L(Vector3f ref, Vector3f wi) const { return set.L(ref, wi); }
};

std::unique_ptr<WarpCase> set_pdf_without_pmf() {
    const ThreeLights l = three_lights();
    const float third = 1.0f / 3.0f;
    return make_light_case(flawed_info("light_set_pdf_without_pmf", {}, "pdf() omits the pmf that sample applies"),
                           kAtOrigin,
                           SetPdfWithoutPmf{ThreeLightSet({third, third, third}, l.sphere, l.triangle, l.disk), l});
}

/// A light set that picks its light as floor(u.x (n - 1)): the last light
/// is never chosen and each other one 1.5 times as often as its pmf says,
/// while sample and pdf() claim the pmf (the u scaling that left a
/// renderer's infinite lights unsampled).
struct SetLastUnsampled {
    ThreeLightSet set;
    ThreeLights lights;
    LightSample sample(Vector3f ref, Point2f u) const {
        const float scaled = u.x * 2.0f;
        const int chosen = static_cast<int>(scaled);
        const Point2f v{std::min(scaled - static_cast<float>(chosen), kOneMinusEpsilon), u.y};
        LightSample s = chosen == 0 ? lights.sphere.sample(ref, v) : lights.triangle.sample(ref, v);
        s.pdf *= set.pmf(static_cast<std::size_t>(chosen));
        return s;
    }
    float pdf(Vector3f ref, Vector3f wi) const { return set.pdf(ref, wi); }
    float L(Vector3f ref, Vector3f wi) const { return set.L(ref, wi); }
};

std::unique_ptr<WarpCase> set_last_unsampled() {
    const ThreeLights l = three_lights();
    const float third = 1.0f / 3.0f;
    return make_light_case(flawed_info("light_set_last_unsampled", {}, "the light is chosen as floor(u (n - 1))"),
                           kAtOrigin,
                           SetLastUnsampled{ThreeLightSet({third, third, third}, l.sphere, l.triangle, l.disk), l});
}

/// The light_set_sky set built as if its lights did not overlap: a sample
/// returns its chosen light's pmf times pdf, and that light's L, while the
/// sky shines behind the sphere and the disk. Each sample's L / pdf is still
/// unbiased for the lights' summed irradiance (an estimator per chosen
/// light), but the pdf it returns is not the density the set draws from
/// (pdf(), the pmf-weighted sum), so MIS weighs it wrongly.
std::unique_ptr<WarpCase> set_sky_chosen_pdf() {
    const ThreeLights l = three_lights();
    return make_light_case(
        flawed_info("light_set_sky_chosen_pdf", {},
                    "the sky set's samples return their chosen light's pmf x pdf and L, not the set's"),
        kAtOrigin,
        LightSet<SphereLight, DiskLight, EnvironmentLight>({0.25f, 0.25f, 0.5f}, l.sphere, l.disk, sky_light()));
}

}  // namespace
}  // namespace flawed_lights

std::vector<FlawedLight> light_flawed_catalogue() {
    using namespace flawed_lights;
    std::vector<FlawedLight> catalogue = {
        // Its pdf is the wrong cone's, consistently: chi2 passes; every sample
        // outside the sphere misses, and its Le over the too-small pdf doubles
        // the estimate.
        {sphere_cone_too_wide, "light_radiance", "samples a cone twice as wide as the sphere",
         {"light_support", "light_irradiance"}},
        // The estimator uses the returned (right) pdf; chi2 integrates pdf().
        {triangle_pdf_per_area, "sample_pdf", "pdf() per area, sample per solid angle", {"chi2"}},
        {triangle_pdf_high_on_half, "chi2", "pdf 3% high on half of the triangle", {"light_irradiance"}},
        {triangle_pdf_tilted, "chi2", "pdf 3% high on half of the triangle, 3% low on the rest", {"light_irradiance"}},
        {spherical_triangle_by_area, "chi2", "drawn by area, claims 1 / Omega", {"light_irradiance"}},
        {spherical_rectangle_by_area, "chi2", "rectangle drawn by area, claims 1 / Omega", {"light_irradiance"}},
        {sphere_inside_without_cosine, "chi2", "inside: area pdf converted without |cos|", {"light_irradiance"}},
        {environment_without_jacobian, "chi2", "environment map without the 1 / sin theta Jacobian",
         {"light_irradiance"}},
        // L and pdf disagree on where the pixel is: half the samples carry no
        // light, half its light is never drawn.
        {environment_half_texel, "light_support", "environment map off by half a texel", {"light_irradiance"}},
        // The estimator divides by the returned (right) density; chi2
        // integrates pdf(), three times too large.
        {set_pdf_without_pmf, "sample_pdf", "light set: pdf() without the pmf", {"chi2"}},
        {set_last_unsampled, "chi2", "light set: the last light never chosen", {"light_irradiance"}},
        // Its directions are drawn from the set's density, which pdf()
        // returns, and each L / pdf is an unbiased estimate: only the pdf
        // and L a sample returns are off, where the sky overlaps a light.
        {set_sky_chosen_pdf, "sample_pdf", "light set with a sky: a sample's pdf is its chosen light's",
         {"light_radiance"}},
    };
    for (FlawedLight& m : mis_flawed_catalogue()) catalogue.push_back(std::move(m));
    return catalogue;
}

void register_flawed_light_cases(Registry& registry) {
    for (const FlawedLight& flawed : light_flawed_catalogue()) {
        std::unique_ptr<WarpCase> light = flawed.make();
        const std::string name = light->name();
        registry.add_case(std::move(light));
        registry.mark_known_flaw(name, flawed.flaw + " (caught by " + flawed.caught_by + ")");
    }
}

}  // namespace warpcheck

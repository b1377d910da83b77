// Class 1 of issue 22: float rounding of the pdf.
//
// Henyey-Greenstein with the textbook float formula, (1 - g^2) / (4 pi (1 +
// g^2 - 2 g cos)^1.5). Correct: it is the phase function every renderer
// evaluates, and its sampler inverts the exact CDF. Hard: near the forward
// peak 1 + g^2 and 2 g cos cancel, and 1 + g^2 was rounded first (relative
// error ~1e-7 of ~2, against a difference of (1 - g)^2 = 1e-4 at g = 0.99),
// so the float density integrates to 1 + 1.35e-5 (g = 0.95) or 1 - 9.3e-5
// (g = 0.99), and a normalisation rule that allows only the quadrature's
// bound and 2^-20 fails it (checked in double: the double formula integrates
// to 1 within 1e-9). Sampled about +z and about an oblique axis (the rounding
// of the frame and of the dot product moves the error, and the verdict flips
// with the direction). Also hard for class 2: the cos theta view's last float
// below 1 holds 2.3e-5 of the mass at g = 0.95, more than the tabulated
// reach rule allows, and about a rotated axis the samples' cos theta never
// comes within 3e-8 of 1.
//
// Twins: the same lobe with its constant off by 1e-3 (ten times the float
// noise at g = 0.99); and smooth densities (linear on [0,1], cosine on the
// hemisphere), whose float evaluation is accurate to ~1e-7, with a 5e-5 scale
// error in the constant: both must still fail chi2's normalisation.
#include <string>
#include <vector>

#include "hard_warps.h"

namespace hard {
namespace {

using warpcheck::chi2::Domain;

struct HenyeyGreenstein {
    float g;
    Frame frame;
    float scale = 1;  // the twin's error: pdf times this

    /// cos theta about the axis by the inverse CDF, (1 + g^2 - ((1 - g^2) / (1 - g + 2 g u))^2) / (2 g).
    Vector3f sample(Point2f u) const {
        const float s = (1 - g * g) / (1 - g + 2 * g * u.x);
        const float cos_theta = std::fmin(std::fmax((1 + g * g - s * s) / (2 * g), -1.0f), 1.0f);
        return frame.to_world(spherical_direction(cos_theta, 2 * kPi * u.y));
    }
    float pdf(Vector3f w) const {
        const float cos_theta = dot(w, frame.z);
        return scale * (1 - g * g) / (4 * kPi * std::pow(1 + g * g - 2 * g * cos_theta, 1.5f));
    }
};

/// The marginal density of cos theta about the axis, in double.
double hg_cos_density(double g, double mu) { return (1 - g * g) / (2 * std::pow(1 + g * g - 2 * g * mu, 1.5)); }

void add_hg(warpcheck::Registry& registry, const std::string& family, double g, double theta_deg, float scale) {
    const Frame frame = Frame::from_z(unit_vector_deg(static_cast<float>(theta_deg), 30));
    std::vector<warpcheck::MonotoneMarginal> views{
        cos_theta_view(frame.z, true, -1, [g](double mu) { return hg_cos_density(g, mu); })};
    // The azimuth only about +z: about a rotated frame, the rounding of the
    // frame moves samples at phi ~ 0 across the seam to phi ~ 2 pi, and the
    // tabulated check compares phi as a line, not a circle (not one of issue
    // 22's classes; left out of the catalogue and reported).
    if (theta_deg == 0) views.push_back(azimuth_view(frame));
    registry.add_case(warpcheck::make_warp_case(
        {.family = family,
         .params = {{"g", g}, {"axis_theta", theta_deg}},
         .description = "Henyey-Greenstein phase function, textbook float formula, about an axis",
         .domain = Domain::sphere(),
         .views = views},
        HenyeyGreenstein{static_cast<float>(g), frame, scale}));
}

// x in [0,1] with density proportional to (1 - x) a + x b (my_warps.cpp's).
struct Linear {
    float a, b, scale = 1;
    float sample(float u) const {
        if (u == 0) return 0;
        return u * (a + b) / (a + std::sqrt((1 - u) * a * a + u * b * b));
    }
    float pdf(float x) const { return x < 0 || x > 1 ? 0 : scale * 2 * ((1 - x) * a + x * b) / (a + b); }
    float invert(float x) const { return std::fmin(x * (a * (2 - x) + b * x) / (a + b), kOneMinusEpsilon); }
};

// The cosine-weighted hemisphere by Malley's method on the polar disk.
struct CosineHemisphere {
    float scale = 1;
    Vector3f sample(Point2f u) const {
        const float r = std::sqrt(u.x), phi = 2 * kPi * u.y;
        return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::fmax(0.0f, 1 - u.x))};
    }
    float pdf(Vector3f w) const { return w.z < 0 ? 0 : scale * w.z / kPi; }
};

void add_smooth(warpcheck::Registry& registry, bool twin) {
    const float scale = twin ? 1 + 5e-5f : 1;
    const std::string suffix = twin ? "_scale_5e-5" : "";
    registry.add_case(warpcheck::make_warp_case({.family = "smooth_linear" + suffix,
                                                 .params = {{"a", 1}, {"b", 3}},
                                                 .description = "density (1 - x) a + x b on [0,1], by inversion",
                                                 .domain = Domain::interval(0, 1)},
                                                Linear{1, 3, scale}));
    registry.add_case(warpcheck::make_warp_case({.family = "smooth_cosine_hemisphere" + suffix,
                                                 .description = "cosine-weighted hemisphere (Malley), no inverse",
                                                 .domain = Domain::hemisphere()},
                                                CosineHemisphere{scale}));
}

}  // namespace

void register_float_pdf(warpcheck::Registry& registry) {
    // About +z for every g; about an oblique axis up to 0.95 (at 0.99 the
    // unbinned check's tabulation of the natural marginals, cos theta and phi
    // about +z, takes 15 s of CPU and still misses its accuracy).
    for (double g : {0.8, 0.9, 0.95, 0.99}) add_hg(registry, "hg_float", g, 0, 1);
    for (double g : {0.8, 0.9, 0.95}) add_hg(registry, "hg_float", g, 57, 1);
    // At g = 0.99 one float step of cos theta moves the float pdf by 0.2% at
    // the peak, and chi2's normalisation allowance is twice that noise summed
    // over the sphere (2.3e-3; the textbook formula's own error is 1.2e-4):
    // a 1e-3 constant there is inside what float evaluation may do and fails
    // only under --strict, so the twin at 0.99 is 1e-2 (at 0.9, 1e-3).
    add_hg(registry, "hg_float_norm_1e-2", 0.99, 0, 1 + 1e-2f);
    add_hg(registry, "hg_float_norm_1e-3", 0.9, 57, 1 - 1e-3f);
    mark_twin(registry, "hg_float_norm_1e-2[g=0.99,axis_theta=0]", "chi2", "the constant is 1e-2 too large");
    mark_twin(registry, "hg_float_norm_1e-3[g=0.9,axis_theta=57]", "chi2", "the constant is 1e-3 too small");
    add_smooth(registry, false);
    add_smooth(registry, true);
    mark_twin(registry, "smooth_linear_scale_5e-5[a=1,b=3]", "chi2", "the density integrates to 1 + 5e-5");
    mark_twin(registry, "smooth_cosine_hemisphere_scale_5e-5", "chi2", "the density integrates to 1 + 5e-5");
}

}  // namespace hard

// The catalogue of correct-but-hard warps (issue 22): what a renderer writes,
// in float, that warpcheck must pass, each beside a wrong twin of the same
// hardness that it must still fail. One file per class of the issue; this
// header holds what they share: renderer-style vector helpers (plain float
// math, as a renderer has them), the monotone views a spherical warp
// declares, and how a twin is marked.
//
// A twin is registered next to its correct warp and marked as a known flaw of
// the whole case, with the checks meant to catch it in a fixed form that
// run_hard.sh reads from `hard_warps --list`:
//     "wrong twin, caught by CHECK[,CHECK...]: why"
// or, where every check that runs must say FAIL (never ERROR):
//     "wrong twin, caught by every check: why"
#pragma once

#include <cmath>
#include <functional>
#include <numbers>
#include <string>

#include <chi2/domain_kinds.h>
#include <validate/api/external.h>

namespace hard {

using warpcheck::Point2f;
using warpcheck::Vector3f;

constexpr float kPi = std::numbers::pi_v<float>;
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

/// The direction of polar angle theta (given by its cosine) and azimuth phi
/// about +z, as renderers write it: sin from 1 - cos^2.
inline Vector3f spherical_direction(float cos_theta, float phi) {
    const float sin_theta = std::sqrt(std::fmax(0.0f, 1 - cos_theta * cos_theta));
    return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

/// The azimuth of (x, y) in [0, 1) turns, as pbrt-v4 inverts it: atan2, plus
/// 2 pi below 0, over 2 pi. Returns exactly 1.0 where phi rounds up to 2 pi
/// (u.y within a float of 1): renderers write it so, and issue 22 asks that
/// this be reported as its own class, not failed by default.
inline float azimuth_turns(float x, float y) {
    float phi = std::atan2(y, x);
    if (phi < 0) phi += 2 * kPi;
    return phi / (2 * kPi);
}

/// An orthonormal frame about a unit vector n (Duff et al. 2017, branchless),
/// as pbrt-v4 and Mitsuba build it.
struct Frame {
    Vector3f x, y, z;
    static Frame from_z(Vector3f n) {
        const float sign = std::copysign(1.0f, n.z);
        const float a = -1 / (sign + n.z);
        const float b = n.x * n.y * a;
        return {{1 + sign * n.x * n.x * a, sign * b, -sign * n.x}, {b, sign + n.y * n.y * a, -n.y}, n};
    }
    Vector3f to_world(Vector3f v) const { return v.x * x + v.y * y + v.z * z; }
};

/// v clamped into [0, 1) (the largest float below 1 at the top), as
/// renderers clamp an inverse's result to a valid input.
inline float clamp_unit(float v) { return std::fmin(std::fmax(v, 0.0f), kOneMinusEpsilon); }

/// A unit vector of polar angle theta_deg and azimuth phi_deg (degrees), in float.
inline Vector3f unit_vector_deg(float theta_deg, float phi_deg) {
    const float t = theta_deg * kPi / 180, p = phi_deg * kPi / 180;
    return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

/// The cos theta view about `axis` (in double, from the float output: the
/// cosine of the angle between the two, both normalised in double), driven by
/// u.x; `pdf` is its marginal density on [lo, 1].
warpcheck::MonotoneMarginal cos_theta_view(Vector3f axis, bool increasing, double lo, std::function<double(double)> pdf);
/// The azimuth view about frame.z, in [0, 2 pi), driven by u.y, uniform.
warpcheck::MonotoneMarginal azimuth_view(const Frame& frame);

/// Marks a registered case as a wrong twin (see the top of this file).
void mark_twin(warpcheck::Registry& registry, const std::string& case_name, const std::string& checks,
               const std::string& why);

// One registration function per class of issue 22 (and its two misses).
void register_float_pdf(warpcheck::Registry& registry);          // 1: float rounding of the pdf
void register_quantised_outputs(warpcheck::Registry& registry);  // 2: float quantisation of the outputs
void register_supports(warpcheck::Registry& registry);           // 3: supports smaller than the domain
void register_discontinuities(warpcheck::Registry& registry);    // 4: jumps and the quadrature's bound
void register_non_inversion(warpcheck::Registry& registry);      // 5: 1D samplers not monotone in u
void register_roundtrip_2d(warpcheck::Registry& registry);       // 6: 2D round trips at float resolution
void register_chance_rules(warpcheck::Registry& registry);       // 7: rules that fail by chance
void register_verdict_words(warpcheck::Registry& registry);      // 8: verdict words
void register_misses(warpcheck::Registry& registry);             // the misses: quantised remap, azimuth gap
void register_sharp_lobes(warpcheck::Registry& registry);        // issue 34: sharp lobes, small and thin supports, singular ends

}  // namespace hard

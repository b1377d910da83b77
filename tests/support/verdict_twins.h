// Wrong warps that earlier verdict rules let through, each with its correct
// twin: the twin must pass every default check, the wrong one must fail the
// check named. The math is written out here (not taken from sampling/), so a
// variant stays what it says whatever the library's warps become.
#pragma once

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <ostream>
#include <string>
#include <vector>

#include "validate/api/warp_case.h"

namespace warpcheck::testing {

struct VerdictTwin {
    std::string name;
    std::string bug;
    std::string caught_by;  ///< the check whose rule the variant tests
    std::function<std::unique_ptr<WarpCase>(const std::string& name)> wrong;
    std::function<std::unique_ptr<WarpCase>(const std::string& name)> correct;
};

/// How GoogleTest names a twin in its output (instead of the struct's bytes).
inline void PrintTo(const VerdictTwin& t, std::ostream* os) { *os << t.name; }

namespace twins {

inline constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;
inline constexpr float kInvPi = std::numbers::inv_pi_v<float>;
inline constexpr float kBelowOne = 0x1.fffffep-1f;

inline WarpCaseInfo info(const std::string& name, chi2::Domain domain, InputKind input) {
    return {name, {}, "verdict twin", input, domain};
}

/// atan2(y, x) / 2 pi in [0, 1): the azimuth's inverse, wrapped.
inline float azimuth(float x, float y) {
    const float phi = std::atan2(y, x) / kTwoPi;
    return phi < 0.0f ? std::fmin(phi + 1.0f, kBelowOne) : phi;
}

inline Point2f polar_disk(Point2f u, float turn) {
    const float r = std::sqrt(u.x), phi = turn * kTwoPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi)};
}
inline float disk_pdf(Point2f p) { return p.x * p.x + p.y * p.y <= 1.0f ? kInvPi : 0.0f; }

/// The polar disk, turning counter-clockwise (turn 1) or clockwise (turn -1).
inline std::unique_ptr<WarpCase> polar(const std::string& n, float turn, bool wrap) {
    return make_warp_case(info(n, chi2::Domain::unit_disk(), InputKind::Uniform2D),
                          warp_of([turn](Point2f u) { return polar_disk(u, turn); })
                              .with_pdf(disk_pdf)
                              .with_invert([turn, wrap](Point2f p) {
  const float phi = wrap ? azimuth(p.x, turn * p.y) : std::atan2(turn * p.y, p.x) / kTwoPi;
  return Point2f{std::fmin(p.x * p.x + p.y * p.y, kBelowOne), phi};
  }));
}

/// The uniform sphere with z = 2 u.x - 1 (the mirror of pbrt's 1 - 2 u.x), its
/// density scaled by `scale`.
inline std::unique_ptr<WarpCase> sphere(const std::string& n, bool nan_near_pole, float scale = 1.0f) {
    return make_warp_case(
        info(n, chi2::Domain::sphere(), InputKind::Uniform2D),
        warp_of([](Point2f u) {
            const float z = 2.0f * u.x - 1.0f, r = std::sqrt(std::fmax(0.0f, (1.0f - z) * (1.0f + z)));
            const float phi = kTwoPi * u.y;
            return Vector3f{r * std::cos(phi), r * std::sin(phi), z};
        })
            .with_pdf([scale](Vector3f) { return scale * 0.25f * kInvPi; })
            .with_invert([nan_near_pole](Vector3f w) {
                if (nan_near_pole && w.z > 0.999f) return Point2f{std::numeric_limits<float>::quiet_NaN(), 0.0f};
                return Point2f{std::fmin(0.5f * (w.z + 1.0f), kBelowOne), azimuth(w.x, w.y)};
            }));
}

/// Malley's method on the polar disk: a cosine-weighted hemisphere, with 1/pi
/// as given (0.318f: 1/pi typed by hand).
inline std::unique_ptr<WarpCase> malley_polar(const std::string& n, float inv_pi = kInvPi) {
    return make_warp_case(
        info(n, chi2::Domain::hemisphere(), InputKind::Uniform2D),
        warp_of([](Point2f u) {
            const Point2f d = polar_disk(u, 1.0f);
            return Vector3f{d.x, d.y, std::sqrt(std::fmax(0.0f, 1.0f - u.x))};
        })
            .with_pdf([inv_pi](Vector3f w) { return w.z >= 0.0f ? w.z * inv_pi : 0.0f; })
            .with_invert([](Vector3f w) { return Point2f{std::fmin(w.x * w.x + w.y * w.y, kBelowOne), azimuth(w.x, w.y)}; }));
}

/// x = u on [0, 1]; the wrong inverse adds 7.
inline std::unique_ptr<WarpCase> identity(const std::string& n, float offset) {
    return make_warp_case(
        info(n, chi2::Domain::interval(0, 1), InputKind::Uniform1D),
            warp_of([](float u) { return u; })
                .with_pdf([](float x) { return x >= 0.0f && x <= 1.0f ? 1.0f : 0.0f; })
                .with_invert([offset](float x) { return x + offset; }));
}

/// The exponential of rate 1e7: every sample lies below 2e-6, so any u maps
/// within 2^-16 of any other. The wrong inverse returns the survival function
/// exp(-rate x) = 1 - u, another input whose sample lies "near" x.
inline std::unique_ptr<WarpCase> steep_exponential(const std::string& n, bool survival) {
    constexpr float rate = 1e7f;
    return make_warp_case(
        info(n, chi2::Domain::half_line(0), InputKind::Uniform1D),
            warp_of([](float u) { return -std::log1p(-u) / rate; })
                .with_pdf([](float x) { return x >= 0.0f ? rate * std::exp(-rate * x) : 0.0f; })
                .with_invert([survival](float x) {
                    const float cdf = -std::expm1(-rate * x);
                    return std::fmin(survival ? 1.0f - cdf : cdf, kBelowOne);
                }));
}

/// The linear density 2x on [0, 1] (x = sqrt(u)); the wrong sampler returns
/// 0.5 for every u in (0, 2^-26], inputs a 2^-24 grid never holds.
inline std::unique_ptr<WarpCase> ramp(const std::string& n, bool wrong_below, float top = 1.0f) {
    return make_warp_case(
        info(n, chi2::Domain::interval(0, 1), InputKind::Uniform1D),
        warp_of([wrong_below, top](float u) {
                    return wrong_below && u > 0.0f && u <= 0x1p-26f ? 0.5f : std::fmin(std::sqrt(u), top);
                })
            .with_pdf([](float x) { return x >= 0.0f && x <= 1.0f ? 2.0f * x : 0.0f; })
            .with_invert([](float x) { return std::fmin(x * x, kBelowOne); }));
}

}  // namespace twins

inline std::vector<VerdictTwin> verdict_twins() {
    using namespace twins;
    return {
        {"disk_polar_inverse_unwrapped_atan2", "azimuth inverse atan2/2pi without wrapping: u.y < 0", "roundtrip",
         [](const std::string& n) { return polar(n, 1.0f, false); },
         [](const std::string& n) { return polar(n, 1.0f, true); }},
        {"disk_polar_clockwise_inverse_unwrapped", "clockwise disk, inverse not wrapped", "roundtrip",
         [](const std::string& n) { return polar(n, -1.0f, false); },
         [](const std::string& n) { return polar(n, -1.0f, true); }},
        {"interval_inverse_plus_seven", "inverse returns u + 7, outside [0,1)", "roundtrip",
         [](const std::string& n) { return identity(n, 7.0f); },
         [](const std::string& n) { return identity(n, 0.0f); }},
        {"sphere_inverse_nan_near_pole", "inverse NaN for z > 0.999", "roundtrip",
         [](const std::string& n) { return sphere(n, true); }, [](const std::string& n) { return sphere(n, false); }},
        {"steep_exponential_survival_inverse", "inverse 1 - CDF of a warp that squeezes all u below 2e-6", "roundtrip",
         [](const std::string& n) { return steep_exponential(n, true); },
         [](const std::string& n) { return steep_exponential(n, false); }},
        {"cosine_hemisphere_pdf_0318", "1/pi typed as 0.318f: the pdf is 9.7e-4 low", "chi2",
         [](const std::string& n) { return malley_polar(n, 0.318f); },
         [](const std::string& n) { return malley_polar(n); }},
        {"sphere_pdf_5e-5_high", "density 5e-5 too high", "chi2",
         [](const std::string& n) { return sphere(n, false, 1.00005f); },
         [](const std::string& n) { return sphere(n, false); }},
        {"ramp_never_reaches_the_top", "samples stop at 0.99976: the top 4.8e-4 of the mass is unreachable",
         "tabulated", [](const std::string& n) { return ramp(n, false, 0.99976f); },
         [](const std::string& n) { return ramp(n, false); }},
        {"ramp_wrong_below_2^-26", "sampler returns 0.5 for u in (0, 2^-26]", "roundtrip",
         [](const std::string& n) { return ramp(n, true); }, [](const std::string& n) { return ramp(n, false); }},
    };
}

/// Correct warps that look different from the built-in ones: each must pass
/// every default check.
inline std::vector<std::pair<std::string, std::function<std::unique_ptr<WarpCase>(const std::string&)>>>
equivalent_warps() {
    using namespace twins;
    return {{"sphere_z_2u_minus_1", [](const std::string& n) { return sphere(n, false); }},
            {"malley_on_polar_disk", [](const std::string& n) { return malley_polar(n); }},
            {"disk_polar_clockwise", [](const std::string& n) { return polar(n, -1.0f, true); }}};
}

}  // namespace warpcheck::testing

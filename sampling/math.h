// Constants and small numeric helpers shared by the warps.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <optional>

#include "sampling/float_bits.h"

namespace warpcheck {

inline constexpr float kPi = std::numbers::pi_v<float>;
inline constexpr float kInvPi = std::numbers::inv_pi_v<float>;
inline constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;
inline constexpr float kInvTwoPi = 0.5f * std::numbers::inv_pi_v<float>;
inline constexpr float kInvFourPi = 0.25f * std::numbers::inv_pi_v<float>;
inline constexpr float kPiOver2 = 0.5f * std::numbers::pi_v<float>;
inline constexpr float kPiOver4 = 0.25f * std::numbers::pi_v<float>;
inline constexpr float kFourOverPi = 4.0f * std::numbers::inv_pi_v<float>;

/// sqrt that maps the small negative results of rounding (and only those) to 0.
inline float safe_sqrt(float x) { return std::sqrt(std::max(x, 0.0f)); }

/// sqrt(1 - z^2) for |z| <= 1, computed as sqrt((1 - z)(1 + z)): accurate near
/// |z| = 1, where 1 - z*z loses the low bits of z.
inline float sin_from_cos(float z) { return safe_sqrt((1.0f - z) * (1.0f + z)); }

/// The azimuth of (x, y) as a fraction of a full turn, in [0, 1): the inverse of
/// phi = 2 pi u. Rounding can land exactly on 1 for phi just below 2 pi; that is
/// clamped to the largest float below 1 so the result stays a valid input.
inline float azimuth_to_unit(float x, float y) {
    float phi = std::atan2(y, x);
    if (phi < 0.0f) phi += kTwoPi;
    return std::min(phi * kInvTwoPi, kOneMinusEpsilon);
}

namespace detail {

/// The scalar operations of sin_cos_core (sampling/lanes.h has the same for lanes).
struct ScalarDoubleOps {
    using Real = double;
    using Int = int64_t;
    static Int truncate(Real x) { return static_cast<Int>(x); }
    static Real to_real(Int k) { return static_cast<Real>(k); }
    static Real select(bool m, Real a, Real b) { return m ? a : b; }
};

/// sin and cos of x, |x| <= 10, in double to within about 2^-52 relative, for
/// rounding to float: written once over an operation set (ScalarDoubleOps, or
/// lanes of doubles in sampling/lanes.h), so that the scalar warps and their
/// vectorised forms compute the same bits. x is reduced by the nearest multiple
/// k of pi/2 with pi/2 split in two parts (the first, 33 bits, times k is
/// exact), then sin and cos of the remainder (|y| <= pi/4) are odd and even
/// polynomials with the minimax coefficients of fdlibm's __kernel_sin and
/// __kernel_cos (error below 2^-58 there), and k mod 4 picks the quadrant.
// (Instantiated on GCC vector types by sampling/lanes.h; see the note there.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
template <typename Ops>
[[gnu::always_inline]] inline void sin_cos_core(typename Ops::Real x, typename Ops::Real& s,
                                                typename Ops::Real& c) {
    using Real = typename Ops::Real;
    constexpr double kTwoOverPi = 0x1.45f306dc9c883p-1;
    constexpr double kPiOver2Hi = 0x1.921fb544p0;              // 33 leading bits of pi/2
    constexpr double kPiOver2Lo = 0x1.0b4611a626331p-34;       // pi/2 - kPiOver2Hi
    // Round to nearest via truncation of a positive value: x >= -10 keeps it positive.
    const auto k = Ops::truncate(x * kTwoOverPi + 8.5) - 8;
    const Real kd = Ops::to_real(k);
    const Real y = (x - kd * kPiOver2Hi) - kd * kPiOver2Lo;
    const Real z = y * y;
    const Real sin_y =
        y + y * z *
                (-1.66666666666666324348e-01 +
                 z * (8.33333333332248946124e-03 +
                      z * (-1.98412698298579493134e-04 +
                           z * (2.75573137070700676789e-06 + z * (-2.50507602534068634195e-08 +
                                                                   z * 1.58969099521155010221e-10)))));
    const Real cos_y =
        1.0 - 0.5 * z +
        z * z *
            (4.16666666666666019037e-02 +
             z * (-1.38888888888741095749e-03 +
                  z * (2.48015872894767294178e-05 +
                       z * (-2.75573143513906633035e-07 + z * (2.08757232129817482790e-09 +
                                                                z * -1.13596475577881948265e-11)))));
    const auto q = k & 3;
    // Quadrant q: sin x = sin y, cos y, -sin y, -cos y; cos x = cos y, -sin y, -cos y, sin y.
    const auto odd = (q & 1) != 0;
    const auto negate_sin = (q & 2) != 0;
    const auto negate_cos = ((q + 1) & 2) != 0;
    const Real s_abs = Ops::select(odd, cos_y, sin_y);
    const Real c_abs = Ops::select(odd, sin_y, cos_y);
    s = Ops::select(negate_sin, -s_abs, s_abs);
    c = Ops::select(negate_cos, -c_abs, c_abs);
}
#pragma GCC diagnostic pop

/// The last value a thread computed from a key of N floats (compared bit for
/// bit): a light's view from one reference point, a microfacet warp seen from
/// one wo. A check evaluates millions of directions from one key, and each
/// value costs a few dozen nanoseconds of trigonometry; the value is a pure
/// function of the key, so the memo changes no result, and each thread has
/// its own, so it needs no lock. The reference is valid until the thread's
/// next call with the same View type.
template <typename View, std::size_t N, typename Compute>
const View& memo_view(const std::array<float, N>& key, Compute compute) {
    thread_local struct {
        std::array<float, N> key{};
        std::optional<View> view;
    } memo;
    if (!memo.view || std::memcmp(memo.key.data(), key.data(), sizeof(float) * N) != 0) {
        memo.view.reset();  // a compute() that throws leaves no stale value behind
        memo.view.emplace(compute());
        memo.key = key;
    }
    return *memo.view;
}

}  // namespace detail

struct SinCos {
    float sin, cos;
};

/// sin and cos of an angle |phi| <= 10 (the warps pass [-pi/4, 2 pi]), each
/// the double-precision value rounded once to float: the correctly rounded
/// result except within ~2^-29 of a rounding midpoint. Unlike libm's sinf and
/// cosf this has a vectorised twin (sampling/lanes.h) that gives the same
/// bits, so the chi-square test's fast path draws exactly the samples the
/// scalar warp does. Outside the range it defers to libm.
inline SinCos sin_cos(float phi) {
    if (!(std::abs(phi) <= 10.0f)) return {std::sin(phi), std::cos(phi)};
    double s, c;
    detail::sin_cos_core<detail::ScalarDoubleOps>(static_cast<double>(phi), s, c);
    return {static_cast<float>(s), static_cast<float>(c)};
}

/// sin and cos in double, for warps that compute in double.
struct SinCosDouble {
    double sin, cos;
};

/// sin and cos of |x| <= 10 in double, to within 2^-51 relative (about one ulp
/// of double): the kernel of sin_cos without its rounding to float. libm's double sin and cos
/// have no vectorised twin (and their last bit may depend on the processor:
/// glibc picks an FMA build where it can); this has one in sampling/lanes.h
/// with the same bits. Outside the range it defers to libm.
inline SinCosDouble sin_cos_double(double x) {
    if (!(std::abs(x) <= 10.0)) return {std::sin(x), std::cos(x)};
    SinCosDouble r{};
    detail::sin_cos_core<detail::ScalarDoubleOps>(x, r.sin, r.cos);
    return r;
}

}  // namespace warpcheck

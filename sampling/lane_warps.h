// Lane forms of the common spherical and disk warps: eight samples at once,
// each step the same IEEE operation (or libm function) as the scalar form in
// disk.h, hemisphere.h, sphere.h and trowbridge_reitz.h, so they return the
// same bits (tests/sampling/test_lanes.cpp).
// The scalar forms stay the readable definition; these feed the vectorised
// chi-square path (validate/lanes/lane_sampling.h). Branches of the scalar forms
// become selects: both sides are computed and the lane picks one.
#pragma once

#include <numbers>

#include "sampling/lanes.h"
#include "sampling/trowbridge_reitz.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"  // see sampling/lanes.h

namespace warpcheck::lanes {

/// A point per lane; z is 0 for points of the disk.
struct Points {
    F32 x, y, z;
};

/// UniformDiskPolar::sample.
struct UniformDiskPolarLanes {
    WARPCHECK_LANE Points operator()(F32 u0, F32 u1) const {
        const F32 r = sqrt(u0);
        const F32 phi = kTwoPi * u1;
        const SinCos sc = sin_cos(phi);
        return {r * sc.cos, r * sc.sin, F32{}};
    }
};

/// UniformDiskConcentric::sample: the wedge |a| > |b| and the other one both
/// computed, one selected; the centre (a = b = 0) maps to the origin.
struct UniformDiskConcentricLanes {
    WARPCHECK_LANE Points operator()(F32 u0, F32 u1) const {
        const F32 a = 2.0f * u0 - 1.0f;
        const F32 b = 2.0f * u1 - 1.0f;
        // Conditions stay inside ?: (see validate/lanes/lane_cells.h). |a| + |b| is 0
        // exactly at the centre a = b = 0, whose 0/0 becomes 0/1.
        const F32 size = abs(a) + abs(b);
        const F32 r = abs(a) > abs(b) ? a : b;
        const F32 ratio = (abs(a) > abs(b) ? b : a) / (size == 0.0f ? F32{} + 1.0f : r);
        const F32 t = kPiOver4 * ratio;
        const F32 phi = abs(a) > abs(b) ? t : kPiOver2 - t;
        const SinCos sc = sin_cos(phi);
        const F32 x = r * sc.cos, y = r * sc.sin;
        return {size == 0.0f ? F32{} : x, size == 0.0f ? F32{} : y, F32{}};
    }
};

/// CosineHemisphere::sample: the concentric disk lifted to the hemisphere.
struct CosineHemisphereLanes {
    WARPCHECK_LANE Points operator()(F32 u0, F32 u1) const {
        const Points d = UniformDiskConcentricLanes{}(u0, u1);
        return {d.x, d.y, safe_sqrt(1.0f - d.x * d.x - d.y * d.y)};
    }
};

/// UniformHemisphere::sample.
struct UniformHemisphereLanes {
    WARPCHECK_LANE Points operator()(F32 u0, F32 u1) const {
        const F32 z = u0;
        const F32 r = sin_from_cos(z);
        const F32 phi = kTwoPi * u1;
        const SinCos sc = sin_cos(phi);
        return {r * sc.cos, r * sc.sin, z};
    }
};

/// CosinePowerHemisphere::sample: the uniform hemisphere's map with z =
/// u.x^(1/(n+1)) in place of u.x, the power from libm per lane (lanes::pow).
struct CosinePowerHemisphereLanes {
    float exponent = 0.0f;
    friend bool operator==(const CosinePowerHemisphereLanes&, const CosinePowerHemisphereLanes&) = default;

    WARPCHECK_LANE Points operator()(F32 u0, F32 u1) const {
        return UniformHemisphereLanes{}(pow(u0, 1.0f / (exponent + 1.0f)), u1);
    }
};

/// UniformSphere::sample.
struct UniformSphereLanes {
    WARPCHECK_LANE Points operator()(F32 u0, F32 u1) const {
        const F32 z = 1.0f - 2.0f * u0;
        const F32 r = sin_from_cos(z);
        const F32 phi = kTwoPi * u1;
        const SinCos sc = sin_cos(phi);
        return {r * sc.cos, r * sc.sin, z};
    }
};

/// UniformCone::sample, for the cap z >= cos_theta_max.
struct UniformConeLanes {
    float cos_theta_max = 0.0f;
    friend bool operator==(const UniformConeLanes&, const UniformConeLanes&) = default;

    WARPCHECK_LANE Points operator()(F32 u0, F32 u1) const {
        const F32 one_minus_cos = u0 * (1.0f - cos_theta_max);
        const F32 z = 1.0f - one_minus_cos;
        const F32 r = safe_sqrt(one_minus_cos * (2.0f - one_minus_cos));
        const F32 phi = kTwoPi * u1;
        const SinCos sc = sin_cos(phi);
        return {r * sc.cos, r * sc.sin, z};
    }
};

/// TrowbridgeReitzNormals::sample: the polar disk point stretched by the
/// roughness and lifted, normalised as normalize() does (1 / length, times each).
struct TrowbridgeReitzNormalsLanes {
    float alpha_x = 1.0f, alpha_y = 1.0f;
    friend bool operator==(const TrowbridgeReitzNormalsLanes&, const TrowbridgeReitzNormalsLanes&) = default;

    WARPCHECK_LANE Points operator()(F32 u0, F32 u1) const {
        const Points p = UniformDiskPolarLanes{}(u0, u1);
        const F32 x = alpha_x * p.x, y = alpha_y * p.y, z = safe_sqrt(1.0f - u0);
        const F32 inv_length = 1.0f / sqrt(x * x + y * y + z * z);
        return {inv_length * x, inv_length * y, inv_length * z};
    }
};

/// TrowbridgeReitzVisibleNormals::sample, in lanes of doubles as the scalar
/// form computes in double: the concentric map's two wedges and the centre
/// computed and selected, then the cap point and the stretch.
struct TrowbridgeReitzVisibleNormalsLanes {
    float alpha_x = 1.0f, alpha_y = 1.0f;
    float wi_x = 0.0f, wi_y = 0.0f, k = 2.0f;
    double one_minus_wi_z = 0.0, rotation = 0.0;
    bool normal_incidence = true;

    TrowbridgeReitzVisibleNormalsLanes() = default;
    explicit TrowbridgeReitzVisibleNormalsLanes(const TrowbridgeReitzVisibleNormals& w)
        : alpha_x(w.tr_.alpha_x()), alpha_y(w.tr_.alpha_y()), wi_x(w.wi_.x), wi_y(w.wi_.y), k(w.k_),
          one_minus_wi_z(w.one_minus_wi_z_), rotation(w.rotation_), normal_incidence(w.normal_incidence_) {}
    friend bool operator==(const TrowbridgeReitzVisibleNormalsLanes&,
                           const TrowbridgeReitzVisibleNormalsLanes&) = default;

    WARPCHECK_LANE Points operator()(F32 u0, F32 u1) const {
        const F64 zero{}, a = 2.0 * to_f64(u0) - 1.0, b = 2.0 * to_f64(u1) - 1.0;
        // Each quotient on its own wedge; the other lanes divide by 1 and are not selected.
        const F64 b_over_a = b / (abs(a) > abs(b) ? a : zero + 1.0);
        const F64 a_over_b = a / (b != 0.0 ? b : zero + 1.0);
        const F64 r = abs(a) > abs(b) ? a : (b != 0.0 ? b : zero);
        const F64 phi = abs(a) > abs(b) ? std::numbers::pi / 4.0 * b_over_a
                                        : (b != 0.0 ? std::numbers::pi / 2.0 - std::numbers::pi / 4.0 * a_over_b : zero);
        const F64 one_minus_r = 1.0 - abs(r);
        const F64 one_minus_r2 = one_minus_r * (2.0 - one_minus_r);
        const SinCosDouble sc = sin_cos_double(phi + rotation);
        const F64 dx = r * sc.cos, dy = r * sc.sin;
        F64 hx = dx, hy = dy, hz = sqrt(one_minus_r2);
        if (!normal_incidence) {
            const double kd = k;
            const F64 scale = sqrt(kd * (one_minus_wi_z + kd * one_minus_r2));
            hx = dx * scale + static_cast<double>(wi_x);
            hy = dy * scale + static_cast<double>(wi_y);
            hz = kd * one_minus_r2;
            // Written as (hx == 0) & (hy == 0) & (hz == 0): masks, not && on vectors.
            const auto at_minus_wi = (hx == 0.0) & (hy == 0.0) & (hz == 0.0);
            hx = at_minus_wi ? zero + static_cast<double>(-wi_y) : hx;
            hy = at_minus_wi ? zero + static_cast<double>(wi_x) : hy;
        }
        const F64 mx = static_cast<double>(alpha_x) * hx, my = static_cast<double>(alpha_y) * hy;
        const F64 inv_len = 1.0 / sqrt(mx * mx + my * my + hz * hz);
        return {to_f32(mx * inv_len), to_f32(my * inv_len), to_f32(hz * inv_len)};
    }
};

}  // namespace warpcheck::lanes

#pragma GCC diagnostic pop

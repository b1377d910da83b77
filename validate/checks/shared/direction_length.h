// A float direction is unit length only to its rounding (~1e-8), and a value
// computed from it by a formula that cancels feels that length far beyond one
// float step of the direction: a half vector wi + wo seen from grazing, or
// cos_t = sqrt(1 - sin^2 t) near the critical angle. The checks that measure
// a pdf's or an f's response to its inputs' length (unbinned_check.cpp for a
// BSDF's wo, bsdf/bsdf_reciprocity.cpp for both inputs) share these.
#pragma once

#include <cmath>

#include "validate/api/warp_case.h"

namespace warpcheck {

/// The relative length change at which a response to a direction's length is
/// measured: 2^-23 moves the largest coordinate of a unit direction (at least
/// 1/sqrt(3), so in [0.5, 1)) by at least one float step, where a smaller
/// change rounds away; a real length error (2^-26 for a wo at 91 degrees) is
/// usually smaller, so the response is measured here and scaled to it, to
/// first order.
inline constexpr double kLengthProbe = 0x1p-23;

/// |len(w) - 1|, in double.
inline double length_error(const WarpOutput& w) {
    return std::abs(std::hypot(static_cast<double>(w[0]), static_cast<double>(w[1]), static_cast<double>(w[2])) - 1.0);
}

/// w scaled by s, each coordinate rounded to float.
inline WarpOutput scaled_direction(const WarpOutput& w, double s) {
    return WarpOutput{static_cast<float>(s * w[0]), static_cast<float>(s * w[1]), static_cast<float>(s * w[2])};
}

}  // namespace warpcheck

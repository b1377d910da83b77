// The float cell of a warp's output seen from its input: how far the input u
// may move before x = sample(u) leaves its float. It is the float spacing of
// x pulled back through the warp's Jacobian, which is measured by finite
// differences of sample() itself. The round-trip check excuses an inverse
// whose error stays within a few such cells (roundtrip.cpp states the rule).
#pragma once

#include <array>
#include <cmath>

#include "validate/api/warp_case.h"

namespace warpcheck {

/// The spacing of floats at x: the width of the float that holds |x| (the gap
/// to the next float up).
double float_spacing(float x);

/// x = sample(u)'s float cell, seen from u.
struct FloatCell {
    /// jacobian[k][j] = d x_k / d u_j, a finite difference of sample() at u;
    /// 0 where x_k does not move measurably (by 32 of its floats, float_cell.cpp)
    /// over any step along u_j up to a quarter of the input range.
    std::array<std::array<double, 2>, 3> jacobian{};
    /// The u-extent of x's float cell along each input axis: the float spacing
    /// of x pulled back through the Jacobian, the larger of the least-squares
    /// pull-back (the pseudo-inverse, which is the inverse for as many outputs
    /// as inputs) and the pull-back of each coordinate on its own (an inverse
    /// may read u_j off one coordinate, as it reads cos theta off z). +inf
    /// along an axis that sample does not depend on at u (a pole: every u_j
    /// there maps to x); 0 where the Jacobian has no pull-back (rank deficient
    /// without a flat axis).
    std::array<double, 2> extent{};

    bool flat(int axis) const { return std::isinf(extent[static_cast<std::size_t>(axis)]); }
};

/// Measures the float cell of x = sample(u) for a warp of `in_dims` uniform
/// inputs (1 or 2) and `out_dims` output coordinates (1 to 3). Calls sample()
/// a few dozen times: meant for the rare inputs whose round trip needs it.
FloatCell measure_float_cell(const WarpCase& warp, const WarpInput& u, const WarpOutput& x, int in_dims,
                             int out_dims);

}  // namespace warpcheck

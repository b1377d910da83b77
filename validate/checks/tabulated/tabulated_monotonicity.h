// Whether a view's coordinate is monotone in its input, measured on a
// deterministic grid: the tabulated check compares a warp with the inversion
// method only where sample is monotone in u, which a declared view claims and a
// 1D warp without views is measured for here. A sampler that is correct but
// not monotone (a 1D table drawn through an alias table, a mixture chosen by
// u) is then not applicable rather than failed; chi2 and unbinned test its
// distribution.
//
// The grid: the 2^16 inputs k 2^-16 (the table's own resolution: a fold that
// spans a bucket shows) and the edge inputs (0, every power of two down to the
// smallest denormal with its float neighbours, 1 - 2^-24), sorted; for a 2D
// warp the other input is 0.5. Each coordinate is compared with the furthest
// one reached at smaller inputs (in the declared direction, or the one the
// ends of the grid show): lying behind it is excused, and counted, within
// `noise`: the check passes the float slack of its x comparison (16 ulps of
// the range), the rounding by which a float warp's outputs may step back (a
// lerp (1 - u) a + u b does where x barely moves with u).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "validate/api/warp_case.h"

namespace warpcheck {

struct MonotonicityProbe {
    uint64_t inputs = 0;  ///< grid inputs tried
    uint64_t finite = 0;  ///< of which gave a finite coordinate (NaN is not evidence either way)
    bool increasing = true;  ///< the direction tested: declared, or shown by the ends of the grid
    uint64_t behind_within_noise = 0;  ///< inputs behind the furthest point reached, within the noise (excused)
    double largest_step_back = 0.0;    ///< the largest distance behind the furthest point reached
    /// Where the largest step back lies, when it exceeds the noise: not monotone.
    bool monotone = true;
    double from_x = 0.0, to_x = 0.0, at_u = 0.0;
    /// Every 128th grid point, for a plot of sample(u).
    std::vector<double> plot_u, plot_x;
};

/// Samples the warp on the grid and judges the coordinate's steps; `direction`
/// is the declared one, or empty to take it from the ends of the grid.
MonotonicityProbe probe_monotonicity(const WarpCase& warp, int input_coordinate,
                                     const std::function<double(const WarpOutput&)>& coordinate, double noise,
                                     std::optional<bool> direction);

}  // namespace warpcheck

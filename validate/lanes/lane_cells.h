// Binning on lanes: the cell of eight points at once, for the vectorised
// chi-square path (here, not in chi2/, because the lane types live with the
// warps in sampling/ and chi2/ includes only itself). It repeats Binning::bin's arithmetic for azimuthal domains
// (membership by |p|^2, v, the phi column by the octant table) in double, with
// comparisons in place of the table walk, so every point it classifies lands
// in the cell bin() gives it. Points it does not classify (NaN, outside the
// domain's slack) come back as -1, for the caller to hand to Binning::bin.
#pragma once

#include "chi2/binning.h"
#include "sampling/lanes.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"  // see sampling/lanes.h

namespace warpcheck {

/// The cell of each lane's point (x, y, z as floats; z is 0 on the disk), or -1
/// where the point is NaN, outside or at a pole and Binning::bin must decide.
WARPCHECK_LANE lanes::I64 lane_cells(const chi2::LanePlan& plan, lanes::F32 xf, lanes::F32 yf, lanes::F32 zf) {
    // Every condition is written inside its ?: so that the compiler keeps it a
    // vector mask (a comparison turned into an integer vector is done lane by lane).
    using lanes::F64;
    using lanes::I64;
    const I64 zero{}, one = zero + 1;
    const F64 x = lanes::to_f64(xf), y = lanes::to_f64(yf), z = lanes::to_f64(zf);
    const F64 xy2 = x * x + y * y;
    const F64 len2 = plan.sphere ? xy2 + z * z : xy2;
    // v as Disk::v_of and SphericalCap::polar_height (z read off x and y near
    // the poles), the same operations in the same order.
    const F64 north = 1.0 - xy2 / (1.0 + z), south = -1.0 + xy2 / (1.0 - z);
    const F64 height = z >= 0.5 ? north : (z <= -0.5 ? south : z);
    const F64 v = plan.sphere ? height : xy2;
    // The phi column, as Binning::phi_column_by_table: the octant's column is the
    // number of its interior edges tan(k du) at or below t = min/max of |x|, |y|.
    const F64 ax = lanes::abs(x), ay = lanes::abs(y);
    const F64 hi = ax < ay ? ay : ax, lo = ay < ax ? ay : ax;
    const F64 t = hi > 0.0 ? lo / (hi > 0.0 ? hi : F64{} + 1.0) : F64{};
    I64 j = zero;
    for (int k = 0; k + 1 < plan.octant_cols; ++k) j += t >= plan.tan_edges[k] ? one : zero;
    // Quadrant and octant by selects: above the diagonal the octant's columns run
    // backwards; (+,+) q, (-,+) 2Q-1-q, (-,-) 2Q+q, (+,-) 4Q-1-q.
    const int64_t quadrant_cols = 2 * int64_t{plan.octant_cols};
    const I64 q = ay > ax ? (quadrant_cols - 1) - j : j;
    const I64 mirrored_q = (2 * quadrant_cols - 1) - q;
    const I64 col = x < 0.0 ? (y < 0.0 ? q + 2 * quadrant_cols : mirrored_q)
                            : (y < 0.0 ? mirrored_q + 2 * quadrant_cols : q);
    // The row, as clamp_index((v - v0) / dv, rows): NaN and negatives to 0, at most rows - 1.
    F64 f = (v - plan.v0) * plan.inv_dv;
    f = f >= 0.0 ? f : F64{};
    f = f >= static_cast<double>(plan.rows) ? F64{} + static_cast<double>(plan.rows - 1) : f;
    const I64 cell = __builtin_convertvector(f, I64) * plan.cols + col;
    // Membership as Disk::bin_contains and SphericalCap::bin_contains (false for
    // NaN); a pole (x = y = 0) is left to Binning::bin, which sets it apart.
    I64 out = len2 <= plan.len2_hi ? cell : zero - 1;
    out = hi > 0.0 ? out : zero - 1;
    if (plan.sphere) {
        // Both conditions in one mask: z - z_floor >= 0 exactly when z >= z_floor
        // (IEEE subtraction keeps the sign), and NaN fails either way.
        const F64 cap = len2 >= plan.len2_lo ? z - plan.z_floor : F64{} - 1.0;
        out = cap >= 0.0 ? out : zero - 1;
    }
    return out;
}

}  // namespace warpcheck

#pragma GCC diagnostic pop

// Two implementations of one warp given the same inputs: do they agree to the
// float? The distance of two outputs is the largest, over their coordinates,
// of the number of floats between them (ulps; +0 and -0 are one value), so
// "within 4 ulps" means the same thing near 0 and near 1. The row shows how
// the distances are spread (a histogram by powers of two) and the inputs where
// they are largest, and fails where any distance exceeds the stated number of
// ulps or either output is NaN (a NaN never agrees).
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "reports/result.h"
#include "validate/api/warp_case.h"

namespace warpcheck {

/// Floats strictly between a and b, plus one (0 when equal, +0 and -0 equal);
/// UINT64_MAX when either is NaN.
uint64_t ulp_distance(float a, float b);
/// The same, except that values smaller than `floor` in magnitude are compared
/// on the float grid at `floor`: |a - b| in ulps of floor, rounded up (0 < floor).
uint64_t ulp_distance(float a, float b, float floor);

struct UlpComparison {
    /// The largest distance, in ulps, that still counts as agreement: what the
    /// two builds claim (0: bit for bit). It is the claim under test, so the
    /// caller states it; the row repeats it.
    uint64_t max_ulps = 0;
    /// 0: ulps on the float grid itself. Otherwise values below it in
    /// magnitude count in ulps of it: a warp's coordinate near 0 is often a
    /// difference of unit-size terms (x = r cos phi near phi = pi / 2), whose
    /// rounding is absolute, and on the grid near 0 a difference of 1e-9
    /// is 10^8 ulps. The outputs' scale (1 for directions) reads differences
    /// as a renderer does; the row names the floor it used.
    float floor = 0.0f;
    int dimension = 3;       ///< coordinates per output
    std::string label_a = "a", label_b = "b";
    /// The inputs both were given (empty: not known; the worst rows then show
    /// their row numbers only) and their kind.
    std::span<const WarpInput> inputs{};
    InputKind input_kind = InputKind::Uniform2D;
};

/// The comparison as a result row ("ulps"): verdict, figures, the histogram
/// (a bar per power of two: 0, 1, 2, 3-4, 5-8, ...) and the 10 worst inputs.
/// a and b must have the same length (the same inputs, row for row).
CheckResult compare_same_inputs(std::span<const WarpOutput> a, std::span<const WarpOutput> b, const UlpComparison& how);

}  // namespace warpcheck

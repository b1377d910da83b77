// Two implementations of one warp with independent draws (another build's or
// a GPU's own random numbers): do their samples come from one distribution?
// Chi-square homogeneity on adaptive cells of the pooled samples (chi2/two_sample.h)
// and Anderson-Darling two-sample on each coordinate of the domain's
// parameters (phi and cos theta on the sphere, x and y in a box, x on a line),
// combined into one p-value (Sidak over the tests) that the run judges at its
// corrected level. The row states its power: the tilt of a marginal that each
// test detects 90% of the time at the samples' effective size n_a n_b / (n_a + n_b).
#pragma once

#include <optional>
#include <span>
#include <string>

#include "chi2/domain.h"
#include "reports/result.h"
#include "validate/api/warp_case.h"
#include "validate/checks/check.h"

namespace warpcheck {

struct TwoSampleComparison {
    /// The domain both sample: its parameters are the coordinates tested, and
    /// a sample outside it fails. Unset: by the outputs' dimension, x on a
    /// line, (x, y) in the plane, directions by (phi, z).
    std::optional<chi2::Domain> domain;
    int dimension = 3;  ///< coordinates per output
    std::string label_a = "a", label_b = "b";
};

/// The comparison as a result row ("two_sample") with its p-value set; a NaN
/// output or one outside the domain fails it without a level. `options`
/// gives the level at which power is stated (validate/checks/shared/power_level.h).
CheckResult compare_independent(std::span<const WarpOutput> a, std::span<const WarpOutput> b,
                                const TwoSampleComparison& how, const RunOptions& options);

}  // namespace warpcheck

// Evidence that a stated power figure is right: the chi2 and unbinned checks
// state the smallest linear tilt of a marginal (chi2/power.h) that they detect
// with 90% probability at the planned level (checks/shared/power_level.h). This
// simulates exactly that deviation and counts how often the check detects it.
//
// The tilted sampler: a warp whose marginal coordinate is a monotone function
// of one uniform input u (the inversion method: x = F^-1(u) in 1D, cos theta
// or phi of a polar map in 2D) has F(x) = u. Feeding it w = G^-1(u) instead,
// with G(w) = w - eps w (1 - w), makes F(x) follow G: the density
// 1 + eps (2 F(x) - 1) on the probability scale, the family of the stated
// figure, at exactly the stated eps (its sign does not matter: the tests are
// symmetric under w -> 1 - w). The density claimed stays the warp's own.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "validate/checks/check.h"
#include "validate/api/warp_case.h"

namespace warpcheck {

/// G^-1(u) for G(w) = w - eps w (1 - w), |eps| < 1: the root of
/// eps w^2 + (1 - eps) w - u = 0 in [0, 1], written without cancellation.
double inverse_tilt(double u, double eps);

/// `base` with uniform input coordinate `coordinate` (0 or 1) passed through
/// inverse_tilt(., eps) before sampling; pdf and inverse are the base's.
std::unique_ptr<WarpCase> tilted_case(const WarpCase& base, int coordinate, double eps);

struct PowerSimulation {
    std::string case_name, check_name;
    std::string figure;       ///< the stated figure simulated, e.g. "power_ad_tilt_eps"
    double stated_eps = 0.0;  ///< its value for the base case
    double eps = 0.0;         ///< the tilt simulated (stated_eps times the scale asked for)
    double level = 0.0;       ///< the level the check's p-value is compared with
    int runs = 0;
    int detected = 0;
    double rate() const { return runs > 0 ? static_cast<double>(detected) / runs : 0.0; }
};

/// The input coordinate (0 or 1) that alone drives parameter `axis` of the
/// case's domain (chi2::Binning's parameters: cos theta or phi on the sphere,
/// x on a line), monotonically, so that tilting that input is exactly a tilt
/// of the parameter's marginal on its probability scale; nullopt when none
/// does. Found by sampling: 256 inputs, each with the other coordinate
/// redrawn three times, must give the same parameter within 1e-6 of its
/// range (float rounding of the other coordinate's terms), and the parameter
/// must be monotone in the coordinate within the same tolerance.
std::optional<int> driving_coordinate(const WarpCase& warp, int axis);

/// Reads `figure` from `check`'s result on `base` (seed options.seed), then
/// runs the check on the case tilted on input `coordinate` by `scale` times
/// that figure, `runs` times with seeds options.seed, options.seed + 1, ...,
/// and counts the runs whose p-value is below the planned level at which the
/// figure is stated (its family-wise alpha options.alpha, Sidak over
/// kPlannedTestsPerRun; a NaN p-value counts as detected).
PowerSimulation simulate_stated_power(const WarpCase& base, const Check& check, int coordinate,
                                      const std::string& figure, const RunOptions& options, int runs,
                                      double scale = 1.0);

}  // namespace warpcheck

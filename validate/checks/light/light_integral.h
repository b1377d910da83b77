// The reference and the rule that light_irradiance and mis_estimator share:
// an estimator's mean against an integral over the sphere of directions
// computed on cells that tile it, placed by a pilot of the sampler where the
// integrand is concentrated (a light a thousandth of a radian across), and
// the bias each row states it could see.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "chi2/binning.h"
#include "chi2/chi2_test.h"
#include "chi2/mean_test.h"
#include "chi2/quadrature.h"
#include "validate/api/warp_case.h"
#include "validate/checks/check.h"

namespace warpcheck::light {

/// The rounding allowance of the reference, relative, as for weight_mean: the
/// float value / pdf of every sample may be off by a few ulps in the same
/// direction, biasing the mean of 10^6 by up to ~16 ulps (2^-20).
inline constexpr double kRoundingAllowance = 0x1p-20;
/// The uniform cells of the reference's cubature, as bsdf_albedo's.
inline constexpr chi2::BinResolution kIntegralCells{16, 32};
/// The effect every row states its power against: a bias of 1% of the
/// integral, what a renderer's user sees as a wrong exposure; a row whose
/// test detects it less than 90% of the time is weak.
inline constexpr double kStatedBias = 0.01;

struct SphereIntegral {
    double value = 0.0, error = 0.0, float_noise = 0.0;
    uint64_t evaluations = 0;
    chi2::PilotRefinement refinement;
};

/// The integrand in batches, divided by `scale`: out[i] = g(wi[i]) / scale.
/// Each integrand divides where its own rounding is least (the irradiance's
/// L (|cos| / scale), as it always has: a reordering moves the adaptive
/// quadrature's refinement, and with it the figures, by a few evaluations).
using DirectionIntegrand = std::function<void(std::span<const WarpOutput>, std::span<double>, double scale)>;

/// The integral of `integrand` over the sphere (verified, with its float
/// noise): on kIntegralCells uniform cells, or, where `pilot` (the sampler's
/// directions) fills under a quarter of them, as many cells of equal pilot
/// probability (chi2's rule); then again on pieces the pilot places where its
/// points cluster (chi2::refine_by_pilot). `pilot_estimate`, the pilot's own
/// estimate of the integral, scales the integrand so that the quadrature's
/// absolute accuracy rule holds relative to the integral.
SphereIntegral integrate_sphere(const std::vector<chi2::SamplePoint>& pilot, double pilot_estimate,
                                const DirectionIntegrand& integrand, const CheckContext& ctx);

/// The reference's uncertainty: its verified bound, its float noise and the
/// estimator's rounding, each independent of the others.
double reference_uncertainty(const SphereIntegral& reference);

/// The relative bias of the mean the two-sided t-test detects 90% of the
/// time at the level of a typical run: (z_{1 - level/2} + z_{0.9}) standard
/// errors over the reference.
double bias_for_power(const CheckContext& ctx, const chi2::MeanTest& t);

/// The rule of an estimator's mean against the integral: the t-test of the
/// finite estimates' moments, with the reference's uncertainty; the row
/// passes unless the runner's level rejects its p-value, states the bias it
/// detects 90% of the time (power_relative_bias) and is weak where that is
/// above kStatedBias; it fails where any estimate is not finite (`invalid`,
/// explained by `invalid_why`). `extra` figures stand before the pilot's.
/// what: the integral's name, estimator: the estimator's, for the summary
/// and the message.
/// The row also carries its point on the family's plot (reports/family_plots.h):
/// the estimate over the integral, minus 1, with its 99% interval, against
/// the case's `theta` (the light's direction from the normal) where it has
/// one, its other parameters naming the curve.
CheckResult judge_estimate(const WarpCase& warp, const chi2::Moments& moments, uint64_t invalid,
                           const SphereIntegral& reference, const CheckContext& ctx, const char* what,
                           const char* estimator, const char* invalid_why, std::vector<Figure> extra = {});

}  // namespace warpcheck::light

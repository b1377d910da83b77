// Small statistics of the BSDF checks: binomial tests of lobe shares, and the
// deviations a test detects with 90% probability (their stated power).
#pragma once

#include <cstdint>

namespace warpcheck::bsdf {

/// The two-sided exact binomial p-value of k successes in n trials against the
/// success probability in [p_lo, p_hi] nearest to k / n: 1 when k / n lies in
/// the band (a band is the uncertainty of a claimed probability: quadrature
/// error, float rounding), else twice the smaller tail at the nearer end, at
/// most 1. A probability of 0 or 1 allows only k = 0 or k = n. NaN if an end is NaN.
double binomial_band_p(uint64_t k, uint64_t n, double p_lo, double p_hi);

/// The two-sided normal quantile sum z_(1 - level/2) + z_(power): a test at
/// `level` detects a shift of this many standard errors with probability
/// `power` (the normal approximation of a t-test or a binomial test at large n).
double detectable_shift_in_standard_errors(double level, double power = 0.9);

}  // namespace warpcheck::bsdf

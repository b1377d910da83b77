// Whether samples' mean agrees with a known value: streaming moments that merge
// in a fixed order, and Student's t-test of the mean against the value. For an
// importance-weighted estimator (a BSDF sampler's weights, 1/pdf over the
// samples) the central limit theorem makes the mean normal with the samples'
// own variance over n, provided that variance is finite.
#pragma once

#include <cstdint>

namespace warpcheck::chi2 {

/// Count, mean and sum of squared deviations (Welford), mergeable (Chan et al.):
/// merging the same parts in the same order gives the same bits.
struct Moments {
    uint64_t n = 0;
    double mean = 0.0;
    double m2 = 0.0;

    void add(double x) {
        ++n;
        const double d = x - mean;
        mean += d / static_cast<double>(n);
        m2 += d * (x - mean);
    }
    void merge(const Moments& o) {
        if (o.n == 0) return;
        if (n == 0) {
            *this = o;
            return;
        }
        const double total = static_cast<double>(n + o.n);
        const double d = o.mean - mean;
        mean += d * static_cast<double>(o.n) / total;
        m2 += o.m2 + d * d * static_cast<double>(n) * static_cast<double>(o.n) / total;
        n += o.n;
    }
    /// The unbiased sample variance (NaN below two samples).
    double variance() const;
};

struct MeanTest {
    double mean = 0.0;
    double reference = 0.0;
    double standard_error = 0.0;  ///< of the difference, all uncertainties included
    double t = 0.0;               ///< (mean - reference) / standard_error
    double p_value = 0.0;         ///< two-sided; NaN when any input is NaN
};

/// Two-sided t-test (n - 1 degrees of freedom) of H0: E[X] = reference.
/// `reference_uncertainty` (an absolute bound, e.g. a quadrature error) is
/// added to the standard error in quadrature, so that a reference known only
/// to +-e, or samples of zero variance, cannot fail by that alone.
MeanTest mean_test(const Moments& m, double reference, double reference_uncertainty);

/// The same test against a reference known only within +-band, a systematic
/// bound (the float rounding of the density it integrates, which every sample
/// shares rather than averages out): the part of the difference beyond the
/// band is tested (t = 0 within it). `reference_uncertainty` is added to the
/// standard error as above.
MeanTest mean_test(const Moments& m, double reference, double reference_uncertainty, double band);

}  // namespace warpcheck::chi2

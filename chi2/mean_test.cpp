#include "chi2/mean_test.h"

#include <cmath>
#include <limits>

#include <boost/math/distributions/students_t.hpp>

namespace warpcheck::chi2 {

double Moments::variance() const {
    return n < 2 ? std::numeric_limits<double>::quiet_NaN() : m2 / static_cast<double>(n - 1);
}

MeanTest mean_test(const Moments& m, double reference, double reference_uncertainty) {
    MeanTest r;
    r.mean = m.mean;
    r.reference = reference;
    const double sampling = m.n < 2 ? 0.0 : m.variance() / static_cast<double>(m.n);
    r.standard_error = std::sqrt(sampling + reference_uncertainty * reference_uncertainty);
    r.t = (m.mean - reference) / r.standard_error;
    if (m.n < 2 || std::isnan(r.t)) {
        // 0/0 (no spread, no difference) agrees; anything NaN, or no samples, cannot be judged.
        const bool agrees = m.n >= 2 && m.mean == reference && r.standard_error == 0.0;
        r.p_value = agrees ? 1.0 : std::numeric_limits<double>::quiet_NaN();
        if (agrees) r.t = 0.0;
        return r;
    }
    if (std::isinf(r.t)) {
        r.p_value = 0.0;
        return r;
    }
    const boost::math::students_t dist(static_cast<double>(m.n - 1));
    r.p_value = 2.0 * boost::math::cdf(boost::math::complement(dist, std::abs(r.t)));
    return r;
}

MeanTest mean_test(const Moments& m, double reference, double reference_uncertainty, double band) {
    if (!(band > 0.0)) return mean_test(m, reference, reference_uncertainty);
    // The reference moved towards the mean by up to the band (NaN stays NaN).
    const double d = m.mean - reference;
    const double moved = std::abs(d) <= band ? m.mean : reference + (d > 0.0 ? band : -band);
    MeanTest r = mean_test(m, std::isnan(d) ? reference : moved, reference_uncertainty);
    r.reference = reference;
    return r;
}

}  // namespace warpcheck::chi2

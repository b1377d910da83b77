#include "validate/checks/bsdf/bsdf_statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/normal.hpp>

namespace warpcheck::bsdf {

double binomial_band_p(uint64_t k, uint64_t n, double p_lo, double p_hi) {
    if (std::isnan(p_lo) || std::isnan(p_hi)) return std::numeric_limits<double>::quiet_NaN();
    if (n == 0) return 1.0;
    p_lo = std::clamp(p_lo, 0.0, 1.0);
    p_hi = std::clamp(p_hi, p_lo, 1.0);
    const double share = static_cast<double>(k) / static_cast<double>(n);
    if (share >= p_lo && share <= p_hi) return 1.0;
    const double p = share < p_lo ? p_lo : p_hi;
    if (p <= 0.0) return k == 0 ? 1.0 : 0.0;
    if (p >= 1.0) return k == n ? 1.0 : 0.0;
    const boost::math::binomial_distribution<double> law(static_cast<double>(n), p);
    const double x = static_cast<double>(k);
    // k lies beyond the band, so beyond the mean n p: only that tail is small.
    const double tail = share < p ? boost::math::cdf(law, x)
                                  : (k == 0 ? 1.0 : boost::math::cdf(boost::math::complement(law, x - 1.0)));
    return std::min(1.0, 2.0 * tail);
}

double detectable_shift_in_standard_errors(double level, double power) {
    const boost::math::normal_distribution<double> z;
    return boost::math::quantile(boost::math::complement(z, level / 2.0)) + boost::math::quantile(z, power);
}

}  // namespace warpcheck::bsdf

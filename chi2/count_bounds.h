// Bounds on counts of rare events, for rules of the form "at most k of N inputs
// may do X": k is the count a Poisson process of the stated mean exceeds only
// with a stated small probability, so such a rule is a test with a known level.
#pragma once

#include <cmath>
#include <cstdint>

#include <boost/math/distributions/poisson.hpp>

namespace warpcheck::chi2 {

/// The smallest k with P(K > k) <= tail_probability for K ~ Poisson(mean).
/// mean 0 gives 0; a non-finite or negative mean, or a tail probability outside
/// (0, 1), gives 0 too (the strictest rule), never a NaN.
inline uint64_t poisson_count_bound(double mean, double tail_probability) {
    if (!(mean > 0.0) || !std::isfinite(mean) || !(tail_probability > 0.0 && tail_probability < 1.0)) return 0;
    using Policy = boost::math::policies::policy<
        boost::math::policies::discrete_quantile<boost::math::policies::integer_round_up>>;
    const boost::math::poisson_distribution<double, Policy> dist(mean);
    return static_cast<uint64_t>(boost::math::quantile(boost::math::complement(dist, tail_probability)));
}

}  // namespace warpcheck::chi2

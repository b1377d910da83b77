// The reference of the "tabulated" check: a density tabulated into a
// piecewise-constant table held in double, with the tolerances its
// discretisation implies. (The renderer-facing sampling/piecewise_constant.h
// stores float values: a density below 1.4e-45 underflows there to 0, and a
// lobe's quantile at u = 0 then lands where the float values begin instead of
// at the start of the range. This table never rounds to float.)
//
// The density is tabulated into kBuckets equal buckets, each the supersampled
// average of the density. For the same u, the table's sample and the warp's
// sample then differ only by the table's discretisation - by an amount that
// follows from the bucket width and how much the density varies across the
// bucket:
//
//   x: the exact CDF F and the table's piecewise-linear CDF L agree at bucket
//      edges, so the two samples lie in the same bucket. Within it, with the
//      density between fmin and fmax, |F - L| <= (fmax - fmin) w / 2, and the
//      slope of F is at least fmin, so |x_warp - x_table| <= min(w, (fmax - fmin) w / (2 fmin)).
//   pdf: the table's density is the bucket average, the warp's density at x lies
//      in [fmin, fmax]: |pdf_warp - pdf_table| <= fmax - fmin.
//
//   CDF accuracy: a float warp inverts its CDF at a u it has itself rounded
//      (forming 1 - u, 1/u - 1 or (u - c) / p in float rounds u by up to one
//      float step of [0.5, 1), 2^-24, and two such steps are allowed: 2^-23),
//      and its float density values carry a relative rounding of up to 2^-22
//      (a bias of up to 2^-22 in the CDF if systematic); the table's bucket
//      averages add their quadrature error accumulated up to there. That error is estimated per bucket
//      from the one-panel trapezoid T (edges) against the 16-point midpoint rule M:
//      their errors are -2 x 16^2 : 1 for smooth f, so |T - M| / 256 overstates
//      M's error by ~2x. So x is only determined to within the interval C^-1(u -+ delta) of
//      the table's CDF C (reaching the end of the range where u -+ delta leaves
//      [0, 1]): its width is added to the x tolerance. It
//      is ~delta / density, and large only where the density is tiny (in the tail
//      of c = 100 on [0, 1], the last 2^-24 of mass spans x in [0.166, 1]).
//
// fmin and fmax come from the supersample points and bucket edges; a 25% margin
// covers extrema between those points. Float slack on top: 16 ulps of the range
// for x (the warp's own rounding) and 1e-5 relative for densities. The density's
// integral over the range has the midpoint rule's error bound (sum over buckets
// of (fmax - fmin) w / supersamples) as its tolerance.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "sampling/tabulate.h"

namespace warpcheck {

class TabulatedReference {
public:
    static constexpr int kBuckets = 1 << 16;
    static constexpr int kSupersamples = 16;

    /// Tabulates `density` on [lo, hi]; `body_mass` is the probability the
    /// range holds (1 minus a truncated tail). A NaN density is recorded
    /// (nan_values), not thrown: it is the warp's defect, for the check to
    /// fail. Throws if the density is infinite on the range (a table cannot
    /// hold it).
    TabulatedReference(const std::function<double(double)>& density, double lo, double hi, double body_mass);

    /// The table's sample for u in [0, 1) of the body: the bucket whose CDF
    /// range holds u (never one of zero mass), linear within it, in double.
    struct Sample {
        double x = 0.0;
        int offset = 0;
    };
    Sample sample(double u_body) const;
    /// The table's density at x, scaled to the body's mass.
    double table_pdf(double x) const;

    /// How far the warp's x may lie from the table's sample in bucket `bucket`.
    double x_tolerance(int bucket, double u_body) const;

    /// The density's range around x (the bucket holding x, and its neighbour if
    /// x is within float slack of the edge) and the table's density there.
    struct Envelope {
        double lo = 0.0, hi = 0.0, table_pdf = 0.0;
    };
    Envelope envelope(double x) const;
    /// How far the warp's density may differ from the table's, relative to
    /// `reference` (the larger of the two).
    double pdf_tolerance(const Envelope& e, double reference) const;

    /// For a batch of inputs, at each u (in the body) and the warp's x: sample(u),
    /// x_tolerance there and envelope(x), the same numbers as one call at a time,
    /// found with the lookups of many inputs in flight at once (each one's table
    /// lines are fetched ahead of it: a lookup is a few loads from tables larger
    /// than the cache). Where u is NaN (an input outside the body) only the
    /// envelope is set.
    struct Lookup {
        Sample sample;
        double x_tolerance = 0.0;
        Envelope envelope;
    };
    void lookup(std::span<const double> u_body, std::span<const double> x, std::span<Lookup> out) const;

    /// How far beyond the truncation point lo (upper: hi) a sample of a tail
    /// input may stay: the x extent of the CDF uncertainty at that end (the
    /// same allowance a body input near the end gets) plus the float slack.
    double tail_allowance(bool upper) const;

    /// The table's CDF at x (in double, linear within a bucket), 0 below the
    /// range and 1 above it.
    double cdf(double x) const;

    double integral() const { return integral_; }
    double integral_tolerance() const { return integral_tol_; }
    double cdf_uncertainty() const { return cdf_delta_; }
    double bucket_width() const { return width_; }
    /// Float slack on x: 16 ulps of the range, the warp's own rounding.
    double x_slack() const { return x_slack_abs_; }
    /// The same slack for a range [lo, hi], before any table is built.
    static double float_slack(double lo, double hi);

    /// How many of the density's evaluations were NaN, and the first x where one was.
    uint64_t nan_values() const { return nan_values_; }
    uint64_t evaluations() const { return evaluations_; }
    double first_nan_x() const { return first_nan_x_; }

private:
    struct Located {
        std::size_t bucket = 0;
        double t = 0.0;  ///< where in the bucket, 0 .. 1
    };
    Located locate(double v) const;
    double inverse_cdf(double v) const;
    double quadrature_error(const std::function<double(double)>& density) const;
    void build_cdf();
    void build_guide();

    double lo_, hi_, width_, body_mass_;
    uint64_t nan_values_ = 0, evaluations_ = 0;
    double first_nan_x_ = 0.0;
    std::vector<BucketSummary> buckets_;
    std::vector<double> cdf_;  ///< the table's CDF at bucket edges, in double
    /// guide_[g]: the position in cdf_ of the first edge above g / kGuideCells,
    /// g = 0 .. kGuideCells, so that locate searches only between two of them
    /// (every check input looks up three CDF values: a search of the whole
    /// table cost three quarters of the check's time). Empty where cdf_ is not
    /// monotone (a negative density): locate then searches the whole table, as
    /// it always did, so the result is the same either way.
    std::vector<uint32_t> guide_;
    static constexpr int kGuideCells = kBuckets;
    double integral_ = 0.0, integral_tol_ = 1e-5, cdf_delta_ = 0.0, x_slack_abs_ = 0.0;
};

}  // namespace warpcheck

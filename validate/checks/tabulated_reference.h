// The reference of the "tabulated" check: a density tabulated into a
// PiecewiseConstant1D, with the tolerances its discretisation implies.
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
//   CDF accuracy: the table's CDF at bucket edges is off by its float rounding
//      (2^-24, and 2^-24 more for rounding u), the float rounding of the density
//      values (2^-22, relative, if systematic), and the quadrature error of the
//      bucket averages accumulated up to there. That error is estimated per bucket
//      from the one-panel trapezoid T (edges) against the 16-point midpoint rule M:
//      their errors are -2 x 16^2 : 1 for smooth f, so |T - M| / 256 overstates
//      M's error by ~2x. So x is only determined to within the interval C^-1(u -+ delta) of
//      the table's CDF C (in double): its width is added to the x tolerance. It
//      is ~delta / density, and large only where the density is tiny (in the tail
//      of c = 100 on [0, 1], the last 2^-24 of mass spans x in [0.166, 1]).
//
// fmin and fmax come from the supersample points and bucket edges; a 25% margin
// covers extrema between those points. Float slack on top: 16 ulps of the range
// for x (the warp's own rounding) and 1e-5 relative for densities. The density's
// integral over the range has the midpoint rule's error bound (sum over buckets
// of (fmax - fmin) w / supersamples) as its tolerance.
#pragma once

#include <functional>
#include <vector>

#include "sampling/piecewise_constant.h"
#include "sampling/tabulate.h"

namespace warpcheck {

class TabulatedReference {
public:
    static constexpr int kBuckets = 1 << 16;
    static constexpr int kSupersamples = 16;

    /// Tabulates `density` on [lo, hi]; `body_mass` is the probability the
    /// range holds (1 minus a truncated tail). Throws if the density is not
    /// finite on the range.
    TabulatedReference(const std::function<double(double)>& density, double lo, double hi, double body_mass);

    /// The table's sample for u in [0, 1) of the body.
    PiecewiseConstant1D::Sample sample(double u_body) const { return table_.sample(static_cast<float>(u_body)); }
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

    /// The table's CDF at x (in double, linear within a bucket), 0 below the
    /// range and 1 above it.
    double cdf(double x) const;

    double integral() const { return integral_; }
    double integral_tolerance() const { return integral_tol_; }
    double cdf_uncertainty() const { return cdf_delta_; }
    double bucket_width() const { return width_; }
    /// Float slack on x: 16 ulps of the range, the warp's own rounding.
    double x_slack() const { return x_slack_abs_; }

private:
    static std::vector<float> table_values(const std::vector<BucketSummary>& buckets, double width);
    double inverse_cdf(double v) const;
    double quadrature_error(const std::function<double(double)>& density) const;

    double lo_, hi_, width_, body_mass_;
    std::vector<BucketSummary> buckets_;
    PiecewiseConstant1D table_;
    std::vector<double> cdf_;  ///< the table's CDF at bucket edges, in double
    double integral_ = 0.0, integral_tol_ = 1e-5, cdf_delta_ = 0.0, x_slack_abs_ = 0.0;
};

}  // namespace warpcheck

#include "validate/checks/tabulated_reference.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace warpcheck {
namespace {

constexpr double kMargin = 1.25;             // extrema between the supersample points
constexpr double kFloatEps = 0x1p-24;        // float rounding of the table's CDF and of u
constexpr double kPdfRelativeSlack = 1e-5;  // float rounding of the densities compared

}  // namespace

std::vector<float> TabulatedReference::table_values(const std::vector<BucketSummary>& buckets, double width) {
    std::vector<float> values(buckets.size());
    double integral = 0.0;
    for (std::size_t i = 0; i < buckets.size(); ++i) {
        values[i] = static_cast<float>(buckets[i].mean);
        integral += buckets[i].mean * width;
    }
    if (!std::isfinite(integral))
        throw std::runtime_error("the density is not finite everywhere on the tabulated range");
    return values;
}

TabulatedReference::TabulatedReference(const std::function<double(double)>& density, double lo, double hi,
                                       double body_mass)
    : lo_(lo),
      hi_(hi),
      width_((hi - lo) / kBuckets),
      body_mass_(body_mass),
      buckets_(tabulate_buckets(density, lo, hi, kBuckets, kSupersamples)),
      table_(table_values(buckets_, width_), static_cast<float>(lo), static_cast<float>(hi)) {
    for (const BucketSummary& b : buckets_) {
        integral_ += b.mean * width_;
        integral_tol_ += (b.max - b.min) * width_ / kSupersamples;
    }
    x_slack_abs_ = 16.0 * kFloatEps * std::max(std::abs(lo_), std::abs(hi_));
    cdf_.assign(buckets_.size() + 1, 0.0);
    for (std::size_t i = 0; i < buckets_.size(); ++i) cdf_[i + 1] = cdf_[i] + buckets_[i].mean * width_;
    for (double& c : cdf_) c /= integral_;
    cdf_delta_ = 2.0 * kFloatEps + 4.0 * kFloatEps + quadrature_error(density) / integral_;
}

double TabulatedReference::quadrature_error(const std::function<double(double)>& density) const {
    double error = 0.0;
    double left = density(lo_);
    for (std::size_t i = 0; i < buckets_.size(); ++i) {
        const double right = density(lo_ + width_ * static_cast<double>(i + 1));
        error += std::abs(0.5 * (left + right) - buckets_[i].mean) * width_ / 256.0;
        left = right;
    }
    return error;
}

double TabulatedReference::table_pdf(double x) const {
    return static_cast<double>(table_.pdf(static_cast<float>(x))) * body_mass_;
}

double TabulatedReference::cdf(double x) const {
    if (!(x > lo_)) return 0.0;
    if (!(x < hi_)) return 1.0;
    const double t = (x - lo_) / width_;
    const auto o = std::min(static_cast<std::size_t>(t), buckets_.size() - 1);
    return cdf_[o] + (t - static_cast<double>(o)) * (cdf_[o + 1] - cdf_[o]);
}

double TabulatedReference::inverse_cdf(double v) const {
    v = std::clamp(v, 0.0, 1.0);
    const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), v);
    const std::size_t o = std::min<std::size_t>(
        static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - cdf_.begin() - 1, 0)), buckets_.size() - 1);
    const double w = cdf_[o + 1] - cdf_[o];
    const double t = w > 0.0 ? std::clamp((v - cdf_[o]) / w, 0.0, 1.0) : 0.0;
    return lo_ + (static_cast<double>(o) + t) * width_;
}

double TabulatedReference::x_tolerance(int bucket, double u_body) const {
    const BucketSummary& b = buckets_[static_cast<std::size_t>(bucket)];
    const double shape = b.min > 0.0 ? (b.max - b.min) * width_ / (2.0 * b.min) : width_;
    const double cdf_spread = inverse_cdf(u_body + cdf_delta_) - inverse_cdf(u_body - cdf_delta_);
    return kMargin * std::min(width_, shape) + x_slack_abs_ + cdf_spread;
}

TabulatedReference::Envelope TabulatedReference::envelope(double x) const {
    if (!(x >= lo_ - x_slack_abs_ && x <= hi_ + x_slack_abs_)) return {0.0, 0.0, 0.0};
    const double t = (x - lo_) / width_;
    const int o = std::clamp(static_cast<int>(t), 0, kBuckets - 1);
    const BucketSummary& b = buckets_[static_cast<std::size_t>(o)];
    Envelope e{b.min, b.max, b.mean / integral_ * body_mass_};
    for (int n : {o - 1, o + 1}) {
        if (n < 0 || n >= kBuckets) continue;
        const double edge = lo_ + (n < o ? o : o + 1) * width_;
        if (std::abs(x - edge) > x_slack_abs_) continue;
        e.lo = std::min(e.lo, buckets_[static_cast<std::size_t>(n)].min);
        e.hi = std::max(e.hi, buckets_[static_cast<std::size_t>(n)].max);
    }
    return e;
}

double TabulatedReference::pdf_tolerance(const Envelope& e, double reference) const {
    return kMargin * (e.hi - e.lo) / integral_ * body_mass_ / reference + integral_tol_ / body_mass_ +
           kPdfRelativeSlack;
}

}  // namespace warpcheck

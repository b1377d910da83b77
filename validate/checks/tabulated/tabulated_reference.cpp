#include "validate/checks/tabulated/tabulated_reference.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

namespace warpcheck {
namespace {

constexpr double kMargin = 1.25;             // extrema between the supersample points
constexpr double kFloatEps = 0x1p-24;        // one float step of u in [0.5, 1)
constexpr double kPdfRelativeSlack = 1e-5;  // float rounding of the densities compared

}  // namespace

TabulatedReference::TabulatedReference(const std::function<double(double)>& density, double lo, double hi,
                                       double body_mass)
    : lo_(lo), hi_(hi), width_((hi - lo) / kBuckets), body_mass_(body_mass) {
    // Count NaN values as they come (a NaN min or max would hide in std::min):
    // the check fails the warp for them instead of erroring.
    const auto counted = [&](double x) {
        const double v = density(x);
        ++evaluations_;
        if (std::isnan(v) && nan_values_++ == 0) first_nan_x_ = x;
        return v;
    };
    buckets_ = tabulate_buckets(counted, lo, hi, kBuckets, kSupersamples);
    if (nan_values_ > 0) return;  // no table: the check reports the NaN values
    for (const BucketSummary& b : buckets_) {
        if (!std::isfinite(b.mean))
            throw std::runtime_error(fmt::format(
                "the density is infinite on the tabulated range (near x = {:.9g}): a table cannot hold it",
                lo_ + width_ * static_cast<double>(&b - buckets_.data())));
        integral_ += b.mean * width_;
        integral_tol_ += (b.max - b.min) * width_ / kSupersamples;
    }
    x_slack_abs_ = float_slack(lo_, hi_);
    build_cdf();
    // 2^-23: the warp's own float arithmetic on u (two roundings of one float
    // step each); 2^-22: the float rounding of its density values.
    cdf_delta_ = 2.0 * kFloatEps + 4.0 * kFloatEps + quadrature_error(density) / integral_;
}

double TabulatedReference::float_slack(double lo, double hi) {
    return 16.0 * kFloatEps * std::max(std::abs(lo), std::abs(hi));
}

void TabulatedReference::build_cdf() {
    const std::size_t n = buckets_.size();
    cdf_.assign(n + 1, 0.0);
    for (std::size_t i = 0; i < n; ++i) cdf_[i + 1] = cdf_[i] + buckets_[i].mean * width_;
    if (integral_ > 0.0) {
        for (double& c : cdf_) c /= integral_;
    } else {  // no mass at all (the normalisation fails it): a uniform CDF keeps the arithmetic finite
        for (std::size_t i = 0; i <= n; ++i) cdf_[i] = static_cast<double>(i) / static_cast<double>(n);
    }
    cdf_[n] = 1.0;
    build_guide();
}

void TabulatedReference::build_guide() {
    guide_.clear();
    if (!std::is_sorted(cdf_.begin(), cdf_.end())) return;
    guide_.resize(kGuideCells + 1);
    std::size_t at = 0;  // one walk up the table: the first edge above each g / kGuideCells
    for (int g = 0; g <= kGuideCells; ++g) {
        const double v = static_cast<double>(g) / kGuideCells;  // exact: kGuideCells is a power of two
        while (at < cdf_.size() && !(cdf_[at] > v)) ++at;
        guide_[static_cast<std::size_t>(g)] = static_cast<uint32_t>(at);
    }
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
    if (!(x >= lo_ && x <= hi_) || !(integral_ > 0.0)) return 0.0;
    const auto o = std::min(static_cast<std::size_t>((x - lo_) / width_), buckets_.size() - 1);
    return buckets_[o].mean / integral_ * body_mass_;
}

double TabulatedReference::cdf(double x) const {
    if (!(x > lo_)) return 0.0;
    if (!(x < hi_)) return 1.0;
    const double t = (x - lo_) / width_;
    const auto o = std::min(static_cast<std::size_t>(t), buckets_.size() - 1);
    return cdf_[o] + (t - static_cast<double>(o)) * (cdf_[o + 1] - cdf_[o]);
}

TabulatedReference::Located TabulatedReference::locate(double v) const {
    v = std::clamp(v, 0.0, 1.0);
    // std::upper_bound over the whole table; with the guide, over the edges
    // between those above g / G and above (g + 1) / G, which hold the answer
    // (the table is sorted, and g / G <= v < (g + 1) / G; v = 1 is cell G).
    auto first = cdf_.begin(), last = cdf_.end();
    if (!guide_.empty() && !std::isnan(v)) {
        const auto g = static_cast<std::size_t>(v * kGuideCells);  // exact product: a power of two
        first = cdf_.begin() + guide_[g];
        if (g < static_cast<std::size_t>(kGuideCells)) last = cdf_.begin() + guide_[g + 1];
    }
    const auto it = std::upper_bound(first, last, v);
    const std::size_t o = std::min<std::size_t>(
        static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - cdf_.begin() - 1, 0)), buckets_.size() - 1);
    const double w = cdf_[o + 1] - cdf_[o];
    return {o, w > 0.0 ? std::clamp((v - cdf_[o]) / w, 0.0, 1.0) : 0.0};
}

double TabulatedReference::inverse_cdf(double v) const {
    const Located l = locate(v);
    return lo_ + (static_cast<double>(l.bucket) + l.t) * width_;
}

TabulatedReference::Sample TabulatedReference::sample(double u_body) const {
    const Located l = locate(u_body);
    return {lo_ + (static_cast<double>(l.bucket) + l.t) * width_, static_cast<int>(l.bucket)};
}

double TabulatedReference::x_tolerance(int bucket, double u_body) const {
    const BucketSummary& b = buckets_[static_cast<std::size_t>(bucket)];
    const double shape = b.min > 0.0 ? (b.max - b.min) * width_ / (2.0 * b.min) : width_;
    // Within delta of an end of [0, 1] the interval reaches that end of the
    // range: every x whose CDF is below delta is as good as any, even where the
    // density underflows to 0 in double and the table's mass begins later (a
    // cos^1000 lobe is 0 below z = 0.475, yet u = 0 rightly gives z = 0).
    const double below = u_body - cdf_delta_ <= 0.0 ? lo_ : inverse_cdf(u_body - cdf_delta_);
    const double above = u_body + cdf_delta_ >= 1.0 ? hi_ : inverse_cdf(u_body + cdf_delta_);
    const double cdf_spread = above - below;
    return kMargin * std::min(width_, shape) + x_slack_abs_ + cdf_spread;
}

void TabulatedReference::lookup(std::span<const double> u_body, std::span<const double> x,
                                std::span<Lookup> out) const {
    // The tables' lines for the inputs ahead of the current one are requested
    // (for the CDF, once the guide entry has arrived), so the loads of many
    // inputs overlap.
    constexpr std::size_t kGuideAhead = 16, kTableAhead = 8;
    const auto guide_cell = [](double v) {
        return static_cast<std::size_t>(std::clamp(v, 0.0, 1.0) * kGuideCells);  // v is not NaN
    };
    const auto prefetch_bucket = [this](double at) {
        const double t = (at - lo_) / width_;
        if (t >= 0.0 && t < kBuckets) __builtin_prefetch(&buckets_[static_cast<std::size_t>(t)]);
    };
    const std::size_t n = u_body.size();
    for (std::size_t i = 0; i < n; ++i) {
        if (const std::size_t a = i + kGuideAhead; a < n && !guide_.empty() && !std::isnan(u_body[a]))
            __builtin_prefetch(&guide_[guide_cell(u_body[a])]);
        if (const std::size_t a = i + kTableAhead; a < n) {
            prefetch_bucket(x[a]);
            if (!guide_.empty() && !std::isnan(u_body[a])) {
                const std::size_t at = guide_[guide_cell(u_body[a])];
                __builtin_prefetch(&cdf_[std::min(at, cdf_.size() - 1)]);
            }
        }
        out[i].envelope = envelope(x[i]);
        if (std::isnan(u_body[i])) continue;
        out[i].sample = sample(u_body[i]);
        out[i].x_tolerance = x_tolerance(out[i].sample.offset, u_body[i]);
    }
}

double TabulatedReference::tail_allowance(bool upper) const {
    const double spread = upper ? hi_ - inverse_cdf(1.0 - cdf_delta_) : inverse_cdf(cdf_delta_) - lo_;
    return spread + x_slack_abs_;
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

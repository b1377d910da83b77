// Tabulating a function into the buckets of a piecewise-constant distribution:
// each bucket gets the average of f over it, estimated by supersampling (the
// midpoint rule on s evenly spaced points, in double). Sampling a point value at
// the bucket centre instead would misplace mass wherever f curves.
#pragma once

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <vector>

namespace warpcheck {

/// What tabulate_buckets() records per bucket: the average of f (the table value),
/// and the smallest and largest f seen (at the supersample points and the two
/// bucket edges) - a measure of how much f varies across the bucket.
struct BucketSummary {
    double mean = 0.0;
    double min = 0.0;
    double max = 0.0;
};

/// Summaries of f: double -> double over the n equal buckets of [min, max], with
/// `supersamples` midpoint-rule points per bucket. f is also evaluated at the
/// n + 1 bucket edges (for min and max only), so it must be finite there.
template <typename F>
std::vector<BucketSummary> tabulate_buckets(F&& f, double min, double max, int n, int supersamples = 16) {
    if (n < 1 || supersamples < 1) throw std::invalid_argument("tabulate: needs n >= 1 and supersamples >= 1");
    if (!(min < max)) throw std::invalid_argument("tabulate: needs min < max");
    std::vector<BucketSummary> out(static_cast<std::size_t>(n));
    const double width = (max - min) / n;
    double left = f(min);
    for (int i = 0; i < n; ++i) {
        const double a = min + width * i;
        const double right = f(i + 1 == n ? max : min + width * (i + 1));
        double sum = 0.0, lo = std::min(left, right), hi = std::max(left, right);
        for (int s = 0; s < supersamples; ++s) {
            const double v = f(a + width * (s + 0.5) / supersamples);
            sum += v;
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
        out[static_cast<std::size_t>(i)] = {sum / supersamples, lo, hi};
        left = right;
    }
    return out;
}

/// The bucket averages of f over n equal buckets of [min, max], as the float
/// values a PiecewiseConstant1D takes.
template <typename F>
std::vector<float> tabulate(F&& f, double min, double max, int n, int supersamples = 16) {
    if (n < 1 || supersamples < 1) throw std::invalid_argument("tabulate: needs n >= 1 and supersamples >= 1");
    if (!(min < max)) throw std::invalid_argument("tabulate: needs min < max");
    std::vector<float> out(static_cast<std::size_t>(n));
    const double width = (max - min) / n;
    for (int i = 0; i < n; ++i) {
        double sum = 0.0;
        for (int s = 0; s < supersamples; ++s) sum += f(min + width * (i + (s + 0.5) / supersamples));
        out[static_cast<std::size_t>(i)] = static_cast<float>(sum / supersamples);
    }
    return out;
}

/// The cell averages of f(x, y) over an nu x nv grid of [x0, x1] x [y0, y1],
/// row-major (f[iy * nu + ix]) as PiecewiseConstant2D takes them, with
/// supersamples^2 points per cell.
template <typename F>
std::vector<float> tabulate_2d(F&& f, double x0, double x1, double y0, double y1, int nu, int nv,
                               int supersamples = 4) {
    if (nu < 1 || nv < 1 || supersamples < 1) throw std::invalid_argument("tabulate_2d: needs nu, nv, supersamples >= 1");
    if (!(x0 < x1) || !(y0 < y1)) throw std::invalid_argument("tabulate_2d: needs x0 < x1 and y0 < y1");
    std::vector<float> out(static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv));
    const double wx = (x1 - x0) / nu, wy = (y1 - y0) / nv;
    for (int iy = 0; iy < nv; ++iy)
        for (int ix = 0; ix < nu; ++ix) {
            double sum = 0.0;
            for (int sy = 0; sy < supersamples; ++sy)
                for (int sx = 0; sx < supersamples; ++sx)
                    sum += f(x0 + wx * (ix + (sx + 0.5) / supersamples), y0 + wy * (iy + (sy + 0.5) / supersamples));
            out[static_cast<std::size_t>(iy) * static_cast<std::size_t>(nu) + static_cast<std::size_t>(ix)] =
                static_cast<float>(sum / (supersamples * supersamples));
        }
    return out;
}

}  // namespace warpcheck

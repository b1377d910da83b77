// A renderer's piecewise-constant tables, in float, written the way pbrt-v4
// writes PiecewiseConstant1D / 2D: the CDF of the bucket weights, sampling by
// the largest CDF entry at or below u (so buckets of weight 0 are skipped),
// and the inverse. Plain math on floats, nothing of warpcheck.
#pragma once

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace hard {

class PiecewiseConstant1D {
public:
    explicit PiecewiseConstant1D(std::vector<float> weights) : func_(std::move(weights)), cdf_(func_.size() + 1, 0.0f) {
        const auto n = static_cast<float>(func_.size());
        for (std::size_t i = 0; i < func_.size(); ++i) cdf_[i + 1] = cdf_[i] + func_[i] / n;
        integral_ = cdf_.back();
        for (std::size_t i = 1; i < cdf_.size(); ++i)
            cdf_[i] = integral_ > 0 ? cdf_[i] / integral_ : static_cast<float>(i) / n;
    }

    struct Sample {
        float x;       ///< in [0, 1]
        float pdf;     ///< density of x on [0, 1]
        std::size_t bucket;
    };

    Sample sample(float u) const {
        // The largest o with cdf[o] <= u, at most n - 1.
        const auto above = std::upper_bound(cdf_.begin(), cdf_.end(), u);
        const std::size_t o = std::min<std::size_t>(static_cast<std::size_t>(above - cdf_.begin()) - 1, size() - 1);
        float du = u - cdf_[o];
        if (cdf_[o + 1] - cdf_[o] > 0) du /= cdf_[o + 1] - cdf_[o];
        return {(static_cast<float>(o) + du) / static_cast<float>(size()), density(o), o};
    }
    float pdf(float x) const { return density(bucket_of(x)); }
    float invert(float x) const {
        const std::size_t o = bucket_of(x);
        const float t = x * static_cast<float>(size()) - static_cast<float>(o);
        return (1 - t) * cdf_[o] + t * cdf_[o + 1];
    }

    std::size_t size() const { return func_.size(); }
    float integral() const { return integral_; }
    float weight(std::size_t i) const { return func_[i]; }

private:
    std::size_t bucket_of(float x) const {
        const auto o = static_cast<long>(x * static_cast<float>(size()));
        return static_cast<std::size_t>(std::clamp<long>(o, 0, static_cast<long>(size()) - 1));
    }
    float density(std::size_t o) const { return integral_ > 0 ? func_[o] / integral_ : 0; }

    std::vector<float> func_, cdf_;
    float integral_ = 0;
};

/// An image of nu x nv weights over [0,1]^2 (row-major, row v at y in
/// [v/nv, (v+1)/nv)): the row from the marginal of the rows' integrals, then
/// the column from that row's conditional, as an environment map is sampled.
class PiecewiseConstant2D {
public:
    /// `marginal_weights`: the rows' integrals as the sampler's marginal sees
    /// them (empty: the conditionals' own, which is correct).
    PiecewiseConstant2D(const std::vector<float>& image, std::size_t nu, std::vector<float> marginal_weights = {})
        : marginal_({1.0f}) {
        const std::size_t nv = image.size() / nu;
        for (std::size_t v = 0; v < nv; ++v)
            rows_.emplace_back(std::vector<float>(image.begin() + static_cast<long>(v * nu),
                                                  image.begin() + static_cast<long>((v + 1) * nu)));
        if (marginal_weights.empty())
            for (const auto& row : rows_) marginal_weights.push_back(row.integral());
        marginal_ = PiecewiseConstant1D(std::move(marginal_weights));
    }

    struct Point {
        float x, y;
    };
    Point sample(float ux, float uy) const {
        const PiecewiseConstant1D::Sample row = marginal_.sample(uy);
        return {rows_[row.bucket].sample(ux).x, row.x};
    }
    /// The density of the image itself: weight / (mean weight).
    float pdf(Point p) const {
        const std::size_t v = std::min(static_cast<std::size_t>(std::max(p.y, 0.0f) * static_cast<float>(rows_.size())),
                                       rows_.size() - 1);
        return rows_[v].pdf(p.x) * rows_[v].integral() / true_integral();
    }
    Point invert(Point p) const {
        const std::size_t v = std::min(static_cast<std::size_t>(std::max(p.y, 0.0f) * static_cast<float>(rows_.size())),
                                       rows_.size() - 1);
        return {rows_[v].invert(p.x), marginal_.invert(p.y)};
    }

private:
    float true_integral() const {
        float sum = 0;
        for (const auto& row : rows_) sum += row.integral();
        return sum / static_cast<float>(rows_.size());
    }
    std::vector<PiecewiseConstant1D> rows_;
    PiecewiseConstant1D marginal_;
};

/// The catalogue's 8 x 8 environment image (`environment_zero_rows`): rows 0-1
/// black ground, row 7 black, zero pixels inside the sky.
inline const std::vector<float>& environment_image() {
    static const std::vector<float> image{
        0, 0, 0,    0, 0, 0,    0, 0,    //
        0, 0, 0,    0, 0, 0,    0, 0,    //
        1, 2, 0,    3, 1, 0.5f, 2, 1,    //
        2, 2, 1,    0, 0, 1,    4, 0.5f, //
        1, 0, 0,    6, 2, 1,    1, 3,    //
        3, 1, 0.5f, 1, 1, 1,    1, 8,    //
        0, 4, 2,    2, 1, 0,    0, 1,    //
        0, 0, 0,    0, 0, 0,    0, 0};
    return image;
}

}  // namespace hard

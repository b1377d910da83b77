// Piecewise-constant distributions: tabulated densities in 1D (over [min, max])
// and 2D (over a box, as a marginal in y and one conditional in x per row), the
// way renderers sample environment maps, light power and tabulated BSDFs.
// Inputs u in [0,1) (1D) or [0,1)^2 (2D).
//
// Input values: NaN or infinite values throw std::invalid_argument; negative
// values carry no probability (they are clamped to 0: a density cannot be
// negative); a table whose values are all zero (after clamping) is sampled
// uniformly, with integral() = 0 so that the caller can tell. No input gives NaN.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "sampling/float_bits.h"
#include "sampling/vector.h"

namespace warpcheck {

/// A density proportional to f[i] on the i-th of n equal buckets of [min, max].
class PiecewiseConstant1D {
public:
    /// What sample() returns: the point, its density (with respect to length) and its bucket.
    struct Sample {
        float x = 0.0f;
        float pdf = 0.0f;
        int offset = 0;
    };

    PiecewiseConstant1D(std::span<const float> f, float min, float max) : min_(min), max_(max) {
        if (f.empty()) throw std::invalid_argument("piecewise_constant_1d: needs at least one value");
        if (!(min < max) || !std::isfinite(min) || !std::isfinite(max))
            throw std::invalid_argument("piecewise_constant_1d: needs finite min < max");
        func_.reserve(f.size());
        for (float v : f) {
            if (!std::isfinite(v))
                throw std::invalid_argument("piecewise_constant_1d: values must be finite, got " + std::to_string(v));
            func_.push_back(std::max(v, 0.0f));
        }
        // The CDF is accumulated in double: a float running sum over n buckets
        // loses up to n ulps, which for 2^16 buckets is a 2^-8 relative error.
        const std::size_t n = func_.size();
        const double width = (static_cast<double>(max) - min) / static_cast<double>(n);
        std::vector<double> running(n + 1, 0.0);
        for (std::size_t i = 0; i < n; ++i) running[i + 1] = running[i] + static_cast<double>(func_[i]) * width;
        integral_ = running[n];
        cdf_.resize(n + 1);
        for (std::size_t i = 0; i <= n; ++i)
            cdf_[i] = integral_ > 0.0 ? static_cast<float>(running[i] / integral_)
                                      : static_cast<float>(static_cast<double>(i) / static_cast<double>(n));
        cdf_[n] = 1.0f;
        inv_integral_ = integral_ > 0.0 ? static_cast<float>(1.0 / integral_) : 0.0f;
        uniform_pdf_ = static_cast<float>(1.0 / (static_cast<double>(max) - min));
    }

    std::size_t size() const { return func_.size(); }
    float min() const { return min_; }
    float max() const { return max_; }
    /// The integral of the (clamped) values over [min, max]; 0 for an all-zero table.
    float integral() const { return static_cast<float>(integral_); }
    std::span<const float> func() const { return func_; }
    /// cdf()[i] = probability of the buckets below i; cdf()[0] = 0, cdf()[size()] = 1.
    std::span<const float> cdf() const { return cdf_; }

    /// The bucket that contains x (x outside [min, max] is clamped to it). Monotone in x.
    int offset(float x) const {
        const float t = (x - min_) / (max_ - min_) * static_cast<float>(func_.size());
        return static_cast<int>(std::clamp(t, 0.0f, static_cast<float>(func_.size() - 1)));
    }

    /// Samples x with density pdf(x): the bucket o with cdf[o] <= u < cdf[o+1]
    /// (never a bucket of zero probability), then linearly within it. The point
    /// is nudged by an ulp where rounding would put it in a neighbouring bucket,
    /// so that pdf(x), invert(x) and the returned offset always agree.
    Sample sample(float u) const {
        u = std::clamp(u, 0.0f, kOneMinusEpsilon);
        const int n = static_cast<int>(func_.size());
        const int o = static_cast<int>(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin()) - 1;
        const float du = (u - cdf_[o]) / (cdf_[o + 1] - cdf_[o]);  // the width is > 0 by the choice of o
        float x = min_ + (static_cast<float>(o) + du) / static_cast<float>(n) * (max_ - min_);
        x = std::clamp(x, min_, max_);
        while (offset(x) < o) x = next_float_up(x);
        while (offset(x) > o) x = next_float_down(x);
        return {x, bucket_pdf(o), o};
    }

    /// Density with respect to length: f[o] / integral on bucket o, 0 outside [min, max]
    /// (an all-zero table: 1 / (max - min)).
    float pdf(float x) const {
        if (!(x >= min_ && x <= max_)) return 0.0f;
        return bucket_pdf(offset(x));
    }

    /// The u that sample() maps to x: the CDF at x, linear within the bucket.
    /// x outside [min, max] is clamped.
    float invert(float x) const {
        x = std::clamp(x, min_, max_);
        const int o = offset(x);
        const float t = (x - min_) / (max_ - min_) * static_cast<float>(func_.size());
        const float du = std::clamp(t - static_cast<float>(o), 0.0f, 1.0f);
        return std::clamp(cdf_[o] + du * (cdf_[o + 1] - cdf_[o]), 0.0f, kOneMinusEpsilon);
    }

private:
    float bucket_pdf(int o) const {
        return integral_ > 0.0 ? func_[static_cast<std::size_t>(o)] * inv_integral_ : uniform_pdf_;
    }

    float min_, max_;
    std::vector<float> func_;
    std::vector<float> cdf_;
    double integral_ = 0.0;
    float inv_integral_ = 0.0f;
    float uniform_pdf_ = 0.0f;
};

/// A density proportional to f on the cells of an nu x nv grid over
/// [x0, x1] x [y0, y1]; f is row-major, f[iy * nu + ix]. Sampling takes the row
/// from the marginal density of y (each row's integral), then x from that row's
/// conditional density: u.y drives y and u.x drives x.
class PiecewiseConstant2D {
public:
    struct Sample {
        Point2f p;
        float pdf = 0.0f;   ///< density with respect to area
        int offset_x = 0;   ///< column
        int offset_y = 0;   ///< row
    };

    PiecewiseConstant2D(std::span<const float> f, int nu, int nv, float x0, float x1, float y0, float y1)
        : marginal_(row_integrals(f, nu, nv, x0, x1, conditionals_), y0, y1) {}

    int nu() const { return static_cast<int>(conditionals_.front().size()); }
    int nv() const { return static_cast<int>(conditionals_.size()); }
    /// The integral of the (clamped) values over the box; 0 for an all-zero table.
    float integral() const { return marginal_.integral(); }
    const PiecewiseConstant1D& marginal() const { return marginal_; }
    const PiecewiseConstant1D& conditional(int row) const { return conditionals_[static_cast<std::size_t>(row)]; }

    Sample sample(Point2f u) const {
        const PiecewiseConstant1D::Sample y = marginal_.sample(u.y);
        const PiecewiseConstant1D::Sample x = conditionals_[static_cast<std::size_t>(y.offset)].sample(u.x);
        return {{x.x, y.x}, x.pdf * y.pdf, x.offset, y.offset};
    }

    /// Density with respect to area: the marginal density of the row times the
    /// conditional density within it (this equals f / integral, and stays
    /// consistent with sample() for all-zero rows and tables). 0 outside the box.
    float pdf(Point2f p) const {
        const float py = marginal_.pdf(p.y);
        if (py == 0.0f) return 0.0f;
        return py * conditionals_[static_cast<std::size_t>(marginal_.offset(p.y))].pdf(p.x);
    }

    /// The u that sample() maps to p (p outside the box is clamped to it).
    Point2f invert(Point2f p) const {
        const int row = marginal_.offset(p.y);
        return {conditionals_[static_cast<std::size_t>(row)].invert(p.x), marginal_.invert(p.y)};
    }

private:
    // Builds the conditionals (one per row) and returns the rows' integrals, the
    // marginal's values. Runs before marginal_ is constructed.
    static std::vector<float> row_integrals(std::span<const float> f, int nu, int nv, float x0, float x1,
                                            std::vector<PiecewiseConstant1D>& conditionals) {
        if (nu < 1 || nv < 1) throw std::invalid_argument("piecewise_constant_2d: needs nu, nv >= 1");
        if (f.size() != static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv))
            throw std::invalid_argument("piecewise_constant_2d: needs nu * nv values, got " + std::to_string(f.size()));
        std::vector<float> rows;
        rows.reserve(static_cast<std::size_t>(nv));
        for (int v = 0; v < nv; ++v) {
            conditionals.emplace_back(f.subspan(static_cast<std::size_t>(v) * static_cast<std::size_t>(nu),
                                                static_cast<std::size_t>(nu)),
                                      x0, x1);
            rows.push_back(conditionals.back().integral());
        }
        return rows;
    }

    std::vector<PiecewiseConstant1D> conditionals_;  // declared first: built before marginal_
    PiecewiseConstant1D marginal_;
};

}  // namespace warpcheck

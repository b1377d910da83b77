// Warps whose density is zero on part of their domain, written as renderers
// write them (in float, no nudging at bucket edges): a triangle light and
// pbrt-style piecewise-constant tables with empty buckets and rows. Each has
// a `wrong` switch for its twin of the same hardness.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include "validate/checks/check.h"
#include "validate/api/registry.h"
#include "validate/run/runner.h"
#include "validate/api/warp_case.h"

namespace warpcheck::testing {

/// A triangle (counter-clockwise vertices) sampled uniformly by the square-root
/// map, with the pdf's inside test by float edge functions.
struct FloatTriangle {
    Point2f a{0.1f, 0.1f}, b{0.9f, 0.2f}, c{0.3f, 0.8f};
    /// The twin: r = u.x instead of sqrt(u.x), crowding the samples towards a.
    bool wrong_radius = false;

    static float edge(Point2f o, Point2f p, Point2f q) { return (p.x - o.x) * (q.y - o.y) - (p.y - o.y) * (q.x - o.x); }
    float area() const { return 0.5f * edge(a, b, c); }
    Point2f sample(Point2f u) const {
        const float r = wrong_radius ? u.x : std::sqrt(u.x), wa = 1 - r, wb = r * (1 - u.y), wc = r * u.y;
        return {wa * a.x + wb * b.x + wc * c.x, wa * a.y + wb * b.y + wc * c.y};
    }
    float pdf(Point2f p) const {
        return edge(a, b, p) >= 0 && edge(b, c, p) >= 0 && edge(c, a, p) >= 0 ? 1 / area() : 0;
    }
    /// Barycentric coordinates, then u = (r^2, lc / r), clamped below 1.
    Point2f invert(Point2f p) const {
        const float k = edge(a, b, c), lb = edge(c, a, p) / k, lc = edge(a, b, p) / k, r = lb + lc;
        constexpr float kBelowOne = 0x1.fffffep-1f;
        return {std::clamp(r * r, 0.0f, kBelowOne), r > 0 ? std::clamp(lc / r, 0.0f, kBelowOne) : 0.0f};
    }
};

/// pbrt-v4's PiecewiseConstant1D on [0, 1]: the bucket o with cdf[o] <= u <
/// cdf[o+1], then x = (o + du) / n, which rounds onto the next bucket's edge
/// when du is within half an ulp of 1 (the next bucket may be empty).
struct PbrtTable1D {
    std::vector<float> func, cdf;
    float integral = 0;

    explicit PbrtTable1D(std::vector<float> f) : func(std::move(f)), cdf(func.size() + 1, 0.0f) {
        const auto n = static_cast<float>(func.size());
        for (std::size_t i = 0; i < func.size(); ++i) cdf[i + 1] = cdf[i] + func[i] / n;
        integral = cdf.back();
        for (float& c : cdf) c /= integral;
        cdf.back() = 1;
    }
    /// x in [0, 1], its bucket, and the bucket's density (returned by reference).
    float sample(float u, float& pdf, std::size_t& bucket) const {
        const auto o = static_cast<std::size_t>(std::upper_bound(cdf.begin(), cdf.end() - 1, u) - cdf.begin()) - 1;
        float du = u - cdf[o];
        if (cdf[o + 1] - cdf[o] > 0) du /= cdf[o + 1] - cdf[o];
        bucket = o;
        pdf = func[o] / integral;
        return (static_cast<float>(o) + du) / static_cast<float>(func.size());
    }
    std::size_t offset(float x) const {
        return std::min(static_cast<std::size_t>(std::max(0.0f, x * static_cast<float>(func.size()))),
                        func.size() - 1);
    }
};

/// pbrt-v4's PiecewiseConstant2D on [0, 1]^2 (f row-major, f[iv * nu + iu]): y
/// from the rows' marginal, then x from the row. `edge_clamp` (the twin) sends
/// every u.y in the top 1% of a row's share onto the row's upper edge.
struct PbrtTable2D {
    std::size_t nu, nv;
    std::vector<float> f;
    std::vector<PbrtTable1D> rows;
    std::unique_ptr<PbrtTable1D> marginal;
    bool edge_clamp = false;

    PbrtTable2D(std::vector<float> values, std::size_t nu_, std::size_t nv_) : nu(nu_), nv(nv_), f(std::move(values)) {
        std::vector<float> row_integrals;
        for (std::size_t v = 0; v < nv; ++v) {
            std::vector<float> row(f.begin() + static_cast<std::ptrdiff_t>(v * nu),
                                   f.begin() + static_cast<std::ptrdiff_t>((v + 1) * nu));
            const float sum = std::accumulate(row.begin(), row.end(), 0.0f);
            if (sum == 0) std::fill(row.begin(), row.end(), 1.0f);  // pbrt samples an empty row uniformly
            row_integrals.push_back(sum / static_cast<float>(nu));
            rows.emplace_back(std::move(row));
        }
        marginal = std::make_unique<PbrtTable1D>(row_integrals);
    }
    PdfSample<Point2f> sample(Point2f u) const {
        float pdf_y = 0, pdf_x = 0;
        std::size_t v = 0, iu = 0;
        float y = marginal->sample(u.y, pdf_y, v);
        if (edge_clamp) {
            const float share = marginal->cdf[v + 1] - marginal->cdf[v];
            if (u.y - marginal->cdf[v] > 0.99f * share) y = static_cast<float>(v + 1) / static_cast<float>(nv);
        }
        const float x = rows[v].sample(u.x, pdf_x, iu);
        return {{x, y}, pdf_x * pdf_y};
    }
    float pdf(Point2f p) const {
        const std::size_t v = marginal->offset(p.y), u = rows[v].offset(p.x);
        return f[v * nu + u] / marginal->integral;
    }
    /// The area of the cells of positive density.
    double support_area() const {
        return static_cast<double>(std::count_if(f.begin(), f.end(), [](float w) { return w > 0; })) /
               static_cast<double>(nu * nv);
    }
};

/// nv rows of nu cells over [0, 1]^2: every odd row empty, and in the full rows
/// every fourth cell empty (an environment map with dark bands and spots).
inline std::vector<float> striped_table(std::size_t nu, std::size_t nv) {
    std::vector<float> f(nu * nv, 0.0f);
    for (std::size_t v = 0; v < nv; v += 2)
        for (std::size_t u = 0; u < nu; ++u)
            f[v * nu + u] = u % 4 == 3 ? 0.0f : 1.0f + static_cast<float>((u * 7 + v) % 5);
    return f;
}

/// Every default check that applies to the case, as `validate` runs them.
inline RunResult run_default_suite(std::unique_ptr<WarpCase> warp, uint64_t seed, uint64_t samples,
                                   bool strict = false) {
    Registry registry;
    register_builtin_checks(registry);
    registry.add_case(std::move(warp));
    RunOptions options;
    options.threads = 2;
    options.seed = seed;
    options.samples = samples;
    options.strict = strict;
    options.check_time_budget = 600.0;
    return run_jobs(select_jobs(registry, {}, {}, options), options);
}

}  // namespace warpcheck::testing

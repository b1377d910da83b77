// Class 3 of issue 22: supports smaller than the domain (with the triangles'
// class 4 and class 6 parts, since they are the same warps).
//
// Triangles inside the unit square, pdf 1/area inside and 0 outside:
// - triangle_right: x, y >= 0, x + y <= 1, by the square-root map (pbrt-v3's
//   UniformSampleTriangle). Correct: the map's Jacobian is constant. Hard
//   (class 4): the density jumps along x + y = 1, which passes through the
//   corners of the chi-square cells, where symmetric quadrature nodes sit on
//   the jump (its stated bound understated the error 500x).
// - triangle: a triangle light (0.1,0.15), (0.85,0.3), (0.35,0.9) as a
//   renderer samples it (barycentrics by the square-root map) and tests
//   points (edge functions in float). Hard (class 3): points sampled on an
//   edge round to either side of it, and the float inside test then gives 0
//   at a sampled point. Hard (class 6): its inverse (barycentrics, then
//   u = ((1 - b0)^2, b1 / (1 - b0))) is exact in real arithmetic, but near
//   vertex p0 the point's absolute rounding (6e-8) is divided by 1 - b0, so
//   about 17 in 10^6 round trips are off by more than 2^-16.
// - triangle_low_distortion: pbrt-v4's SampleUniformTriangle (Heitz 2019)
//   on the right triangle, with pbrt-v4's exact inverse.
// Twins: the triangle sampled without the square root; its inverse 1e-3 off.
//
// A table sampler with buckets of weight 0 whose sample returns its pdf and
// which has no pdf function: E[1/pdf] is the support's length (0.5), not the
// domain's (1). Twin: the returned pdf's total forgets one bucket's weight.
//
// An environment-map-like 2D piecewise-constant sampler over [0,1]^2 with
// zero rows (a sky above black ground) and zero pixels. Twin: the marginal's
// row sums skip the last column (an off-by-one), so rows are chosen wrongly.
#include <string>
#include <vector>

#include "hard_warps.h"
#include "environment_map.h"
#include "piecewise.h"

namespace hard {
namespace {

using warpcheck::chi2::Domain;
using warpcheck::InputKind;

struct RightTriangle {
    Point2f sample(Point2f u) const {
        const float s = std::sqrt(u.x);
        return {s * (1 - u.y), s * u.y};
    }
    float pdf(Point2f p) const { return p.x >= 0 && p.y >= 0 && p.x + p.y <= 1 ? 2 : 0; }
    Point2f invert(Point2f p) const {
        const float s = p.x + p.y;
        return {s * s, s > 0 ? p.y / s : 0};
    }
};

struct RightTriangleLowDistortion {
    Point2f sample(Point2f u) const {
        if (u.x < u.y) {
            const float b0 = u.x / 2;
            return {b0, u.y - b0};
        }
        const float b1 = u.y / 2;
        return {u.x - b1, b1};
    }
    float pdf(Point2f p) const { return p.x >= 0 && p.y >= 0 && p.x + p.y <= 1 ? 2 : 0; }
    Point2f invert(Point2f p) const {
        if (p.x > p.y) return {p.x + p.y, 2 * p.y};
        return {2 * p.x, p.y + p.x};
    }
};

float edge(Point2f a, Point2f b, Point2f p) { return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x); }

struct TriangleLight {
    Point2f p0{0.1f, 0.15f}, p1{0.85f, 0.3f}, p2{0.35f, 0.9f};
    bool no_sqrt = false;        // twin (class 3)
    float inverse_error = 0;     // twin (class 6): u.x scaled by 1 + this

    float twice_area() const { return edge(p0, p1, p2); }
    Point2f sample(Point2f u) const {
        const float s = no_sqrt ? u.x : std::sqrt(u.x);
        const float b0 = 1 - s, b1 = u.y * s, b2 = 1 - b0 - b1;
        return {b0 * p0.x + b1 * p1.x + b2 * p2.x, b0 * p0.y + b1 * p1.y + b2 * p2.y};
    }
    float pdf(Point2f p) const {
        const bool inside = edge(p1, p2, p) >= 0 && edge(p2, p0, p) >= 0 && edge(p0, p1, p) >= 0;
        return inside ? 2 / twice_area() : 0;
    }
    Point2f invert(Point2f p) const {
        const float b0 = edge(p1, p2, p) / twice_area(), b1 = edge(p2, p0, p) / twice_area();
        const float s = 1 - b0;
        // Clamped into [0,1) as pbrt-v4's inverses clamp: the contract of
        // invert is a valid input, and near a vertex b1 / s divides the edge
        // function's rounding (~1e-8) by s (2.4e-4 at u.x = 2^-24), so it
        // reaches 1.00017 for u.y one float below 1.
        return {clamp_unit(s * s * (1 + inverse_error)), clamp_unit(s > 0 ? b1 / s : 0)};
    }
};

template <typename Warp>
void add_triangle(warpcheck::Registry& registry, const std::string& family, const std::string& description, Warp warp) {
    registry.add_case(warpcheck::make_warp_case(
        {.family = family, .description = description, .domain = Domain::unit_square()}, warp));
}

void register_triangles(warpcheck::Registry& registry) {
    add_triangle(registry, "triangle_right", "uniform on x + y <= 1 in the unit square, square-root map",
                 RightTriangle{});
    add_triangle(registry, "triangle_low_distortion", "uniform on x + y <= 1, pbrt-v4's map and exact inverse",
                 RightTriangleLowDistortion{});
    add_triangle(registry, "triangle", "a triangle light inside the unit square, float edge-function pdf",
                 TriangleLight{});
    TriangleLight no_sqrt;
    no_sqrt.no_sqrt = true;
    add_triangle(registry, "triangle_no_sqrt", "the triangle light sampled without the square root", no_sqrt);
    mark_twin(registry, "triangle_no_sqrt", "chi2,unbinned", "density 1/(1 - b0) instead of uniform");
    TriangleLight bad_inverse;
    bad_inverse.inverse_error = 1e-3f;
    add_triangle(registry, "triangle_inverse_1e-3", "the triangle light with u.x of its inverse 1e-3 too large",
                 bad_inverse);
    mark_twin(registry, "triangle_inverse_1e-3", "roundtrip", "the inverse's u.x is scaled by 1 + 1e-3");
}

// A table sampler that returns its pdf, with no pdf function.
struct TableReturningPdf {
    PiecewiseConstant1D table;
    float forgotten_weight = 0;  // twin: the returned pdf's total lacks this
    warpcheck::PdfSample<float> sample(float u) const {
        const PiecewiseConstant1D::Sample s = table.sample(u);
        const float n = static_cast<float>(table.size());
        const float total = table.integral() * n - forgotten_weight;
        return {s.x, table.weight(s.bucket) * n / total};
    }
};

void register_table(warpcheck::Registry& registry) {
    const std::vector<float> weights{1, 0, 3, 0, 0, 2, 0.5f, 0};
    for (bool twin : {false, true}) {
        registry.add_case(warpcheck::make_warp_case(
            {.family = twin ? "table_zero_buckets_pdf_forgets_weight" : "table_zero_buckets",
             .description = "piecewise-constant table with buckets of weight 0; pdf only from sample",
             .domain = Domain::interval(0, 1),
             // Declared, as a renderer knows its table's empty buckets: 4 of
             // the 8 buckets, 0.5. Undeclared, inverse_pdf_mean can only test
             // E[1/pdf] <= 1 (the domain's length), which the twin's 0.46 meets.
             .support_measure = 0.5},
            warpcheck::warp_of([table = TableReturningPdf{PiecewiseConstant1D(weights), twin ? 0.5f : 0.0f}](float u) {
                                   return table.sample(u);
                               })));
    }
    mark_twin(registry, "table_zero_buckets_pdf_forgets_weight", "inverse_pdf_mean",
              "the returned pdf divides by a total without the bucket of weight 0.5");
}

void register_environment(warpcheck::Registry& registry) {
    registry.add_case(warpcheck::make_warp_case(
        {.family = "environment_zero_rows",
         .description = "8x8 piecewise-constant image with zero rows and pixels, row then column",
         .domain = Domain::unit_square()},
        EnvironmentMap{PiecewiseConstant2D(environment_image(), 8)}));
    std::vector<float> short_sums;  // each row's integral without its last column (the twin's off-by-one)
    for (std::size_t v = 0; v < 8; ++v) {
        float sum = 0;
        for (std::size_t x = 0; x + 1 < 8; ++x) sum += environment_image()[v * 8 + x];
        short_sums.push_back(sum / 8);
    }
    registry.add_case(warpcheck::make_warp_case(
        {.family = "environment_zero_rows_marginal_off_by_one",
         .description = "the environment map whose marginal skips each row's last column",
         .domain = Domain::unit_square()},
        EnvironmentMap{PiecewiseConstant2D(environment_image(), 8, short_sums)}));
    mark_twin(registry, "environment_zero_rows_marginal_off_by_one", "chi2,unbinned",
              "rows chosen by sums without their last column (row 5 loses half its weight)");
}

}  // namespace

void register_supports(warpcheck::Registry& registry) {
    register_triangles(registry);
    register_table(registry);
    register_environment(registry);
}

}  // namespace hard

// Piecewise-constant warps: tabulated densities as a renderer builds them for
// light selection (1D) and environment maps (2D), including steps, empty
// buckets and rows, negative input values (no mass) and all-zero tables (uniform).
#include <cmath>
#include <memory>
#include <vector>

#include "sampling/piecewise_constant.h"
#include "sampling/tabulate.h"
#include "validate/api/registry.h"

namespace warpcheck {
namespace {

void add_1d(Registry& registry, const std::string& family, const std::string& what, std::vector<float> f, float lo,
            float hi) {
    const auto d = std::make_shared<const PiecewiseConstant1D>(f, lo, hi);
    registry.add_case(make_warp_case(
        {.family = family,
         .params = {{"n", static_cast<double>(f.size())}},
         .description = what,
         .domain = chi2::Domain::interval(lo, hi)},
        warp_of([d](float u) { return d->sample(u).x; })
            .with_pdf([d](float x) { return d->pdf(x); })
            .with_invert([d](float x) { return d->invert(x); })));
}

void add_2d(Registry& registry, const std::string& family, const std::string& what, std::vector<float> f, int nu,
            int nv, float x0, float x1, float y0, float y1) {
    const auto d = std::make_shared<const PiecewiseConstant2D>(f, nu, nv, x0, x1, y0, y1);
    // y comes from the marginal alone, driven by u.y alone: a monotone 1D view.
    MonotoneMarginal m;
    m.input_coordinate = 1;
    m.lo = y0;
    m.hi = y1;
    m.label = "y";
    m.coordinate = [](const WarpOutput& o) { return static_cast<double>(o[1]); };
    m.pdf = [d](double y) { return static_cast<double>(d->marginal().pdf(static_cast<float>(y))); };
    WarpCaseInfo info{.family = family,
                      .params = {{"nu", static_cast<double>(nu)}, {"nv", static_cast<double>(nv)}},
                      .description = what,
                      .domain = chi2::Domain::box(x0, x1, y0, y1),
                      .views = {std::move(m)}};
    registry.add_case(make_warp_case(info,
        warp_of([d](Point2f u) { return d->sample(u).p; })
            .with_pdf([d](Point2f p) { return d->pdf(p); })
            .with_invert([d](Point2f p) { return d->invert(p); })));
}

void register_piecewise_constant_cases(Registry& registry) {
    add_1d(registry, "piecewise_constant_1d",
           "8 steps on [0, 1] with empty buckets and a negative value (no mass); pdf f / integral",
           {1.0f, 0.0f, 3.0f, 0.5f, -2.0f, 4.0f, 0.25f, 2.0f}, 0.0f, 1.0f);
    add_1d(registry, "piecewise_constant_1d",
           "64 buckets tabulated from 0.1 + sin^2(3x) exp(-x) on [-1, 2]; pdf f / integral",
           tabulate([](double x) { return 0.1 + std::pow(std::sin(3.0 * x), 2) * std::exp(-x); }, -1.0, 2.0, 64),
           -1.0f, 2.0f);
    add_1d(registry, "piecewise_constant_1d_all_zero", "all-zero table on [0, 2]: uniform, pdf 1/2",
           std::vector<float>(4, 0.0f), 0.0f, 2.0f);
    add_2d(registry, "piecewise_constant_2d",
           "8 x 6 steps on [0, 2] x [-1, 1] with an empty row and empty cells; pdf f / integral",
           {1, 2, 0, 4, 1, 1, 3, 0,  //
            0, 0, 0, 0, 0, 0, 0, 0,  //
            5, 1, 1, 0, 2, 2, 1, 1,  //
            1, 1, 1, 1, 1, 1, 1, 1,  //
            0, 3, 0, 3, 0, 3, 0, 3,  //
            2, 0.5f, 8, 1, 1, 1, 0.25f, 1},
           8, 6, 0.0f, 2.0f, -1.0f, 1.0f);
    const double pi = 3.14159265358979323846;
    add_2d(registry, "piecewise_constant_2d",
           "32 x 16 environment-map-like table on [0, 2 pi] x [0, pi] (a sun and a sky gradient); pdf f / integral",
           tabulate_2d(
               [](double phi, double theta) {
                   const double sun = std::exp(-40.0 * (std::pow(phi - 2.0, 2) + std::pow(theta - 0.8, 2)));
                   return (0.2 + std::cos(theta / 2.0) + 50.0 * sun) * std::sin(theta);
               },
               0.0, 2.0 * pi, 0.0, pi, 32, 16),
           32, 16, 0.0f, static_cast<float>(2.0 * pi), 0.0f, static_cast<float>(pi));
    add_2d(registry, "piecewise_constant_2d_all_zero", "all-zero 3 x 2 table on [0, 1]^2: uniform, pdf 1",
           std::vector<float>(6, 0.0f), 3, 2, 0.0f, 1.0f, 0.0f, 1.0f);
}

WARPCHECK_BUILTIN_CASES(60, register_piecewise_constant_cases);

}  // namespace

}  // namespace warpcheck

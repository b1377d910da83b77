// Exponential warps: the exponential on [0, inf) at three rates, and the trimmed
// exponential on [0, xmax] from a nearly uniform rate to one where the trimming
// is invisible in float.
#include <cmath>

#include "sampling/exponential.h"
#include "validate/api/registry.h"

namespace warpcheck {
namespace {

void register_exponential_cases(Registry& registry) {
    using chi2::Domain;
    for (double a : {0.1, 1.0, 10.0}) {
        const Exponential e(static_cast<float>(a));
        WarpCaseInfo info{.family = "exponential",
                          .params = {{"a", a}},
                          .description = "exponential with rate a on [0, inf): pdf a exp(-a x), x = -log1p(-u) / a",
                          .domain = Domain::half_line(0.0)};
        // The tabulated check truncates the half-line where the tail holds 1e-3 of
        // the mass (so that ~1000 of 1e6 samples test the tail explicitly); the tail
        // mass comes from the CDF, exp(-a hi), with the rate as the warp holds it.
        MonotoneMarginal view;
        view.hi = static_cast<double>(static_cast<float>(std::log(1000.0) / a));
        view.tail_mass = std::exp(-static_cast<double>(e.rate()) * view.hi);
        view.label = "x";
        info.views = {view};
        registry.add_case(make_warp_case(info, e));
    }
    // c = 1e-6: c xmax is tiny, the density is uniform to 1e-6 and the naive
    // normalisation 1 - exp(-c xmax) keeps only ~1 significant digit in float.
    // c = 100: exp(-c xmax) is below float precision; all mass within ~0.1.
    for (auto [c, x_max] : {std::pair{1e-6, 1.0}, {1.0, 1.0}, {0.5, 4.0}, {100.0, 1.0}}) {
        const TrimmedExponential t(static_cast<float>(c), static_cast<float>(x_max));
        WarpCaseInfo info{
            .family = "trimmed_exponential",
            .params = {{"c", c}, {"x_max", x_max}},
            .description = "exponential with rate c trimmed to [0, x_max]: pdf c exp(-c x) / (1 - exp(-c x_max))",
            .domain = Domain::interval(0.0, x_max)};
        // Uniform chi-square cells over [0, x_max] put c = 100's mass (scale 0.01)
        // into a handful of cells; 20 cells per 1/c keep ~150 cells with counts.
        if (c * x_max > 10.0) info.chi2_resolution.first = static_cast<int>(20.0 * c * x_max);
        registry.add_case(make_warp_case(info, t));
    }
}

WARPCHECK_BUILTIN_CASES(40, register_exponential_cases);

}  // namespace

}  // namespace warpcheck

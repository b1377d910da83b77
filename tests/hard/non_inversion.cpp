// Class 5 of issue 22: 1D samplers that are not the inversion method.
//
// Correct samplers of a 1D density on [0,1] whose x is not monotone in u, so
// a comparison with the inversion method (the tabulated check) is not a test
// of them:
// - alias_1d: a piecewise-constant density (eight buckets, one of weight 0)
//   through Vose's alias table: u picks a bucket and is remapped within it
//   (pbrt-v4's AliasTable), then x = (bucket + remapped u) / 8.
// - mixture_1d: two components chosen by u (0.3: density 2x; 0.7: 3 (1-x)^2),
//   u rescaled for the chosen one, as a BSDF picks a lobe.
// Twins: the alias table built from one weight 20% too large; the mixture's
// pdf with the weight 0.35 instead of the 0.3 it samples with.
#include <numeric>
#include <string>
#include <vector>

#include "alias_table.h"
#include "hard_warps.h"

namespace hard {
namespace {

using warpcheck::chi2::Domain;
using warpcheck::InputKind;

struct Alias1D {
    std::vector<float> weights;  // the pdf's
    AliasTable table;            // the sampler's (the twin's differs)
    float sample(float u) const {
        const auto [bucket, v] = table.sample(u);
        return (static_cast<float>(bucket) + v) / static_cast<float>(weights.size());
    }
    float pdf(float x) const {
        if (x < 0 || x > 1) return 0;
        const auto n = static_cast<float>(weights.size());
        const std::size_t i = std::min(static_cast<std::size_t>(x * n), weights.size() - 1);
        return weights[i] * n / std::accumulate(weights.begin(), weights.end(), 0.0f);
    }
};

struct Mixture1D {
    float select = 0.3f, pdf_select = 0.3f;  // the twin's pdf_select differs
    float sample(float u) const {
        if (u < select) return std::sqrt(u / select);                            // density 2x
        return 1 - std::cbrt(1 - (u - select) / (1 - select));                  // density 3 (1 - x)^2
    }
    float pdf(float x) const {
        if (x < 0 || x > 1) return 0;
        return pdf_select * 2 * x + (1 - pdf_select) * 3 * (1 - x) * (1 - x);
    }
};

}  // namespace

void register_non_inversion(warpcheck::Registry& registry) {
    const std::vector<float> weights{2, 0.5f, 1, 0, 3, 1.5f, 0.25f, 4};
    std::vector<float> skewed = weights;
    skewed[4] *= 1.2f;
    for (bool twin : {false, true})
        registry.add_case(warpcheck::make_warp_case(
            {.family = twin ? "alias_1d_weight_20pc_off" : "alias_1d",
             .description = "piecewise-constant density on [0,1] through an alias table (not monotone in u)",
             .domain = Domain::interval(0, 1)},
            Alias1D{weights, AliasTable(twin ? skewed : weights)}));
    mark_twin(registry, "alias_1d_weight_20pc_off", "chi2,unbinned", "the table's bucket 4 weighs 3.6, the pdf's 3");

    for (bool twin : {false, true})
        registry.add_case(warpcheck::make_warp_case(
            {.family = twin ? "mixture_1d_wrong_weight" : "mixture_1d",
             .params = {{"select", 0.3}},
             .description = "0.3 of density 2x, 0.7 of 3 (1-x)^2, the component chosen by u",
             .domain = Domain::interval(0, 1)},
            Mixture1D{0.3f, twin ? 0.35f : 0.3f}));
    mark_twin(registry, "mixture_1d_wrong_weight[select=0.3]", "chi2,unbinned", "the pdf weighs the components 0.35");
}

}  // namespace hard

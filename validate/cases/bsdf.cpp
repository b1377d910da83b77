// Built-in BSDFs and a phase function (sampling/bsdf_*.h), each over a grid of
// outgoing directions from normal incidence to grazing (80 and 89 degrees)
// and, for transmission, from below the surface.
#include <utility>

#include "sampling/bsdf_conductor.h"
#include "sampling/bsdf_diffuse.h"
#include "validate/bsdf/bsdf_grid.h"
#include "validate/registry.h"

namespace warpcheck {
namespace {

/// Gold at about 600 nm: eta + i k relative to air.
constexpr float kGoldEta = 0.2f, kGoldK = 3.0f;

void register_lambertian(Registry& registry) {
    add_case_grid(registry,
                  {.family = "lambertian", .description = "Lambertian reflection, f = R / pi, cosine-weighted sampling"},
                  {{"R", {0.5}}, {"theta_o", {0, 60, 89}}}, [](WarpCaseInfo info, const GridPoint& p) {
                      return make_bsdf_case(std::move(info), {.wo = grid_wo(p)},
                                            Lambertian(static_cast<float>(p["R"])));
                  });
}

void register_rough_conductor(Registry& registry) {
    add_case_grid(registry,
                  {.family = "rough_conductor",
                   .description = "Trowbridge-Reitz conductor (gold), sampled by visible normals"},
                  {{"alpha", {0.05, 0.3, 1}}, {"theta_o", {0, 30, 60, 80, 89}}},
                  [](WarpCaseInfo info, const GridPoint& p) {
                      const TrowbridgeReitz tr(static_cast<float>(p["alpha"]));
                      return make_bsdf_case(std::move(info), {.wo = grid_wo(p)}, RoughConductor(tr, kGoldEta, kGoldK));
                  });
}

void register_bsdf_cases(Registry& registry) {
    register_lambertian(registry);
    register_rough_conductor(registry);
}

WARPCHECK_BUILTIN_CASES(70, register_bsdf_cases);

}  // namespace
}  // namespace warpcheck

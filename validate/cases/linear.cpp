// Linear and bilinear warps (sampling/linear.h).
#include "sampling/linear.h"
#include "validate/registry.h"

namespace warpcheck {

void register_linear_cases(Registry& registry) {
    for (auto [a, b] : {std::pair{1.0, 3.0}, std::pair{0.0, 1.0}, std::pair{2.0, 0.0}}) {
        const auto fa = static_cast<float>(a), fb = static_cast<float>(b);
        registry.add_case(make_warp_case(
            {"linear", {{"a", a}, {"b", b}}, "density proportional to (1-x) a + x b on [0,1]", InputKind::Uniform1D,
             chi2::Domain::interval(0.0, 1.0)},
            [=](float u) { return sample_linear(u, fa, fb); }, [=](float x) { return linear_pdf(x, fa, fb); },
            [=](float x) { return invert_linear(x, fa, fb); }));
    }
    const Bilinear patch(1.0f, 4.0f, 0.5f, 2.0f);
    registry.add_case(make_warp_case({"bilinear", {{"w00", 1}, {"w10", 4}, {"w01", 0.5}, {"w11", 2}},
                                      "density proportional to the bilinear interpolation of corner weights",
                                      InputKind::Uniform2D, chi2::Domain::unit_square()},
                                     [=](Point2f u) { return patch.sample(u); },
                                     [=](Point2f p) { return patch.pdf(p); },
                                     [=](Point2f p) { return patch.invert(p); }));
}

}  // namespace warpcheck

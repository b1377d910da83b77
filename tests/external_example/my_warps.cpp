// A renderer's own warp, validated by warpcheck without forking it.
#include <cmath>

#include <validate/external.h>

// The renderer's warp: x in [0,1] with density proportional to (1-x) a + x b.
struct LinearWarp {
    float a, b;
    float sample(float u) const {
        // The root of the quadratic CDF in the form without cancellation; it is
        // 0/0 at u = 0 when a = 0, where the answer is 0.
        if (u == 0) return 0;
        const float lerp_sq = (1 - u) * a * a + u * b * b;
        return u * (a + b) / (a + std::sqrt(lerp_sq));
    }
    float pdf(float x) const { return x < 0 || x > 1 ? 0 : 2 * ((1 - x) * a + x * b) / (a + b); }
    // The CDF; kept below 1, since sample rounds its largest inputs up to x = 1
    // and an inverse must return a valid input u of [0,1).
    float invert(float x) const { return std::fmin(x * (a * (2 - x) + b * x) / (a + b), 0x1.fffffep-1f); }
};

void warpcheck_register(warpcheck::Registry& registry) {
    for (auto [a, b] : {std::pair{1.0f, 3.0f}, std::pair{0.0f, 1.0f}}) {
        const LinearWarp warp{a, b};
        // With members named sample, pdf and invert, make_warp_case(info, warp)
        // would do; three callables adapt a warp with any other names.
        registry.add_case(warpcheck::make_warp_case(
            {.family = "linear",
             .params = {{"a", a}, {"b", b}},
             .description = "density proportional to (1-x) a + x b on [0,1]",
             .input = warpcheck::InputKind::Uniform1D,
             .domain = warpcheck::chi2::Domain::interval(0, 1)},
            [warp](float u) { return warp.sample(u); },
            [warp](float x) { return warp.pdf(x); },
            [warp](float x) { return warp.invert(x); }));
    }
}

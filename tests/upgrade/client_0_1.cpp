// A renderer's registration as warpcheck 0.1's README taught it (README.md and
// tests/external_example/my_warps.cpp before the headers moved to
// validate/api/, commit d2e9561): the old include path, and the positional
// make_warp_case, make_weighted_case and make_u32_float_case. Left as it was
// written: run_upgrade.sh compiles it against the installed package and
// requires a deprecation warning naming what replaces each old form, and
// every check that applies to its cases to pass.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <vector>

#include <chi2/domain_kinds.h>
#include <validate/external.h>

namespace {

constexpr float kPif = std::numbers::pi_v<float>;

// The renderer's warp: x in [0,1] with density proportional to (1-x) a + x b.
struct LinearWarp {
    float a, b;
    float sample(float u) const {
        if (u == 0) return 0;
        const float lerp_sq = (1 - u) * a * a + u * b * b;
        return u * (a + b) / (a + std::sqrt(lerp_sq));
    }
    float pdf(float x) const { return x < 0 || x > 1 ? 0 : 2 * ((1 - x) * a + x * b) / (a + b); }
    float invert(float x) const { return std::fmin(x * (a * (2 - x) + b * x) / (a + b), 0x1.fffffep-1f); }
};

warpcheck::Vector3f direction(float cos_theta, float phi) {
    const float sin_theta = std::sqrt(std::fmax(0.0f, 1 - cos_theta * cos_theta));
    return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

// A renderer's Sample(u, &pdf): the cosine-weighted hemisphere.
struct CosineHemisphere {
    warpcheck::Vector3f sample(warpcheck::Point2f u, float* pdf) const {
        const float cos_theta = std::sqrt(u.x);
        *pdf = cos_theta / kPif;
        return direction(cos_theta, 2 * kPif * u.y);
    }
    float pdf(warpcheck::Vector3f w) const { return w.z > 0 ? w.z / kPif : 0; }
};

// A table-driven sampler with no pdf function: piecewise constant over the cells of [0, 1).
struct TableSampler {
    std::vector<float> weights;
    warpcheck::PdfSample<float> sample(float u) const {
        const float total = std::accumulate(weights.begin(), weights.end(), 0.0f);
        const auto n = static_cast<float>(weights.size());
        std::size_t i = 0;
        float below = 0;
        while (i + 1 < weights.size() && u * total >= below + weights[i]) below += weights[i++];
        const float t = std::fmin((u * total - below) / weights[i], 0x1.fffffep-1f);
        return {(static_cast<float>(i) + t) / n, weights[i] / total * n};
    }
};

// A diffuse lobe and a power-cosine lobe of exponent n, picked with probability select.
struct PhongMixture {
    float kd = 0.5f, ks = 0.3f, n = 20, select = 0.3f;
    float eval(warpcheck::Vector3f w) const {
        return w.z > 0 ? (kd / kPif + ks * (n + 2) / (2 * kPif) * std::pow(w.z, n)) * w.z : 0;
    }
    float pdf(warpcheck::Vector3f w) const {
        return w.z > 0 ? (1 - select) * w.z / kPif + select * (n + 1) / (2 * kPif) * std::pow(w.z, n) : 0;
    }
    warpcheck::WeightedSample<warpcheck::Vector3f> sample(warpcheck::Point2f u) const {
        const bool power = u.x < select;
        const float v = power ? u.x / select : (u.x - select) / (1 - select);
        const warpcheck::Vector3f w = direction(power ? std::pow(1 - v, 1 / (n + 1)) : std::sqrt(1 - v), 2 * kPif * u.y);
        return {w, eval(w) / pdf(w)};
    }
};

float unit_float_from_bits(uint32_t u) { return static_cast<float>(u >> 8) * 0x1p-24f; }

}  // namespace

void warpcheck_register(warpcheck::Registry& registry) {
    using namespace warpcheck;
    const LinearWarp linear{1.0f, 3.0f};
    registry.add_case(make_warp_case({.family = "linear",
                                      .params = {{"a", 1}, {"b", 3}},
                                      .description = "density proportional to (1-x) a + x b on [0,1]",
                                      .input = InputKind::Uniform1D,
                                      .domain = chi2::Domain::interval(0, 1)},
                                     [linear](float u) { return linear.sample(u); },
                                     [linear](float x) { return linear.pdf(x); },
                                     [linear](float x) { return linear.invert(x); }));
    const CosineHemisphere cosine;
    registry.add_case(make_warp_case({.family = "cosine_returned_pdf",
                                      .description = "cosine-weighted hemisphere whose sample returns its pdf",
                                      .domain = chi2::Domain::hemisphere()},
                                     [cosine](Point2f u) {
                                         float pdf = 0;
                                         const Vector3f w = cosine.sample(u, &pdf);
                                         return PdfSample<Vector3f>{w, pdf};
                                     },
                                     [cosine](Vector3f w) { return cosine.pdf(w); }));
    const TableSampler table{{1, 3, 2, 0.5f}};
    registry.add_case(make_warp_case({.family = "table_no_pdf",
                                      .description = "piecewise-constant table; pdf only from sample",
                                      .input = InputKind::Uniform1D,
                                      .domain = chi2::Domain::interval(0, 1)},
                                     [table](float u) { return table.sample(u); }));
    add_case_grid(registry, {.family = "phong_mixture", .domain = chi2::Domain::hemisphere()},
                  {{"n", {5, 50}}, {"select", {0.3}}}, [](WarpCaseInfo info, const GridPoint& p) {
                      PhongMixture m;
                      m.n = float(p["n"]);
                      m.select = float(p["select"]);
                      return make_weighted_case(std::move(info), [m](Point2f u) { return m.sample(u); },
                                                [m](Vector3f w) { return m.eval(w); },
                                                [m](Vector3f w) { return m.pdf(w); });
                  });
    registry.add_case(make_u32_float_case(
        {.family = "renderer_unit_float",
         .description = "float in [0,1) from the top 24 of 32 random bits",
         .domain = chi2::Domain::interval(0, 1)},
        Monotone::Claimed, [](uint32_t u) { return unit_float_from_bits(u); },
        [](float x) { return x >= 0 && x < 1 ? 1.0f : 0.0f; },
        [](float x) { return static_cast<uint32_t>(x * 0x1p24f) << 8; }));
}

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

void register_renderer_kinds(warpcheck::Registry& registry);  // below: samplers that return more than a point

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
    register_renderer_kinds(registry);
}

// ---- Samplers that return more than a point (README, "Samplers that return more than a point") ----
// Each kind is registered correct and as a wrong twin; the twins are marked as
// known flaws, so `--all` runs the correct ones and run_example.sh runs each
// twin by name and asserts that the check meant to catch it fails.
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

constexpr float kPi = 3.14159265358979323846f;

warpcheck::Vector3f direction(float cos_theta, float phi) {
    const float sin_theta = std::sqrt(std::fmax(0.0f, 1 - cos_theta * cos_theta));
    return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

// A renderer's Sample(u, &pdf): the cosine-weighted hemisphere, its pdf
// computed from u. The twin takes cos theta = u.x for the pdf, not sqrt(u.x).
struct CosineHemisphere {
    bool wrong_pdf = false;
    warpcheck::Vector3f sample(warpcheck::Point2f u, float* pdf) const {
        const float cos_theta = std::sqrt(u.x);
        *pdf = (wrong_pdf ? u.x : cos_theta) / kPi;
        return direction(cos_theta, 2 * kPi * u.y);
    }
    float pdf(warpcheck::Vector3f w) const { return w.z > 0 ? w.z / kPi : 0; }
};

// A table-driven sampler with no pdf function: piecewise constant over the
// cells of [0, 1). The twin returns the cell's probability, not its density.
struct TableSampler {
    std::vector<float> weights;
    bool probability_not_density = false;
    warpcheck::PdfSample<float> sample(float u) const {
        const float total = std::accumulate(weights.begin(), weights.end(), 0.0f);
        const auto n = static_cast<float>(weights.size());
        std::size_t i = 0;
        float below = 0;
        while (i + 1 < weights.size() && u * total >= below + weights[i]) below += weights[i++];
        const float t = std::fmin((u * total - below) / weights[i], 0x1.fffffep-1f);
        const float probability = weights[i] / total;
        return {(static_cast<float>(i) + t) / n, probability_not_density ? probability : probability * n};
    }
};

// A BSDF-style mixture: a diffuse lobe and a power-cosine lobe of exponent n,
// eval = (kd / pi + ks (n + 2) / (2 pi) cos^n theta) cos theta, whose integral
// over the hemisphere is kd + ks. sample picks the power lobe with probability
// `select`; the twin's pdf says `pdf_select` instead (0.5 against 0.3).
struct PhongMixture {
    float kd = 0.5f, ks = 0.3f, n = 20, select = 0.3f, pdf_select = 0.3f;
    float eval(warpcheck::Vector3f w) const {
        return w.z > 0 ? (kd / kPi + ks * (n + 2) / (2 * kPi) * std::pow(w.z, n)) * w.z : 0;
    }
    float pdf(warpcheck::Vector3f w) const {
        return w.z > 0 ? (1 - pdf_select) * w.z / kPi + pdf_select * (n + 1) / (2 * kPi) * std::pow(w.z, n) : 0;
    }
    warpcheck::WeightedSample<warpcheck::Vector3f> sample(warpcheck::Point2f u) const {
        const bool power = u.x < select;
        const float v = power ? u.x / select : (u.x - select) / (1 - select);
        const warpcheck::Vector3f w = direction(power ? std::pow(1 - v, 1 / (n + 1)) : std::sqrt(1 - v), 2 * kPi * u.y);
        return {w, eval(w) / pdf(w)};
    }
};

// Vose's alias table: sample returns the index and u remapped to [0,1) for
// reuse. The twin forgets to rescale the remapped u by the bin's threshold.
struct AliasTable {
    std::vector<float> pmf, q;
    std::vector<uint32_t> alias;
    bool remap_not_rescaled = false;
    explicit AliasTable(const std::vector<float>& w) : pmf(w.size()), q(w.size(), 1.0f), alias(w.size()) {
        const float total = std::accumulate(w.begin(), w.end(), 0.0f);
        std::vector<double> scaled(w.size());
        std::vector<uint32_t> small, large;
        for (uint32_t i = 0; i < w.size(); ++i) {
            pmf[i] = w[i] / total;
            scaled[i] = double(w[i]) * double(w.size()) / total;
            alias[i] = i;
            (scaled[i] < 1 ? small : large).push_back(i);
        }
        while (!small.empty() && !large.empty()) {
            const uint32_t s = small.back(), l = large.back();
            small.pop_back();
            q[s] = float(scaled[s]);
            alias[s] = l;
            scaled[l] -= 1 - scaled[s];
            if (scaled[l] < 1) large.pop_back(), small.push_back(l);
        }
    }
    warpcheck::DiscreteSample sample(float u) const {
        const float scaled = u * float(q.size());
        const uint32_t i = std::min(uint32_t(scaled), uint32_t(q.size() - 1));
        const float up = scaled - float(i);
        if (up < q[i]) return {i, std::fmin(remap_not_rescaled ? up : up / q[i], 0x1.fffffep-1f)};
        return {alias[i], std::fmin((up - q[i]) / (1 - q[i]), 0x1.fffffep-1f)};
    }
};

void register_renderer_kinds(warpcheck::Registry& registry) {
    using namespace warpcheck;
    // A sample that returns its pdf, with a pdf function: "sample_pdf" compares the two.
    for (bool wrong : {false, true}) {
        const CosineHemisphere warp{wrong};
        registry.add_case(make_warp_case(
            {.family = wrong ? "cosine_returned_pdf_wrong" : "cosine_returned_pdf",
             .description = "cosine-weighted hemisphere whose sample returns its pdf",
             .domain = chi2::Domain::hemisphere()},
            [warp](Point2f u) {
                float pdf = 0;
                const Vector3f w = warp.sample(u, &pdf);
                return PdfSample<Vector3f>{w, pdf};
            },
            [warp](Vector3f w) { return warp.pdf(w); }));
    }
    // A sample that returns its pdf and no pdf function: the returned pdf is the pdf.
    for (bool wrong : {false, true}) {
        const TableSampler table{{1, 3, 2, 0.5f}, wrong};
        registry.add_case(make_warp_case({.family = wrong ? "table_no_pdf_wrong" : "table_no_pdf",
                                          .description = "piecewise-constant table; pdf only from sample",
                                          .input = InputKind::Uniform1D,
                                          .domain = chi2::Domain::interval(0, 1)},
                                         [table](float u) { return table.sample(u); }));
    }
    // Weighted samplers, over a grid of exponents and selection probabilities.
    add_case_grid(registry, {.family = "phong_mixture", .domain = chi2::Domain::hemisphere()},
                  {{"n", {5, 50}}, {"select", {0.3, 0.6}}}, [](WarpCaseInfo info, const GridPoint& p) {
                      PhongMixture m;
                      m.n = float(p["n"]);
                      m.select = m.pdf_select = float(p["select"]);
                      return make_weighted_case(std::move(info), [m](Point2f u) { return m.sample(u); },
                                                [m](Vector3f w) { return m.eval(w); },
                                                [m](Vector3f w) { return m.pdf(w); });
                  });
    PhongMixture twin;
    twin.pdf_select = 0.5f;
    registry.add_case(make_weighted_case({.family = "phong_mixture_wrong", .domain = chi2::Domain::hemisphere()},
                                         [twin](Point2f u) { return twin.sample(u); },
                                         [twin](Vector3f w) { return twin.eval(w); },
                                         [twin](Vector3f w) { return twin.pdf(w); }));
    // Discrete: an alias table over weights (one of them 0), with its remapped u.
    for (bool wrong : {false, true}) {
        AliasTable table({1, 0, 3, 2, 0.5f, 7});
        table.remap_not_rescaled = wrong;
        registry.add_case(make_warp_case({.family = wrong ? "alias_table_wrong" : "alias_table",
                                          .description = "alias table over six weights, one of them 0",
                                          .input = InputKind::Uniform1D,
                                          .categories = table.pmf.size()},
                                         [table](float u) { return table.sample(u); },
                                         [table](uint32_t i) { return table.pmf[i]; }));
    }
    for (const char* twin_name :
         {"cosine_returned_pdf_wrong", "table_no_pdf_wrong", "phong_mixture_wrong", "alias_table_wrong"})
        registry.mark_known_flaw(twin_name, "a wrong twin: run_example.sh checks that it fails");
}

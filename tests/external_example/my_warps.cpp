// A renderer's own warps, validated by warpcheck without forking it: one of
// each kind the case API takes, each correct and with a wrong twin (registered
// as a known flaw, so that --all passes; run_example.sh runs each twin by name
// and asserts that the check meant to catch it fails).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <vector>

#include <validate/api/bsdf_grid.h>
#include <validate/api/external.h>

namespace {

constexpr double kPi = std::numbers::pi;

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

void register_linear(warpcheck::Registry& registry) {
    for (auto [a, b] : {std::pair{1.0f, 3.0f}, std::pair{0.0f, 1.0f}}) {
        const LinearWarp warp{a, b};
        // With members named sample, pdf and invert, make_warp_case(info, warp)
        // would do; named callables adapt a warp whose parts have other names.
        registry.add_case(warpcheck::make_warp_case(
            {.family = "linear",
             .params = {{"a", a}, {"b", b}},
             .description = "density proportional to (1-x) a + x b on [0,1]",
             .domain = warpcheck::Domain::interval(0, 1)},
            warpcheck::warp_of([warp](float u) { return warp.sample(u); })
                .with_pdf([warp](float x) { return warp.pdf(x); })
                .with_invert([warp](float x) { return warp.invert(x); })));
    }
}

// ---- Samplers that return more than a point (validate/api/README.md, "Samplers that return more than a point") ----
// Each kind is registered correct and as a wrong twin; the twins are marked as
// known flaws, so `--all` runs the correct ones and run_example.sh runs each
// twin by name and asserts that the check meant to catch it fails.

constexpr float kPif = std::numbers::pi_v<float>;

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
        *pdf = (wrong_pdf ? u.x : cos_theta) / kPif;
        return direction(cos_theta, 2 * kPif * u.y);
    }
    float pdf(warpcheck::Vector3f w) const { return w.z > 0 ? w.z / kPif : 0; }
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
        return w.z > 0 ? (kd / kPif + ks * (n + 2) / (2 * kPif) * std::pow(w.z, n)) * w.z : 0;
    }
    float pdf(warpcheck::Vector3f w) const {
        return w.z > 0 ? (1 - pdf_select) * w.z / kPif + pdf_select * (n + 1) / (2 * kPif) * std::pow(w.z, n) : 0;
    }
    warpcheck::WeightedSample<warpcheck::Vector3f> sample(warpcheck::Point2f u) const {
        const bool power = u.x < select;
        const float v = power ? u.x / select : (u.x - select) / (1 - select);
        const warpcheck::Vector3f w = direction(power ? std::pow(1 - v, 1 / (n + 1)) : std::sqrt(1 - v), 2 * kPif * u.y);
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
    float pdf(uint32_t i) const { return pmf[i]; }  // the pmf
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
             .domain = warpcheck::Domain::hemisphere()},
            warp_of([warp](Point2f u) {
                float pdf = 0;
                const Vector3f w = warp.sample(u, &pdf);
                return PdfSample<Vector3f>{w, pdf};
            }).with_pdf([warp](Vector3f w) { return warp.pdf(w); })));
    }
    // A sample that returns its pdf and no pdf function: the returned pdf is the pdf.
    for (bool wrong : {false, true}) {
        const TableSampler table{{1, 3, 2, 0.5f}, wrong};
        registry.add_case(make_warp_case({.family = wrong ? "table_no_pdf_wrong" : "table_no_pdf",
                                          .description = "piecewise-constant table; pdf only from sample",
                                          .domain = warpcheck::Domain::interval(0, 1)},
                                         table));
    }
    // Weighted samplers, over a grid of exponents and selection probabilities.
    add_case_grid(registry, {.family = "phong_mixture", .domain = warpcheck::Domain::hemisphere()},
                  {{"n", {5, 50}}, {"select", {0.3, 0.6}}}, [](WarpCaseInfo info, const GridPoint& p) {
                      PhongMixture m;
                      m.n = float(p["n"]);
                      m.select = m.pdf_select = float(p["select"]);
                      return make_warp_case(std::move(info), m);  // its members sample, eval and pdf
                  });
    PhongMixture twin;
    twin.pdf_select = 0.5f;
    registry.add_case(
        make_warp_case({.family = "phong_mixture_wrong", .domain = warpcheck::Domain::hemisphere()}, twin));
    // Discrete: an alias table over weights (one of them 0), with its remapped u.
    for (bool wrong : {false, true}) {
        AliasTable table({1, 0, 3, 2, 0.5f, 7});
        table.remap_not_rescaled = wrong;
        registry.add_case(make_warp_case({.family = wrong ? "alias_table_wrong" : "alias_table",
                                          .description = "alias table over six weights, one of them 0",
                                          .categories = table.pmf.size()},
                                         table));
    }
    for (const char* twin_name :
         {"cosine_returned_pdf_wrong", "table_no_pdf_wrong", "phong_mixture_wrong", "alias_table_wrong"})
        registry.mark_known_flaw(twin_name, "a wrong twin: run_example.sh checks that it fails");
}

// The normal distribution by inversion: the lower-tail quantile from
// Abramowitz & Stegun 26.2.23, refined by Newton steps on Phi(x) = p.
double lower_normal_quantile(double p) {
    const double t = std::sqrt(-2 * std::log(p));
    double x = -(t - (2.515517 + 0.802853 * t + 0.010328 * t * t) /
                         (1 + 1.432788 * t + 0.189269 * t * t + 0.001308 * t * t * t));
    for (int k = 0; k < 3; ++k) x -= (0.5 * std::erfc(-x / std::sqrt(2.0)) - p) / (std::exp(-x * x / 2) / std::sqrt(2 * kPi));
    return x;
}

// The whole real line: a normal distribution with mean mu and deviation sigma.
struct NormalWarp {
    float mu, sigma;
    bool pdf_forgets_sigma = false;  // the wrong twin's bug: the density lacks its 1/sigma
    float sample(float u) const {
        // u = 0 is taken as the middle of the smallest step of the input, 2^-65,
        // so that every input maps to a finite x with a positive density.
        const double p = std::max(std::min<double>(u, 1 - u), 0x1p-65);
        const double z = lower_normal_quantile(p);
        return static_cast<float>(mu + sigma * (u < 0.5f ? z : -z));
    }
    float pdf(float x) const {
        const double z = (x - mu) / sigma;
        return static_cast<float>(std::exp(-z * z / 2) / ((pdf_forgets_sigma ? 1.0 : sigma) * std::sqrt(2 * kPi)));
    }
    float invert(float x) const {
        return std::fmin(static_cast<float>(0.5 * std::erfc(-(x - mu) / (sigma * std::sqrt(2.0)))), 0x1.fffffep-1f);
    }
};

void register_normal(warpcheck::Registry& registry) {
    for (bool wrong : {false, true}) {
        const NormalWarp warp{2.0f, 0.5f, wrong};
        // The tabulated check needs the view truncated: 4 sigma each side, with
        // the mass beyond each end, Phi(-4).
        warpcheck::MonotoneMarginal x;
        x.lo = 2.0 - 4 * 0.5;
        x.hi = 2.0 + 4 * 0.5;
        x.lower_tail_mass = x.tail_mass = 0.5 * std::erfc(4 / std::sqrt(2.0));
        x.label = "x";
        registry.add_case(warpcheck::make_warp_case(
            {.family = wrong ? "normal_pdf_forgets_sigma" : "normal",
             .params = {{"mu", 2}, {"sigma", 0.5}},
             .description = "normal distribution on the whole real line, by inversion",
             .domain = warpcheck::Domain::real_line(),
             .views = {x}},
            warp));
    }
}

// (-inf, b]: x = b + log(1 - u) / rate, density rate exp(rate (x - b)).
struct MirroredExponentialWarp {
    float b, rate;
    bool invert_flipped = false;  // the wrong twin's bug: returns 1 - u
    float sample(float u) const { return b + std::log1p(-u) / rate; }
    float pdf(float x) const { return x > b ? 0 : rate * std::exp(rate * (x - b)); }
    float invert(float x) const {
        const float tail = std::exp(rate * (x - b));  // the probability above x
        return invert_flipped ? tail : -std::expm1(rate * (x - b));
    }
};

void register_mirrored_exponential(warpcheck::Registry& registry) {
    for (bool wrong : {false, true}) {
        // x decreases as u grows; truncated at 10 / rate below b.
        warpcheck::MonotoneMarginal x;
        x.increasing = false;
        x.lo = 1.0 - 10 / 4.0;
        x.hi = 1.0;
        x.lower_tail_mass = std::exp(-10.0);
        x.label = "x";
        registry.add_case(warpcheck::make_warp_case(
            {.family = wrong ? "mirrored_exponential_inverse_flipped" : "mirrored_exponential",
             .params = {{"b", 1}, {"rate", 4}},
             .description = "exponential tail on the half-line (-inf, b]",
             .domain = warpcheck::Domain::lower_half_line(1),
             .views = {x}},
            MirroredExponentialWarp{1.0f, 4.0f, wrong}));
    }
}

// No inverse: cosine-weighted directions by projecting a uniform disk point
// (polar map) up to the hemisphere. A warp object without an invert member.
struct CosineHemisphereNoInverse {
    float pdf_scale = 1;  // the wrong twin's bug: 1/2, a density that integrates to 1/2
    warpcheck::Vector3f sample(warpcheck::Point2f u) const {
        const float r = std::sqrt(u.x), phi = 2 * std::numbers::pi_v<float> * u.y;
        return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::fmax(0.0f, 1 - u.x))};
    }
    float pdf(warpcheck::Vector3f w) const { return w.z < 0 ? 0 : pdf_scale * w.z / std::numbers::pi_v<float>; }
};

void register_no_inverse(warpcheck::Registry& registry) {
    for (bool wrong : {false, true}) {
        registry.add_case(warpcheck::make_warp_case(
            {.family = wrong ? "cosine_hemisphere_no_inverse_half_pdf" : "cosine_hemisphere_no_inverse",
             .description = "cosine-weighted hemisphere without an inverse: the round trip is not applicable",
             .domain = warpcheck::Domain::hemisphere()},
            CosineHemisphereNoInverse{wrong ? 0.5f : 1.0f}));
    }
}

// Two views of one spherical warp: cos theta = 1 - 2 u.x and the azimuth
// phi = 2 pi u.y. The wrong twin bends phi by 1e-3 of a turn: cos theta, the
// density and the solid angle are untouched, only the azimuth view sees it.
struct UniformSphereTwoViews {
    float bend = 0;
    warpcheck::Vector3f sample(warpcheck::Point2f u) const {
        const float z = 1 - 2 * u.x, r = std::sqrt(std::fmax(0.0f, 1 - z * z));
        const float turn = u.y + bend * std::sin(2 * std::numbers::pi_v<float> * u.y);
        const float phi = 2 * std::numbers::pi_v<float> * turn;
        return {r * std::cos(phi), r * std::sin(phi), z};
    }
    float pdf(warpcheck::Vector3f) const { return static_cast<float>(1 / (4 * kPi)); }
};

void register_sphere_views(warpcheck::Registry& registry) {
    warpcheck::MonotoneMarginal cos_theta;
    cos_theta.increasing = false;  // z falls as u.x grows
    cos_theta.lo = -1;
    cos_theta.hi = 1;
    cos_theta.label = "cos theta";
    cos_theta.coordinate = [](const warpcheck::WarpOutput& w) { return double{w[2]}; };
    cos_theta.pdf = [](double) { return 0.5; };
    warpcheck::MonotoneMarginal azimuth;
    azimuth.input_coordinate = 1;  // phi grows with u.y
    azimuth.lo = 0;
    azimuth.hi = 2 * kPi;
    azimuth.label = "phi";
    azimuth.coordinate = [](const warpcheck::WarpOutput& w) {
        return w[0] == 0 && w[1] == 0 ? std::nan("") : warpcheck::exact_phi(w[0], w[1]);  // NaN at a pole
    };
    azimuth.pdf = [](double) { return 1 / (2 * kPi); };
    for (bool wrong : {false, true}) {
        registry.add_case(warpcheck::make_warp_case(
            {.family = wrong ? "uniform_sphere_azimuth_bent" : "uniform_sphere",
             .description = "uniform directions, with a cos theta view and an azimuth view",
             .domain = warpcheck::Domain::sphere(),
             .views = {cos_theta, azimuth}},
            UniformSphereTwoViews{wrong ? 1e-3f : 0.0f}));
    }
}

// A warp written once as a template over its float type, as Mitsuba's are:
// make_warp_case instantiates it on float for every check, and on eight floats
// at once for the chi-square check's vectorised path (validate/api/float_template_warp.h),
// where it gives the same bits. warpcheck::lanes has the math for either type.
template <typename Float>
struct Vec2 {
    Float x, y;
};
template <typename Float>
struct Vec3 {
    Float x, y, z;
};

// Uniform directions in the cone z >= cos_theta_max. The wrong twin draws its
// cos theta from a cone 2% wider than the one its pdf describes.
struct TemplatedCone {
    float cos_theta_max, drawn_cos_theta_max;
    template <typename Float>
    Vec3<Float> sample(Vec2<Float> u) const {
        const Float one_minus_cos = u.x * (1 - drawn_cos_theta_max);
        const Float sin_theta = warpcheck::lanes::safe_sqrt(one_minus_cos * (2 - one_minus_cos));
        const auto phi = warpcheck::lanes::sin_cos(2 * kPif * u.y);
        return {sin_theta * phi.cos, sin_theta * phi.sin, 1 - one_minus_cos};
    }
    float pdf(warpcheck::Vector3f w) const {
        return w.z >= cos_theta_max - 0x1p-22f ? 1 / (2 * kPif * (1 - cos_theta_max)) : 0;
    }
};

void register_templated(warpcheck::Registry& registry) {
    for (bool wrong : {false, true}) {
        const float c = 0.3f;
        registry.add_case(warpcheck::make_warp_case(
            {.family = wrong ? "templated_cone_too_wide" : "templated_cone",
             .description = "uniform in a cone, written as a template over the float type",
             .domain = warpcheck::Domain::spherical_cap(c)},
            TemplatedCone{c, wrong ? 1 - 1.02f * (1 - c) : c}));
    }
}

// A float sampler of raw bits, on the exhaustive check's fast path: all 2^32
// inputs are swept and every float counted. The correct one keeps the top 24
// bits (each float of the 2^-24 grid exactly 256 times, in order); the wrong
// twin swaps neighbouring grid values, so it still counts every float 256
// times (the statistics cannot see it) but breaks the monotone order it claims.
float unit_float_from_bits(uint32_t u, bool swap_neighbours) {
    const uint32_t k = (u >> 8) ^ (swap_neighbours ? 1u : 0u);
    return static_cast<float>(k) * 0x1p-24f;
}

void register_float_sampler(warpcheck::Registry& registry) {
    for (bool wrong : {false, true}) {
        registry.add_case(warpcheck::make_u32_float_case(
            {.family = wrong ? "renderer_unit_float_swapped" : "renderer_unit_float",
             .description = "float in [0,1) from the top 24 of 32 random bits",
             .domain = warpcheck::Domain::interval(0, 1)},
            warpcheck::Monotone::Claimed,
            warpcheck::warp_of([wrong](uint32_t u) { return unit_float_from_bits(u, wrong); })
                .with_pdf([](float x) { return x >= 0 && x < 1 ? 1.0f : 0.0f; })
                .with_invert([wrong](float x) {
                    return (static_cast<uint32_t>(x * 0x1p24f) ^ (wrong ? 1u : 0u)) << 8;
                })));
    }
}

// A renderer's diffuse BSDF as it is (pbrt-v4's BxDF shape: sample, f, pdf
// and flags): cosine-weighted wi by Malley's method, f = R / pi; its wrong
// twin makes f brighter towards the normal on the wi side only, which is not
// reciprocal.
struct RendererDiffuse {
    float r;
    bool wrong = false;
    warpcheck::BsdfFlags flags() const { return warpcheck::BsdfFlags::Reflection | warpcheck::BsdfFlags::Continuous; }
    float f(warpcheck::Vector3f wo, warpcheck::Vector3f wi) const {
        if (!(wo.z * wi.z > 0)) return 0.0f;
        return r * std::numbers::inv_pi_v<float> * (wrong ? 0.7f + 0.6f * std::abs(wi.z) : 1.0f);
    }
    float pdf(warpcheck::Vector3f wo, warpcheck::Vector3f wi) const {
        return wo.z * wi.z > 0 ? std::abs(wi.z) * std::numbers::inv_pi_v<float> : 0.0f;
    }
    warpcheck::BsdfSample sample(warpcheck::Vector3f wo, float, warpcheck::Point2f u) const {
        const float rad = std::sqrt(u.x), phi = 2 * std::numbers::pi_v<float> * u.y;
        warpcheck::Vector3f wi{rad * std::cos(phi), rad * std::sin(phi), std::sqrt(std::max(0.0f, 1 - u.x))};
        if (wo.z < 0) wi.z = -wi.z;
        const float p = pdf(wo, wi);
        if (!(p > 0)) return {};
        return {wi, f(wo, wi), p, flags()};
    }
};

void register_bsdfs(warpcheck::Registry& registry) {
    using namespace warpcheck;
    add_case_grid(registry, {.family = "renderer_diffuse", .description = "a renderer's diffuse BSDF"},
                  {{"theta_o", {0, 60, 85}}}, [](WarpCaseInfo info, const GridPoint& point) {
                      return make_bsdf_case(std::move(info), {.wo = grid_wo(point)}, RendererDiffuse{0.7f});
                  });
    // Its wrong twin, a known flaw: validate runs it only when named.
    const WarpCaseInfo twin{.family = "renderer_diffuse_not_reciprocal", .params = {{"theta_o", 60}}};
    registry.add_case(make_bsdf_case(twin, {.wo = bsdf_direction(60)}, RendererDiffuse{0.7f, true}));
    registry.mark_known_flaw(case_name(twin.family, twin.params), "f not reciprocal: brighter towards the normal at wi");
}

}  // namespace

void warpcheck_register(warpcheck::Registry& registry) {
    register_bsdfs(registry);
    register_linear(registry);
    register_normal(registry);
    register_mirrored_exponential(registry);
    register_no_inverse(registry);
    register_sphere_views(registry);
    register_renderer_kinds(registry);
    register_float_sampler(registry);
    register_templated(registry);
    // The wrong twins: known flaws, run by name (or with --include-flawed).
    registry.mark_known_flaw("normal_pdf_forgets_sigma[mu=2,sigma=0.5]", "the density lacks its 1/sigma");
    registry.mark_known_flaw("mirrored_exponential_inverse_flipped[b=1,rate=4]", "invert returns 1 - u");
    registry.mark_known_flaw("cosine_hemisphere_no_inverse_half_pdf", "the density integrates to 1/2");
    registry.mark_known_flaw("uniform_sphere_azimuth_bent", "phi bent by 1e-3 of a turn");
    registry.mark_known_flaw("renderer_unit_float_swapped", "neighbouring floats swapped: not monotone as claimed");
    registry.mark_known_flaw("templated_cone_too_wide", "draws from a cone 2% wider than its pdf's");
}

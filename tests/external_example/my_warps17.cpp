// A renderer that compiles as C++17 registers its warps in its own files
// through validate/api/register17.h alone; the program links warpcheck::main.
// One correct case of every kind a C++20 renderer can register, each new kind
// with a wrong twin (a known flaw: run_example.sh runs each twin by name and
// asserts that the check meant to catch it fails).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <numeric>
#include <string>
#include <vector>

#include <validate/api/register17.h>

static_assert(__cplusplus == 201703L, "this file proves that registration compiles as C++17");

namespace {

namespace w17 = warpcheck::cxx17;

constexpr float kPi = 3.14159265f;
constexpr float kInvPi = 0.318309886f;

// A renderer's diffuse BSDF in C++17: cosine-weighted wi, f = R / pi. Its
// wrong twin returns a sample whose weight misses |cos theta_i| (f / |cos|).
struct Diffuse17 {
    float r;
    bool wrong = false;
    double f(const w17::Point& wo, const w17::Point& wi) const { return wo[2] * wi[2] > 0 ? r * kInvPi : 0.0; }
    double pdf(const w17::Point& wo, const w17::Point& wi) const {
        return wo[2] * wi[2] > 0 ? std::abs(wi[2]) * kInvPi : 0.0;
    }
    w17::BsdfSample sample(const w17::Point& wo, const w17::Point2& u) const {
        const float rad = std::sqrt(u[0]), phi = 2 * kPi * u[1];
        w17::Point wi{rad * std::cos(phi), rad * std::sin(phi), std::sqrt(std::max(0.0f, 1 - u[0]))};
        if (wo[2] < 0) wi[2] = -wi[2];
        const float p = std::abs(wi[2]) * kInvPi;
        if (!(p > 0)) return {};
        w17::BsdfSample s;
        s.wi = wi;
        s.f = wrong ? r * kInvPi / std::abs(wi[2]) : r * kInvPi;
        s.pdf = p;
        return s;
    }
};

// A stochastic BSDF in C++17, as a layered one is: f(wo, wi) an unbiased
// estimate (R / pi times 2U, U uniform from a hash of wo's and wi's bits, so a
// pair always gets the same value), a sample's weight an unbiased estimate of
// R (R times 2U from its input) with pdf() only for MIS. Its wrong twin's
// weights are 5% high on average; no pointwise comparison could tell.
struct NoisyDiffuse17 {
    float r;
    float bias = 1.0f;
    static float unit(std::uint32_t h) {
        h ^= h >> 16;
        h *= 0x7feb352dU;
        h ^= h >> 15;
        h *= 0x846ca68bU;
        h ^= h >> 16;
        return static_cast<float>(h >> 8) * 0x1p-24f;
    }
    static std::uint32_t bits(float x) {
        std::uint32_t b;
        std::memcpy(&b, &x, sizeof b);
        return b;
    }
    double f(const w17::Point& wo, const w17::Point& wi) const {
        if (!(wo[2] * wi[2] > 0)) return 0.0;
        std::uint32_t h = 0x9e3779b9U;
        for (float c : {wo[0], wo[1], wo[2], wi[0], wi[1], wi[2]}) h = (h ^ bits(c)) * 0x01000193U;
        return r * kInvPi * 2.0f * unit(h);
    }
    double pdf(const w17::Point& wo, const w17::Point& wi) const { return Diffuse17{r, false}.pdf(wo, wi); }
    w17::BsdfSample sample(const w17::Point& wo, const w17::Point2& u) const {
        w17::BsdfSample s = Diffuse17{r, false}.sample(wo, u);  // cosine-weighted wi, pdf |cos| / pi
        if (!(s.pdf > 0)) return s;
        const float weight = r * bias * 2.0f * unit(bits(u[0]) * 0x01000193U ^ bits(u[1]));
        s.f = weight * s.pdf / std::abs(s.wi[2]);
        return s;
    }
};

void register_bsdfs(warpcheck::Registry& registry) {
    for (bool wrong : {false, true}) {
        w17::BsdfInfo info;
        info.family = wrong ? "noisy_diffuse_cxx17_biased" : "noisy_diffuse_cxx17";
        info.params = {{"theta_o", 30}};
        info.description = "a stochastic BSDF (f an estimate, the sample's pdf proportional), registered from C++17";
        info.wo = w17::bsdf_direction(30);
        info.stochastic = true;
        w17::add_bsdf(registry, info, NoisyDiffuse17{0.6f, wrong ? 1.05f : 1.0f});
        if (wrong)
            w17::mark_known_flaw(registry, "noisy_diffuse_cxx17_biased[theta_o=30]", "",
                                 "its sampled weights are 5% high on average");
    }
    for (bool wrong : {false, true})
        for (double theta : {0.0, 70.0}) {
            w17::BsdfInfo info;
            info.family = wrong ? "diffuse_cxx17_weight_no_cos" : "diffuse_cxx17";
            info.params = {{"theta_o", theta}};
            info.description = "a renderer's diffuse BSDF, registered from C++17";
            info.wo = w17::bsdf_direction(theta);
            w17::add_bsdf(registry, info, Diffuse17{0.6f, wrong});
            if (wrong)
                w17::mark_known_flaw(registry, "diffuse_cxx17_weight_no_cos[theta_o=" + std::to_string(int(theta)) + "]",
                                     "", "the sampled weight misses |cos theta_i|");
        }
    // The same BSDF over a grid whose axes declare the ranges validate --fuzz
    // draws from: R in [0, 1], wo from normal incidence to grazing on both
    // sides. Its twin turns NaN for R below 10^-3 (a division by the albedo):
    // its grid point R = 0.6 passes --all, and --fuzz finds it at R = 0.
    for (bool planted : {false, true}) {
        w17::BsdfInfo base;
        base.family = planted ? "diffuse_grid_cxx17_dark_nan" : "diffuse_grid_cxx17";
        base.description = "a renderer's diffuse BSDF over a grid with ranges, registered from C++17";
        w17::add_bsdf_grid(registry, base,
                           {{"R", {0.6}, {{0, 1}}}, {"theta_o", {0, 70}, {{0, 90, false, true}, {90, 180, true, false}}}},
                           [planted](const w17::GridPoint& p) {
                               const float r = static_cast<float>(p["R"]);
                               return Diffuse17{planted && r < 1e-3f ? std::nanf("") : r, false};
                           });
    }
}

// The logistic distribution on the whole real line, mean mu, scale s.
struct Logistic {
    float mu, s;
    float sample(float u) const {
        // u = 0 is taken as half the smallest input step, 2^-65: x stays finite.
        const double p = u > 0 ? double{u} : 0x1p-65;
        return static_cast<float>(mu + s * std::log(p / (1 - p)));
    }
    double pdf(float x) const {
        const double e = std::exp(-std::abs(x - mu) / s);  // symmetric, no overflow
        return e / (s * (1 + e) * (1 + e));
    }
    float invert(float x) const { return std::fmin(static_cast<float>(1 / (1 + std::exp(-(x - mu) / s))), 0x1.fffffep-1f); }
};

void register_logistic(warpcheck::Registry& registry) {
    w17::CaseInfo info;
    info.family = "logistic_cxx17";
    info.params = {{"mu", -3}, {"s", 0.25}};
    info.description = "logistic distribution on the real line, registered from C++17";
    info.domain = w17::Domain::real_line();
    w17::View x;  // truncated where 1e-4 of the mass lies beyond each end
    x.lo = -3 - 0.25 * std::log(1e4 - 1);
    x.hi = -3 + 0.25 * std::log(1e4 - 1);
    x.lower_tail_mass = x.tail_mass = 1e-4;
    x.label = "x";
    info.views = {x};
    w17::add_case(registry, info, Logistic{-3.0f, 0.25f});
}

w17::Point direction(float cos_theta, float phi) {
    const float sin_theta = std::sqrt(std::max(0.0f, 1 - cos_theta * cos_theta));
    return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

// No inverse: cosine-weighted directions. The twin's density is half the true one.
struct CosineNoInverse {
    float pdf_scale = 1;
    w17::Point sample(const w17::Point2& u) const { return direction(std::sqrt(u[0]), 2 * kPi * u[1]); }
    float pdf(const w17::Point& w) const { return w[2] < 0 ? 0 : pdf_scale * w[2] * kInvPi; }
};

// The pdf returned with the sample, and a pdf function: the twin computes the
// returned pdf from u.x, not from cos theta = sqrt(u.x).
struct CosineReturnedPdf {
    bool wrong = false;
    w17::PdfSample<w17::Point> sample(const w17::Point2& u) const {
        const float cos_theta = std::sqrt(u[0]);
        return {direction(cos_theta, 2 * kPi * u[1]), (wrong ? u[0] : cos_theta) * kInvPi};
    }
    float pdf(const w17::Point& w) const { return w[2] > 0 ? w[2] * kInvPi : 0; }
};

// The pdf returned with the sample and no pdf function: a piecewise-constant
// table on [0,1) with an empty cell, so its support is 3/4 of the interval.
// The twin returns the cell's probability, not its density.
struct TableNoPdf {
    std::array<float, 4> weights{1, 0, 3, 2};
    bool probability_not_density = false;
    w17::PdfSample<float> sample(float u) const {
        const float total = std::accumulate(weights.begin(), weights.end(), 0.0f);
        std::size_t i = 0;
        float below = 0;
        while (i + 1 < weights.size() && (weights[i] == 0 || u * total >= below + weights[i])) below += weights[i++];
        const float t = std::fmin((u * total - below) / weights[i], 0x1.fffffep-1f);
        const float probability = weights[i] / total;
        return {(static_cast<float>(i) + t) / 4, probability_not_density ? probability : probability * 4};
    }
};

void register_points(warpcheck::Registry& registry) {
    for (bool wrong : {false, true}) {
        w17::CaseInfo info;
        info.family = wrong ? "cosine_cxx17_no_inverse_half_pdf" : "cosine_cxx17_no_inverse";
        info.description = "cosine-weighted hemisphere without an inverse, from C++17";
        info.domain = w17::Domain::hemisphere();
        w17::add_case(registry, info, CosineNoInverse{wrong ? 0.5f : 1.0f});
        info.family = wrong ? "cosine_cxx17_returned_pdf_wrong" : "cosine_cxx17_returned_pdf";
        info.description = "cosine-weighted hemisphere whose sample returns its pdf, from C++17";
        w17::add_case(registry, info, CosineReturnedPdf{wrong});
        info.family = wrong ? "table_cxx17_no_pdf_wrong" : "table_cxx17_no_pdf";
        info.description = "piecewise-constant table with an empty cell; pdf only from sample, from C++17";
        info.domain = w17::Domain::interval(0, 1);
        info.support_measure = 0.75;
        TableNoPdf table;
        table.probability_not_density = wrong;
        w17::add_case(registry, info, table);
    }
}

// A discrete choice by the CDF of four weights: sample returns the index, pdf
// is the pmf. The twin's pmf swaps the probabilities of the first two.
struct Choice {
    std::array<float, 4> pmf{0.1f, 0.2f, 0.3f, 0.4f};
    bool pmf_swapped = false;
    std::uint32_t sample(float u) const {
        std::uint32_t i = 0;
        for (float below = pmf[0]; i + 1 < pmf.size() && u >= below; below += pmf[++i]) {}
        return i;
    }
    float pdf(std::uint32_t i) const { return pmf_swapped && i < 2 ? pmf[1 - i] : pmf[i]; }
};

// The same choice with u remapped to [0,1) for reuse. The twin forgets to
// rescale the remapped u by the chosen category's probability.
struct ChoiceRemapped {
    Choice choice;
    bool not_rescaled = false;
    w17::DiscreteSample sample(float u) const {
        const std::uint32_t i = choice.sample(u);
        float below = 0;
        for (std::uint32_t k = 0; k < i; ++k) below += choice.pmf[k];
        const float up = u - below;
        return {i, std::fmin(std::max(not_rescaled ? up : up / choice.pmf[i], 0.0f), 0x1.fffffep-1f)};
    }
    float pdf(std::uint32_t i) const { return choice.pdf(i); }
};

void register_discrete(warpcheck::Registry& registry) {
    for (bool wrong : {false, true}) {
        w17::CaseInfo info;
        info.family = wrong ? "choice_cxx17_pmf_swapped" : "choice_cxx17";
        info.description = "a choice among four weights by their CDF, from C++17";
        info.categories = 4;
        Choice choice;
        choice.pmf_swapped = wrong;
        w17::add_case(registry, info, choice);
        info.family = wrong ? "choice_cxx17_remap_not_rescaled" : "choice_cxx17_remapped";
        info.description = "a choice among four weights that returns u remapped for reuse, from C++17";
        ChoiceRemapped remapped;
        remapped.not_rescaled = wrong;
        w17::add_case(registry, info, remapped);
    }
}

// A weighted sampler, a diffuse and a power-cosine lobe: members sample, eval
// and pdf, so that eval and pdf cannot be swapped. The twin's pdf chooses the
// power lobe with probability 0.5, its sample with `select`.
struct PhongMixture {
    float kd = 0.5f, ks = 0.3f, n = 20, select = 0.3f, pdf_select = 0.3f;
    float eval(const w17::Point& w) const {
        return w[2] > 0 ? (kd * kInvPi + ks * (n + 2) / (2 * kPi) * std::pow(w[2], n)) * w[2] : 0;
    }
    float pdf(const w17::Point& w) const {
        return w[2] > 0 ? (1 - pdf_select) * w[2] * kInvPi + pdf_select * (n + 1) / (2 * kPi) * std::pow(w[2], n) : 0;
    }
    w17::WeightedSample<w17::Point> sample(const w17::Point2& u) const {
        const bool power = u[0] < select;
        const float v = power ? u[0] / select : (u[0] - select) / (1 - select);
        const w17::Point w = direction(power ? std::pow(1 - v, 1 / (n + 1)) : std::sqrt(1 - v), 2 * kPi * u[1]);
        return {w, eval(w) / pdf(w)};
    }
};

// Weighted samplers over a grid of exponents (the twin over a grid of one).
void register_weighted_grid(warpcheck::Registry& registry) {
    w17::CaseInfo info;
    info.family = "phong_cxx17";
    info.description = "diffuse + power-cosine mixture with its weight, over a grid of exponents, from C++17";
    info.domain = w17::Domain::hemisphere();
    w17::add_case_grid(registry, info, {{"n", {5, 50}}}, [](const w17::GridPoint& p) {
        PhongMixture m;
        m.n = static_cast<float>(p["n"]);
        return m;
    });
    info.family = "phong_cxx17_wrong";
    w17::add_case_grid(registry, info, {{"n", {20}}}, [](const w17::GridPoint& p) {
        PhongMixture m;
        m.n = static_cast<float>(p["n"]);
        m.pdf_select = 0.5f;
        return m;
    });
}

// Float samplers of raw bits on the exhaustive check's fast path: the top 24
// of 32 bits on the 2^-24 grid of [0,1), and the top 23 of 64 bits as every
// float of [1,2), each value equally often and in order. The twins swap
// neighbouring values: every float is still counted equally (the statistics
// cannot see it), but the monotone order they claim is broken.
struct UnitFloat32 {
    bool swap_neighbours = false;
    float sample(std::uint32_t u) const {
        return static_cast<float>((u >> 8) ^ (swap_neighbours ? 1u : 0u)) * 0x1p-24f;
    }
    float pdf(float x) const { return x >= 0 && x < 1 ? 1.0f : 0.0f; }
};
struct OneToTwo64 {
    bool swap_neighbours = false;
    float sample(std::uint64_t u) const {
        return 1 + static_cast<float>((u >> 41) ^ (swap_neighbours ? 1u : 0u)) * 0x1p-23f;
    }
    float pdf(float x) const { return x >= 1 && x < 2 ? 1.0f : 0.0f; }
};

void register_float_samplers(warpcheck::Registry& registry) {
    for (bool wrong : {false, true}) {
        w17::CaseInfo info;
        info.family = wrong ? "unit_float_cxx17_swapped" : "unit_float_cxx17";
        info.description = "float in [0,1) from the top 24 of 32 random bits, from C++17";
        info.domain = w17::Domain::interval(0, 1);
        w17::add_u32_float_case(registry, info, w17::Monotone::Claimed, UnitFloat32{wrong});
        info.family = wrong ? "one_to_two_cxx17_swapped" : "one_to_two_cxx17";
        info.description = "every float of [1,2) from the top 23 of 64 random bits, swept over those bits, from C++17";
        info.domain = w17::Domain::interval(1, 2);
        w17::U64Subrange top23;
        top23.shift = 41;
        w17::add_u64_float_case(registry, info, top23, w17::Monotone::Claimed, OneToTwo64{wrong});
    }
}

// A renderer's RGB diffuse in C++17 (albedo per channel, cosine-weighted wi
// whichever channel is the hero): every BSDF check runs on each hero channel,
// bsdf_spectral on the others' values at its samples. Its wrong twin's
// sampled green value is 0.5% high, seen from the red hero's samples.
struct DiffuseRgb17 {
    std::array<float, 3> albedo;
    float green_scale = 1.0f;
    w17::SpectralBsdfSample<3> sample(const w17::Point& wo, float, const w17::Point2& u, int) const {
        const w17::BsdfSample s = Diffuse17{1.0f, false}.sample(wo, u);
        w17::SpectralBsdfSample<3> out;
        if (!(s.pdf > 0)) return out;
        out.wi = s.wi;
        for (int c = 0; c < 3; ++c) out.f[c] = albedo[c] * kInvPi, out.pdf[c] = s.pdf;
        out.f[1] *= green_scale;
        return out;
    }
    std::array<float, 3> f(const w17::Point& wo, const w17::Point& wi) const {
        const float cosine = wo[2] * wi[2] > 0 ? kInvPi : 0.0f;
        return {albedo[0] * cosine, albedo[1] * cosine, albedo[2] * cosine};
    }
    std::array<float, 3> pdf(const w17::Point& wo, const w17::Point& wi) const {
        const float p = static_cast<float>(Diffuse17{1.0f, false}.pdf(wo, wi));
        return {p, p, p};
    }
};

void register_spectral(warpcheck::Registry& registry) {
    for (bool wrong : {false, true}) {
        w17::BsdfInfo base;
        base.family = wrong ? "rgb_cxx17_green_high" : "rgb_cxx17";
        base.description = "a renderer's RGB diffuse, one case per hero channel, registered from C++17";
        const std::vector<double> heroes = wrong ? std::vector<double>{0} : std::vector<double>{0, 1, 2};
        w17::add_spectral_bsdf_grid(registry, base, {{"theta_o", {40}}, {"hero", heroes}},
                                    [wrong](const w17::GridPoint&) {
                                        return DiffuseRgb17{{0.7f, 0.5f, 0.3f}, wrong ? 1.005f : 1.0f};
                                    });
    }
}

// A renderer's sphere light in C++17, seen from the origin: uniform over the
// cone that subtends the sphere, pdf(ref, wi) and L(ref, wi) from the ray's
// intersection. Its wrong twin returns twice the radiance its own L() finds.
struct SphereLight17 {
    w17::Point c;
    float r, le;
    bool wrong = false;

    static float dot(const w17::Point& a, const w17::Point& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
    w17::Point to_centre(const w17::Point& ref) const { return {c[0] - ref[0], c[1] - ref[1], c[2] - ref[2]}; }
    float one_minus_cos_max(const w17::Point& ref) const {
        const w17::Point oc = to_centre(ref);
        const float s2 = r * r / dot(oc, oc);
        return s2 / (1 + std::sqrt(1 - s2));
    }
    bool hits(const w17::Point& ref, const w17::Point& wi) const {
        const w17::Point oc = to_centre(ref);
        const float b = dot(oc, wi);
        return b > 0 && dot(oc, oc) - b * b <= r * r;
    }
    w17::LightSample sample(const w17::Point& ref, const w17::Point2& u) const {
        const w17::Point oc = to_centre(ref);
        const float d = std::sqrt(dot(oc, oc)), omc_max = one_minus_cos_max(ref);
        const w17::Point a{oc[0] / d, oc[1] / d, oc[2] / d};
        // An orthonormal frame around a (Duff et al. 2017).
        const float sign = std::copysign(1.0f, a[2]), p = -1 / (sign + a[2]), q = a[0] * a[1] * p;
        const w17::Point t{1 + sign * a[0] * a[0] * p, sign * q, -sign * a[0]}, b{q, sign + a[1] * a[1] * p, -a[1]};
        const float omc = u[0] * omc_max, st = std::sqrt(omc * (2 - omc)), phi = 2 * kPi * u[1];
        const float x = st * std::cos(phi), y = st * std::sin(phi), z = 1 - omc;
        w17::LightSample s;
        s.wi = {x * t[0] + y * b[0] + z * a[0], x * t[1] + y * b[1] + z * a[1], x * t[2] + y * b[2] + z * a[2]};
        s.pdf = 1 / (2 * kPi * omc_max);
        s.L = wrong ? 2 * le : le;
        s.distance = d - r;
        return s;
    }
    double pdf(const w17::Point& ref, const w17::Point& wi) const {
        return hits(ref, wi) ? 1 / (2 * kPi * one_minus_cos_max(ref)) : 0.0;
    }
    double L(const w17::Point& ref, const w17::Point& wi) const { return hits(ref, wi) ? le : 0.0; }
};

void register_lights(warpcheck::Registry& registry) {
    for (bool wrong : {false, true}) {
        w17::LightInfo info;
        info.family = wrong ? "sphere_light_cxx17_double_radiance" : "sphere_light_cxx17";
        info.description = "a renderer's sphere light seen from the origin, registered from C++17";
        info.ref = {0, 0, 0};
        info.normal = {0, 0, 1};
        w17::add_light(registry, info, SphereLight17{{2.0f, 0.0f, 3.4641016f}, 1.0f, 2.0f, wrong});
    }
}

// The shading point of the MIS cases: the diffuse BSDF seen from wo at 40
// degrees, and a light's description seen from the origin with the normal +z.
w17::BsdfInfo shading_bsdf() {
    w17::BsdfInfo bsdf;
    bsdf.family = "diffuse_cxx17";
    bsdf.wo = w17::bsdf_direction(40.0, 180.0);
    return bsdf;
}
w17::LightInfo seen_from_origin(const char* family) {
    w17::LightInfo at;
    at.family = family;
    at.normal = {0, 0, 1};
    return at;
}

// Direct lighting as the renderer combines it: the diffuse BSDF and the
// sphere light at the origin, power heuristic. The wrong twin's MIS code
// evaluates the light's pdf per area of the sphere's silhouette disk, 1 /
// (pi r^2), where its sampler returns a density per solid angle.
void register_mis(warpcheck::Registry& registry) {
    const SphereLight17 light{{2.0f, 0.0f, 3.4641016f}, 1.0f, 2.0f};
    for (bool wrong : {false, true}) {
        w17::MisInfo info;
        info.family = wrong ? "direct_cxx17_area_pdf" : "direct_cxx17";
        info.description = "a diffuse BSDF and a sphere light combined by MIS, registered from C++17";
        std::function<double(const w17::Point&, const w17::Point&)> area_pdf;
        if (wrong)
            area_pdf = [light](const w17::Point& ref, const w17::Point& wi) {
                return light.hits(ref, wi) ? 1 / (kPi * light.r * light.r) : 0.0;
            };
        w17::add_mis(registry, info, shading_bsdf(), Diffuse17{0.6f, false}, seen_from_origin("sphere_light_cxx17"),
                     light, area_pdf);
    }
    // Two sphere lights, one MIS sum: the wrong twin's second light has the
    // first one's pdf in the sum (a light index mixed up in the MIS code).
    const SphereLight17 second{{-2.0f, 1.0f, 3.0f}, 0.5f, 4.0f};
    for (bool wrong : {false, true}) {
        w17::MisInfo info;
        info.family = wrong ? "direct_two_lights_cxx17_pdf_swapped" : "direct_two_lights_cxx17";
        info.description = "a diffuse BSDF and two sphere lights combined by MIS, registered from C++17";
        std::function<double(const w17::Point&, const w17::Point&)> swapped;
        if (wrong) swapped = [light](const w17::Point& ref, const w17::Point& wi) { return light.pdf(ref, wi); };
        w17::add_mis(registry, info, shading_bsdf(), Diffuse17{0.6f, false},
                     {w17::mis_light(seen_from_origin("sphere_light_cxx17"), light),
                      w17::mis_light(seen_from_origin("small_sphere_light_cxx17"), second, swapped)});
    }
}

}  // namespace

void warpcheck_register(warpcheck::Registry& registry) {
    register_logistic(registry);
    register_points(registry);
    register_discrete(registry);
    register_weighted_grid(registry);
    register_float_samplers(registry);
    register_bsdfs(registry);
    register_spectral(registry);
    register_lights(registry);
    register_mis(registry);
    // The wrong twins: known flaws, run by name (or with --include-flawed).
    for (const char* twin :
         {"cosine_cxx17_no_inverse_half_pdf", "cosine_cxx17_returned_pdf_wrong", "table_cxx17_no_pdf_wrong",
          "choice_cxx17_pmf_swapped", "choice_cxx17_remap_not_rescaled", "phong_cxx17_wrong[n=20]",
          "unit_float_cxx17_swapped", "one_to_two_cxx17_swapped", "sphere_light_cxx17_double_radiance",
          "direct_cxx17_area_pdf", "rgb_cxx17_green_high[theta_o=40,hero=0]",
          "direct_two_lights_cxx17_pdf_swapped"})
        w17::mark_known_flaw(registry, twin, "", "a wrong twin: run_example.sh checks that it fails");
}

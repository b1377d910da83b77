// A renderer that compiles as C++17 registers its warps in its own files
// through validate/api/register17.h alone; the program links warpcheck::main.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include <validate/api/register17.h>

static_assert(__cplusplus == 201703L, "this file proves that registration compiles as C++17");

namespace {

namespace w17 = warpcheck::cxx17;

// A renderer's diffuse BSDF in C++17: cosine-weighted wi, f = R / pi. Its
// wrong twin returns a sample whose weight misses |cos theta_i| (f / |cos|).
struct Diffuse17 {
    float r;
    bool wrong = false;
    static constexpr float kInvPi = 0.318309886f;
    double f(const w17::Point& wo, const w17::Point& wi) const { return wo[2] * wi[2] > 0 ? r * kInvPi : 0.0; }
    double pdf(const w17::Point& wo, const w17::Point& wi) const {
        return wo[2] * wi[2] > 0 ? std::abs(wi[2]) * kInvPi : 0.0;
    }
    w17::BsdfSample sample(const w17::Point& wo, const std::array<float, 2>& u) const {
        const float rad = std::sqrt(u[0]), phi = 6.28318531f * u[1];
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

void register_bsdfs(warpcheck::Registry& registry) {
    for (bool wrong : {false, true})
        for (double theta : {0.0, 70.0}) {
            const Diffuse17 bsdf{0.6f, wrong};
            w17::BsdfInfo info;
            info.family = wrong ? "diffuse_cxx17_weight_no_cos" : "diffuse_cxx17";
            info.params = {{"theta_o", theta}};
            info.description = "a renderer's diffuse BSDF, registered from C++17";
            info.wo = w17::bsdf_direction(theta);
            w17::add_bsdf(
                registry, info,
                [bsdf](const w17::Point& wo, float, const std::array<float, 2>& u) { return bsdf.sample(wo, u); },
                [bsdf](const w17::Point& wo, const w17::Point& wi) { return bsdf.f(wo, wi); },
                [bsdf](const w17::Point& wo, const w17::Point& wi) { return bsdf.pdf(wo, wi); });
            if (wrong)
                w17::mark_known_flaw(registry, "diffuse_cxx17_weight_no_cos[theta_o=" + std::to_string(int(theta)) + "]",
                                     "", "the sampled weight misses |cos theta_i|");
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

}  // namespace

void warpcheck_register(warpcheck::Registry& registry) {
    namespace w17 = warpcheck::cxx17;
    const Logistic warp{-3.0f, 0.25f};
    w17::CaseInfo info;
    info.family = "logistic_cxx17";
    info.params = {{"mu", -3}, {"s", 0.25}};
    info.description = "logistic distribution on the real line, registered from C++17";
    info.input = w17::Input::Uniform1D;
    info.domain = w17::Domain::real_line();
    w17::View x;  // truncated where 1e-4 of the mass lies beyond each end
    x.lo = -3 - 0.25 * std::log(1e4 - 1);
    x.hi = -3 + 0.25 * std::log(1e4 - 1);
    x.lower_tail_mass = x.tail_mass = 1e-4;
    x.label = "x";
    info.views = {x};
    w17::add_case(
        registry, info, [warp](const w17::WarpInput& u) { return w17::Point{warp.sample(u.u[0]), 0, 0}; },
        [warp](const w17::Point& p) { return warp.pdf(p[0]); },
        [warp](const w17::Point& p) { return w17::WarpInput{{warp.invert(p[0]), 0}, 0}; });
    register_bsdfs(registry);
}

// A renderer's own warps, validated by warpcheck without forking it: one of
// each kind the case API takes, each correct and with a wrong twin (registered
// as a known flaw, so that --all passes; run_example.sh runs each twin by name
// and asserts that the check meant to catch it fails).
#include <cmath>
#include <numbers>

#include <chi2/domain_kinds.h>
#include <validate/external.h>

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
             .input = warpcheck::InputKind::Uniform1D,
             .domain = warpcheck::chi2::Domain::real_line(),
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
             .input = warpcheck::InputKind::Uniform1D,
             .domain = warpcheck::chi2::Domain::lower_half_line(1),
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
             .domain = warpcheck::chi2::Domain::hemisphere()},
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
        return w[0] == 0 && w[1] == 0 ? std::nan("") : warpcheck::chi2::exact_phi(w[0], w[1]);  // NaN at a pole
    };
    azimuth.pdf = [](double) { return 1 / (2 * kPi); };
    for (bool wrong : {false, true}) {
        registry.add_case(warpcheck::make_warp_case(
            {.family = wrong ? "uniform_sphere_azimuth_bent" : "uniform_sphere",
             .description = "uniform directions, with a cos theta view and an azimuth view",
             .domain = warpcheck::chi2::Domain::sphere(),
             .views = {cos_theta, azimuth}},
            UniformSphereTwoViews{wrong ? 1e-3f : 0.0f}));
    }
}

}  // namespace

void warpcheck_register(warpcheck::Registry& registry) {
    register_linear(registry);
    register_normal(registry);
    register_mirrored_exponential(registry);
    register_no_inverse(registry);
    register_sphere_views(registry);
    // The wrong twins: known flaws, run by name (or with --include-flawed).
    registry.mark_known_flaw("normal_pdf_forgets_sigma[mu=2,sigma=0.5]", "the density lacks its 1/sigma");
    registry.mark_known_flaw("mirrored_exponential_inverse_flipped[b=1,rate=4]", "invert returns 1 - u");
    registry.mark_known_flaw("cosine_hemisphere_no_inverse_half_pdf", "the density integrates to 1/2");
    registry.mark_known_flaw("uniform_sphere_azimuth_bent", "phi bent by 1e-3 of a turn");
}

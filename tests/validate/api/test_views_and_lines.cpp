// Several 1D views per case, and 1D warps on the whole real line and on
// (-inf, b]: correct warps pass the tabulated, unbinned and chi2 checks, and a
// wrong twin fails the check (and the view) meant to catch it.
#include <cmath>
#include <numbers>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "chi2/domain_kinds.h"
#include "support/check_harness.h"
#include "validate/checks/checks.h"

namespace warpcheck {
namespace {

using ::testing::HasSubstr;
using testing::run_check;

// Uniform over the sphere, z = 1 - 2 u.x and phi = 2 pi u.y, or with `bend`
// moving azimuth mass: phi = 2 pi (u.y + bend sin(2 pi u.y)) / ... (cos theta untouched).
Vector3f sphere_sample(Point2f u, float bend) {
    const float z = 1.0f - 2.0f * u.x, r = std::sqrt(std::fmax(0.0f, 1.0f - z * z));
    const float t = u.y + bend * std::sin(2.0f * std::numbers::pi_v<float> * u.y);
    const float phi = 2.0f * std::numbers::pi_v<float> * t;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

MonotoneMarginal cos_theta_view() {
    MonotoneMarginal m;
    m.increasing = false;
    m.lo = -1.0;
    m.label = "cos theta";
    m.coordinate = [](const WarpOutput& o) { return static_cast<double>(o[2]); };
    m.pdf = [](double) { return 0.5; };
    return m;
}

MonotoneMarginal azimuth_view() {
    MonotoneMarginal m;
    m.input_coordinate = 1;
    m.hi = 2.0 * std::numbers::pi;
    m.label = "phi";
    m.coordinate = [](const WarpOutput& o) {
        return o[0] == 0.0f && o[1] == 0.0f ? std::nan("") : chi2::exact_phi(o[0], o[1]);
    };
    m.pdf = [](double) { return 0.5 / std::numbers::pi; };
    return m;
}

std::unique_ptr<WarpCase> sphere_case(float bend, std::vector<MonotoneMarginal> views) {
    return make_warp_case({.family = "sphere", .domain = chi2::Domain::sphere(), .views = std::move(views)},
                          warp_of([bend](Point2f u) { return sphere_sample(u, bend); })
                              .with_pdf([](Vector3f) { return static_cast<float>(0.25 / std::numbers::pi); }));
}

TEST(Views, EachViewIsTabulatedAndNamed) {
    const auto check = make_tabulated_check();
    const CheckResult good = run_check(*check, *sphere_case(0.0f, {cos_theta_view(), azimuth_view()}));
    EXPECT_EQ(good.verdict, Verdict::Pass) << good.message;
    EXPECT_EQ(*good.figure("views"), 2.0);
    EXPECT_TRUE(good.figure("phi_max_x_error_over_tolerance").has_value());
    EXPECT_TRUE(good.figure("cos_theta_max_x_error_over_tolerance").has_value());
    EXPECT_THAT(good.plots.back().title, HasSubstr("(view phi)"));

    // A 1e-3 azimuth error: invisible in cos theta, caught in the azimuth view, which the message names.
    const CheckResult cos_only = run_check(*check, *sphere_case(1e-3f, {cos_theta_view()}));
    EXPECT_EQ(cos_only.verdict, Verdict::Pass) << cos_only.message;
    const CheckResult both = run_check(*check, *sphere_case(1e-3f, {cos_theta_view(), azimuth_view()}));
    EXPECT_EQ(both.verdict, Verdict::Fail);
    EXPECT_THAT(both.message, HasSubstr("view phi:"));
    EXPECT_THAT(both.message, Not(HasSubstr("view cos theta:")));
}

// The standard normal by inversion: Abramowitz & Stegun 26.2.23 as the start,
// then Newton steps on Phi(x) = p in double, in the lower tail (p = min(u, 1-u)).
double lower_normal_quantile(double p) {
    const double t = std::sqrt(-2.0 * std::log(p));
    double x = -(t - (2.515517 + 0.802853 * t + 0.010328 * t * t) /
                         (1.0 + 1.432788 * t + 0.189269 * t * t + 0.001308 * t * t * t));
    for (int k = 0; k < 3; ++k) {
        const double cdf = 0.5 * std::erfc(-x / std::sqrt(2.0));
        const double pdf = std::exp(-0.5 * x * x) / std::sqrt(2.0 * std::numbers::pi);
        x -= (cdf - p) / pdf;
    }
    return x;
}

struct Normal {
    float mu, sigma, pdf_scale = 1.0f;
    float invert(float x) const {
        return std::fmin(static_cast<float>(0.5 * std::erfc(-(x - mu) / (sigma * std::sqrt(2.0)))), 0x1.fffffep-1f);
    }
    float sample(float u) const {
        const double p = std::max(std::min<double>(u, 1.0 - u), 0x1p-65);  // u = 0: half the smallest step
        const double z = lower_normal_quantile(p);
        return static_cast<float>(mu + sigma * (u < 0.5f ? z : -z));
    }
    float pdf(float x) const {
        const double z = (x - mu) / sigma;
        return static_cast<float>(pdf_scale * std::exp(-0.5 * z * z) / (sigma * std::sqrt(2.0 * std::numbers::pi)));
    }
};

std::unique_ptr<WarpCase> normal_case(Normal n) {
    MonotoneMarginal view;  // 4 sigma either side; Phi(-4) = 3.17e-5 beyond each end
    view.lo = n.mu - 4.0 * n.sigma;
    view.hi = n.mu + 4.0 * n.sigma;
    view.lower_tail_mass = view.tail_mass = 0.5 * std::erfc(4.0 / std::sqrt(2.0));
    view.label = "x";
    return make_warp_case({.family = "normal", .domain = chi2::Domain::real_line(),
                           .views = {view}},
                          n);
}

TEST(RealLine, NormalPassesAndAScaleErrorFails) {
    for (auto make : {make_tabulated_check, make_chi2_check, make_unbinned_check, make_consistency_check,
                      make_roundtrip_check}) {
        const auto check = make();
        const CheckResult r = run_check(*check, *normal_case({100.0f, 0.01f}), 1'000'000);
        EXPECT_EQ(r.verdict, Verdict::Pass) << check->name() << ": " << r.message;
        EXPECT_GE(r.p_value.value_or(1.0), 1e-3) << check->name();
    }
    const auto tabulated = make_tabulated_check();
    const CheckResult r = run_check(*tabulated, *normal_case({100.0f, 0.01f}), 1'000'000);
    EXPECT_GT(*r.figure("tail_samples"), 20.0);  // both tails are exercised
    // A density 1% too high fails the tabulated check's normalisation.
    const CheckResult wrong = run_check(*tabulated, *normal_case({100.0f, 0.01f, 1.01f}));
    EXPECT_EQ(wrong.verdict, Verdict::Fail);
    EXPECT_THAT(wrong.message, HasSubstr("integrates to"));
    // The chi2 check centres its cells on the distribution.
    const CheckResult chi2 = run_check(*make_chi2_check(), *normal_case({100.0f, 0.01f}), 1'000'000);
    EXPECT_NEAR(*chi2.figure("line_center"), 100.0, 0.01);
}

// x = b + log(1 - u) / rate on (-inf, b]: decreasing in u.
std::unique_ptr<WarpCase> mirrored_exponential(float b, float rate, float sample_rate) {
    MonotoneMarginal view;
    view.increasing = false;
    view.lo = b - 10.0 / rate;
    view.hi = b;
    view.lower_tail_mass = std::exp(-10.0);
    view.label = "x";
    return make_warp_case({.family = "mirrored_exponential", .domain = chi2::Domain::lower_half_line(b), .views = {view}},
                          warp_of([b, sample_rate](float u) { return b + std::log1p(-u) / sample_rate; })
                              .with_pdf([b, rate](float x) { return x > b ? 0.0f : rate * std::exp(rate * (x - b)); })
                              .with_invert([b, rate](float x) { return -std::expm1(rate * (x - b)); }));
}

TEST(LowerHalfLine, MirroredExponentialPassesAndARateErrorFails) {
    for (auto make : {make_tabulated_check, make_chi2_check, make_unbinned_check, make_consistency_check}) {
        const auto check = make();
        const CheckResult r = run_check(*check, *mirrored_exponential(2.0f, 3.0f, 3.0f), 1'000'000);
        EXPECT_EQ(r.verdict, Verdict::Pass) << check->name() << ": " << r.message;
        EXPECT_GE(r.p_value.value_or(1.0), 1e-3) << check->name();
    }
    const CheckResult wrong = run_check(*make_tabulated_check(), *mirrored_exponential(2.0f, 3.0f, 3.03f));
    EXPECT_EQ(wrong.verdict, Verdict::Fail);
    const CheckResult wrong_chi2 = run_check(*make_chi2_check(), *mirrored_exponential(2.0f, 3.0f, 3.03f), 1'000'000);
    EXPECT_LT(*wrong_chi2.p_value, 1e-6);
}

}  // namespace
}  // namespace warpcheck

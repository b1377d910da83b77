// The coated BSDF's random walks (sampling/bsdf_layered.h) against the closed
// form of a smooth coat over a Lambertian base, computed here in double:
//     f = T(wo) T(wi) R / (pi eta^2 (1 - R r_i)),
// r_i = 2 * integral over [0, 1] of mu F_inside(mu) dmu, the coat's cosine-weighted
// internal reflectance. The walk's f averaged over its seeds, and the
// sampler's mean weight, must meet it within their measured noise; the
// planted flaws must not.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>

#include "sampling/bsdf_diffuse.h"
#include "sampling/bsdf_layered.h"
#include "sampling/pcg32.h"

namespace warpcheck {
namespace {

/// Fresnel reflectance of a smooth dielectric in double: cos_i on the side it
/// arrives from, eta the index of the far side over the near one.
double fresnel(double cos_i, double eta) {
    const double sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0) return 1.0;
    const double cos_t = std::sqrt(1.0 - sin2_t);
    const double a = (eta * cos_i - cos_t) / (eta * cos_i + cos_t), b = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5 * (a * a + b * b);
}

/// r_i by the midpoint rule on 2^16 intervals (the integrand's kink at the
/// critical angle costs at most one interval's width, 1.5e-5, times its jump 0).
double internal_reflectance(double eta) {
    constexpr int kSteps = 1 << 16;
    double sum = 0.0;
    for (int k = 0; k < kSteps; ++k) {
        const double mu = (k + 0.5) / kSteps;
        sum += mu * fresnel(mu, 1.0 / eta);
    }
    return 2.0 * sum / kSteps;
}

double closed_form_f(double R, double eta, double cos_o, double cos_i, double r_i) {
    return (1.0 - fresnel(cos_o, eta)) * (1.0 - fresnel(cos_i, eta)) * R /
           (std::numbers::pi * eta * eta * (1.0 - R * r_i));
}

double closed_form_f(double R, double eta, double cos_o, double cos_i) {
    return closed_form_f(R, eta, cos_o, cos_i, internal_reflectance(eta));
}

/// The integral of the closed form's f |cos theta_i| over the hemisphere.
double closed_form_albedo(double R, double eta, double cos_o) {
    constexpr int kSteps = 1 << 14;
    const double r_i = internal_reflectance(eta);
    double sum = 0.0;
    for (int k = 0; k < kSteps; ++k) {
        const double mu = (k + 0.5) / kSteps;
        sum += closed_form_f(R, eta, cos_o, mu, r_i) * mu;
    }
    return 2.0 * std::numbers::pi * sum / kSteps;
}

/// A running mean and variance (Welford); sampling/ tests do not link chi2/.
struct Moments {
    double n = 0.0, mean = 0.0, m2 = 0.0;
    void add(double x) {
        n += 1.0;
        const double d = x - mean;
        mean += d / n;
        m2 += d * (x - mean);
    }
    double standard_error() const { return std::sqrt(m2 / (n - 1.0) / n); }
};

Vector3f direction(double cos_theta, double phi) {
    const double s = std::sqrt(1.0 - cos_theta * cos_theta);
    return {static_cast<float>(s * std::cos(phi)), static_cast<float>(s * std::sin(phi)), static_cast<float>(cos_theta)};
}

/// The mean of f(wo, wi) over `seeds` coats that differ only in their seed.
Moments f_over_seeds(float R, float eta, Vector3f wo, Vector3f wi, int seeds, CoatFlaw flaw = CoatFlaw::None) {
    Moments m;
    for (int s = 0; s < seeds; ++s)
        m.add(CoatedBsdf(Lambertian(R), eta, static_cast<uint64_t>(s) + 1, flaw).f(wo, wi));
    return m;
}

// Five standard errors: a correct walk fails one of these comparisons with
// probability below 6e-7 each; 1e-5 relative is the float computation's.
void expect_mean_is(const Moments& m, double reference) {
    const double se = m.standard_error();
    EXPECT_LE(std::abs(m.mean - reference), 5.0 * se + 1e-5 * reference) << "mean " << m.mean << " vs " << reference;
}

TEST(CoatedBsdf, TheWalksMeanFIsTheClosedFormOfACoatedLambertian) {
    for (const double R : {0.3, 0.8, 1.0})
        for (const double eta : {1.1, 1.5, 3.0})
            for (const auto& [co, ci] : {std::pair{1.0, 0.5}, std::pair{0.2, 0.9}, std::pair{0.05, 0.05}}) {
                const Moments m = f_over_seeds(static_cast<float>(R), static_cast<float>(eta), direction(co, 0.0),
                                                     direction(ci, 2.0), 20'000);
                SCOPED_TRACE(::testing::Message() << "R " << R << " eta " << eta << " cos " << co << " " << ci);
                expect_mean_is(m, closed_form_f(R, eta, co, ci));
            }
}

TEST(CoatedBsdf, TheSamplersMeanWeightIsTheClosedFormsAlbedoPlusTheCoatsReflection) {
    for (const double co : {1.0, 0.5, 0.1}) {
        const CoatedBsdf coat(Lambertian(0.8f), 1.5f);
        const Vector3f wo = direction(co, 1.0);
        Pcg32 rng(7, 11);
        Moments continuous, all;
        for (int k = 0; k < 400'000; ++k) {
            const BsdfSample s = coat.sample(wo, rng.next_float(), {rng.next_float(), rng.next_float()});
            const double w = s.pdf > 0.0f ? static_cast<double>(s.f) * std::abs(s.wi.z) / s.pdf : 0.0;
            continuous.add(has(s.flags, BsdfFlags::Delta) ? 0.0 : w);
            all.add(w);
        }
        SCOPED_TRACE(::testing::Message() << "cos theta_o " << co);
        expect_mean_is(continuous, closed_form_albedo(0.8, 1.5, co));
        expect_mean_is(all, closed_form_albedo(0.8, 1.5, co) + fresnel(co, 1.5));
    }
}

// The planted flaws move f by more than the comparison's noise: Schlick's
// transmittance at cos theta_o = 0.2 is 13% off the exact one, the dropped
// 1 / eta^2 multiplies the bouncing paths by 2.25.
TEST(CoatedBsdf, ThePlantedFlawsMissTheClosedForm) {
    const Vector3f wo = direction(0.2, 0.0), wi = direction(0.9, 2.0);
    const double reference = closed_form_f(0.8, 1.5, 0.2, 0.9);
    const Moments schlick = f_over_seeds(0.8f, 1.5f, wo, wi, 80'000, CoatFlaw::SchlickInF);
    EXPECT_GT(std::abs(schlick.mean - reference), 6.0 * schlick.standard_error());
    const Moments jacobian = f_over_seeds(0.8f, 1.5f, wo, wi, 80'000, CoatFlaw::JacobianInF);
    EXPECT_GT(jacobian.mean - reference, 6.0 * jacobian.standard_error());
}

TEST(CoatedBsdf, ASeedGivesTheSameEstimateForTheSamePairAndTheSameSampleForTheSameInput) {
    const CoatedBsdf coat(Lambertian(0.8f), 1.5f, 42);
    const Vector3f wo = direction(0.7, 0.0), wi = direction(0.4, 1.0);
    EXPECT_EQ(coat.f(wo, wi), coat.f(wo, wi));
    const BsdfSample a = coat.sample(wo, 0.5f, {0.25f, 0.75f}), b = coat.sample(wo, 0.5f, {0.25f, 0.75f});
    EXPECT_EQ(a.wi, b.wi);
    EXPECT_EQ(a.f, b.f);
    EXPECT_THROW(CoatedBsdf(Lambertian(0.5f), 1.0f), std::invalid_argument);
}

}  // namespace
}  // namespace warpcheck

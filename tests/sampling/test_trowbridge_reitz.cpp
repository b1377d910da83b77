// Trowbridge-Reitz: known values of D, Lambda and G1; normalisation of D cos and
// of the visible-normal density for every tested view; round trips of both warps
// at edge and random inputs; defined behaviour at grazing, below-horizon and
// smallest-alpha inputs.
#include <gtest/gtest.h>

#include <boost/math/quadrature/gauss_kronrod.hpp>

#include <cmath>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

#include "sampling/pcg32.h"
#include "sampling/trowbridge_reitz.h"

namespace warpcheck {
namespace {

using boost::math::quadrature::gauss_kronrod;

const std::vector<std::pair<float, float>> kAlphas = {{0.05f, 0.05f}, {0.3f, 0.3f}, {1.0f, 1.0f},
                                                       {0.3f, 0.05f},  {0.05f, 0.4f}};
const float kNormalEdges[] = {0.0f, 0x1p-24f, 0.25f, 0.5f, 0.75f, kOneMinusEpsilon};

Vector3f direction(double theta, double phi) {
    return {static_cast<float>(std::sin(theta) * std::cos(phi)), static_cast<float>(std::sin(theta) * std::sin(phi)),
            static_cast<float>(std::cos(theta))};
}

double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }

/// Integral over the hemisphere of f(w) dw, as iterated adaptive Gauss-Kronrod
/// quadrature in z = cos theta (outer) and phi (inner, over [0, 2 pi) split at
/// `phi_breaks(z)` where f has kinks). The peak of D near z = 1 for small alpha
/// is resolved by the outer adaptivity; the substitution z = 1 - s^2 spreads it.
/// The integrands are float functions (relative noise ~1e-7), so asking for more
/// than 1e-7 only makes the adaptive rule subdivide noise.
template <typename F, typename Breaks>
double integrate_hemisphere(F f, Breaks phi_breaks) {
    auto inner = [&](double s) {
        const double z = 1.0 - s * s, r = std::sqrt(std::max(0.0, 1.0 - z * z));
        std::vector<double> cuts = phi_breaks(z);
        cuts.insert(cuts.begin(), 0.0);
        cuts.push_back(2.0 * std::numbers::pi);
        double sum = 0.0;
        for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
            if (!(cuts[k + 1] > cuts[k])) continue;
            sum += gauss_kronrod<double, 31>::integrate(
                [&](double phi) {
                    return static_cast<double>(f(Vector3f{static_cast<float>(r * std::cos(phi)),
                                                          static_cast<float>(r * std::sin(phi)),
                                                          static_cast<float>(z)}));
                },
                cuts[k], cuts[k + 1], 4, 1e-7);
        }
        return 2.0 * s * sum;  // dz = 2 s ds
    };
    return gauss_kronrod<double, 31>::integrate(inner, 0.0, 1.0, 8, 1e-7);
}

auto no_breaks = [](double) { return std::vector<double>{}; };

/// For a view in the xz-plane, the azimuths where wo.wm = 0 at height z.
auto mask_breaks(Vector3f wo) {
    return [wo](double z) {
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        std::vector<double> out;
        if (wo.x == 0.0f || r == 0.0) return out;
        const double c = -static_cast<double>(wo.z) * z / (static_cast<double>(wo.x) * r);  // cos phi at the kink
        if (c > -1.0 && c < 1.0) {
            const double p = std::acos(c);
            out = {p, 2.0 * std::numbers::pi - p};
        }
        return out;
    };
}

// --- Parameters and known values ---------------------------------------------

TEST(TrowbridgeReitz, RejectsBadParameters) {
    for (float a : {0.0f, -0.1f, 1e-5f, 1e5f, std::nanf(""), std::numeric_limits<float>::infinity()}) {
        EXPECT_THROW(TrowbridgeReitz(a, 0.3f), std::invalid_argument) << a;
        EXPECT_THROW(TrowbridgeReitz(0.3f, a), std::invalid_argument) << a;
    }
    const TrowbridgeReitz tr(0.3f);
    EXPECT_THROW(tr.visible_normals({0.0f, 0.0f, 0.0f}), std::invalid_argument);
    EXPECT_THROW(tr.visible_normals({std::nanf(""), 0.0f, 1.0f}), std::invalid_argument);
    EXPECT_NO_THROW(TrowbridgeReitz{TrowbridgeReitz::kMinAlpha});
}

TEST(TrowbridgeReitz, KnownValues) {
    for (auto [ax, ay] : kAlphas) {
        const TrowbridgeReitz tr(ax, ay);
        const Vector3f n{0.0f, 0.0f, 1.0f};
        EXPECT_FLOAT_EQ(tr.G1(n), 1.0f);
        EXPECT_EQ(tr.lambda(n), 0.0f);
        EXPECT_FLOAT_EQ(tr.D(n), 1.0f / (kPi * ax * ay));  // the peak
        EXPECT_EQ(tr.G1({1.0f, 0.0f, 0.0f}), 0.0f);          // horizon
        EXPECT_EQ(tr.lambda({1.0f, 0.0f, 0.0f}), std::numeric_limits<float>::infinity());
        EXPECT_EQ(tr.D({0.0f, 0.6f, -0.8f}), 0.0f);
        Pcg32 rng(3, 4);
        for (int i = 0; i < 1000; ++i) {
            const Vector3f w = direction(std::acos(rng.next_double()), 2.0 * std::numbers::pi * rng.next_double());
            EXPECT_NEAR(tr.G1(w), 1.0 / (1.0 + tr.lambda(w)), 1e-6);
            EXPECT_NEAR(tr.G1_over_cos(w) * w.z, tr.G1(w), 1e-6);
            // Lambda against its textbook form (sqrt(1 + alpha^2 tan^2) - 1) / 2, in double.
            const double tan2 = (1.0 - double(w.z) * w.z) / (double(w.z) * w.z);
            const double phi = std::atan2(w.y, w.x);
            const double a2 = std::pow(ax * std::cos(phi), 2) + std::pow(ay * std::sin(phi), 2);
            EXPECT_NEAR(tr.lambda(w), (std::sqrt(1.0 + a2 * tan2) - 1.0) / 2.0, 1e-5 * (1.0 + tr.lambda(w)));
        }
    }
    // Isotropic D against the tan form alpha^2 / (pi cos^4 (alpha^2 + tan^2)^2).
    const TrowbridgeReitz iso(0.3f);
    for (double theta : {0.1, 0.5, 1.0, 1.5}) {
        const double t2 = std::pow(std::tan(theta), 2), c4 = std::pow(std::cos(theta), 4);
        EXPECT_NEAR(iso.D(direction(theta, 0.7)), 0.09 / (std::numbers::pi * c4 * std::pow(0.09 + t2, 2)),
                    1e-5 * iso.D(direction(theta, 0.7)));
    }
}

// --- Normalisation -------------------------------------------------------------

TEST(TrowbridgeReitz, DCosIntegratesToOne) {
    for (auto [ax, ay] : kAlphas) {
        const TrowbridgeReitz tr(ax, ay);
        const double integral = integrate_hemisphere([&](Vector3f w) { return tr.normals().pdf(w); }, no_breaks);
        EXPECT_NEAR(integral, 1.0, 1e-5) << ax << " " << ay;
    }
}

TEST(TrowbridgeReitz, MarginalDensitiesIntegrateToOne) {
    for (double a : {0.05, 0.3, 1.0, 3.0}) {
        const double i = gauss_kronrod<double, 31>::integrate(
            [a](double z) { return TrowbridgeReitz::isotropic_cos_theta_pdf(a, z); }, 0.0, 1.0, 15, 1e-12);
        EXPECT_NEAR(i, 1.0, 1e-9) << a;
    }
    for (auto [ax, ay] : kAlphas) {
        const double i = gauss_kronrod<double, 31>::integrate(
            [ax = ax, ay = ay](double p) { return TrowbridgeReitz::azimuth_pdf(ax, ay, p); }, 0.0, 2.0 * std::numbers::pi, 15, 1e-12);
        EXPECT_NEAR(i, 1.0, 1e-9) << ax << " " << ay;
    }
}

TEST(TrowbridgeReitz, VisibleDensityIntegratesToOneForEveryView) {
    for (auto [ax, ay] : kAlphas) {
        const TrowbridgeReitz tr(ax, ay);
        for (double theta_o : {0.0, 30.0, 60.0, 85.0, 89.9, 90.0}) {
            const Vector3f wo = direction(radians(theta_o), 0.0);
            const auto vis = tr.visible_normals(wo);
            const double integral = integrate_hemisphere([&](Vector3f w) { return vis.pdf(w); }, mask_breaks(wo));
            EXPECT_NEAR(integral, 1.0, 1e-4) << ax << " " << ay << " theta_o=" << theta_o;
        }
    }
}

TEST(TrowbridgeReitz, VisibleDensityWithoutMaskIsNotNormalised) {
    // The common mistake |wo.wm| instead of max(0, wo.wm): back-facing normals add mass.
    const TrowbridgeReitz tr(1.0f);
    const Vector3f wo = direction(radians(85.0), 0.0);
    const float g1_over_cos = tr.G1_over_cos(wo);
    const double integral = integrate_hemisphere(
        [&](Vector3f w) { return g1_over_cos * std::abs(dot(wo, w)) * tr.D(w); }, mask_breaks(wo));
    EXPECT_GT(integral, 1.1);
}

TEST(TrowbridgeReitz, VisibleNormalsAtNormalIncidenceAreDCos) {
    const TrowbridgeReitz tr(0.3f, 0.05f);
    const auto vis = tr.visible_normals({0.0f, 0.0f, 1.0f});
    Pcg32 rng(5, 6);
    for (int i = 0; i < 1000; ++i) {
        const Vector3f w = tr.normals().sample({rng.next_float(), rng.next_float()});
        EXPECT_NEAR(vis.pdf(w), tr.normals().pdf(w), 1e-5 * tr.normals().pdf(w));
    }
}

TEST(TrowbridgeReitz, ViewBelowHorizonIsMirrored) {
    const TrowbridgeReitz tr(0.3f, 0.05f);
    const Vector3f wo = direction(radians(60.0), 0.4);
    const auto below = tr.visible_normals(-1.0f * wo);
    const auto above = tr.visible_normals(wo);
    EXPECT_EQ(below.wo(), above.wo());
    const Point2f u{0.3f, 0.7f};
    EXPECT_EQ(below.sample(u), above.sample(u));
}

// --- Round trips and consistency --------------------------------------------------

// |invert(sample(u)) - u| within 2^-16, or (where the map is not injective, as at
// the pole u.x = 0 of the normal warp) sample(invert(x)) == x within 1e-6.
template <typename Sample, typename Invert>
void expect_round_trip(Sample sample, Invert invert, Point2f u, const char* what) {
    const Vector3f x = sample(u);
    const Point2f back = invert(x);
    const double du = std::max(std::abs(back.x - u.x), std::abs(back.y - u.y));
    if (du <= 0x1p-16) return;
    const Vector3f x2 = sample(back);
    EXPECT_LE(length(x2 - x), 1e-6f) << what << " u=(" << u.x << "," << u.y << ") back=(" << back.x << ","
                                     << back.y << ")";
}

TEST(TrowbridgeReitz, NormalRoundTrip) {
    for (auto [ax, ay] : kAlphas) {
        const TrowbridgeReitz tr(ax, ay);
        auto s = [&](Point2f u) { return tr.normals().sample(u); };
        auto i = [&](Vector3f w) { return tr.normals().invert(w); };
        for (float a : kNormalEdges)
            for (float b : kNormalEdges) expect_round_trip(s, i, {a, b}, "normal edge");
        Pcg32 rng(1, 2);
        for (int k = 0; k < 200000; ++k) expect_round_trip(s, i, {rng.next_float(), rng.next_float()}, "normal");
    }
}

TEST(TrowbridgeReitz, VisibleRoundTripAndConsistency) {
    for (auto [ax, ay] : kAlphas) {
        const TrowbridgeReitz tr(ax, ay);
        for (double theta_o : {0.0, 30.0, 60.0, 85.0, 90.0}) {
            for (double phi_o : {0.0, 2.0}) {
                const auto vis = tr.visible_normals(direction(radians(theta_o), phi_o));
                auto s = [&](Point2f u) { return vis.sample(u); };
                auto i = [&](Vector3f w) { return vis.invert(w); };
                auto consistent = [&](Point2f u) {
                    const Vector3f w = vis.sample(u);
                    const float p = vis.pdf(w);
                    EXPECT_NEAR(length(w), 1.0f, 1e-6f);
                    EXPECT_GE(w.z, 0.0f);
                    // A zero density only at the horizon (normal incidence, u on the disk's rim).
                    EXPECT_TRUE(std::isfinite(p) && (p > 0.0f || w.z == 0.0f))
                        << "theta_o=" << theta_o << " u=(" << u.x << "," << u.y << ") pdf=" << p;
                };
                for (float a : kNormalEdges)
                    for (float b : kNormalEdges) {
                        expect_round_trip(s, i, {a, b}, "visible edge");
                        consistent({a, b});
                    }
                Pcg32 rng(9, 10);
                for (int k = 0; k < 50000; ++k) {
                    const Point2f u{rng.next_float(), rng.next_float()};
                    expect_round_trip(s, i, u, "visible");
                    consistent(u);
                }
            }
        }
    }
}

TEST(TrowbridgeReitz, SmallestAlphaStaysFinite) {
    const TrowbridgeReitz tr(TrowbridgeReitz::kMinAlpha);
    Pcg32 rng(11, 12);
    for (double theta_o : {0.0, 60.0, 85.0, 90.0}) {
        const auto vis = tr.visible_normals(direction(radians(theta_o), 0.0));
        for (int k = 0; k < 10000; ++k) {
            const Point2f u{rng.next_float(), rng.next_float()};
            const Vector3f m = tr.normals().sample(u), v = vis.sample(u);
            EXPECT_TRUE(std::isfinite(tr.normals().pdf(m)) && tr.normals().pdf(m) > 0.0f);
            EXPECT_TRUE(std::isfinite(vis.pdf(v)));
            const Point2f back = tr.normals().invert(m);
            EXPECT_LE(std::max(std::abs(back.x - u.x), std::abs(back.y - u.y)), 1e-4f);
        }
    }
}

}  // namespace
}  // namespace warpcheck

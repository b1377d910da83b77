// The geometric warps: known values, normalisation, round trips, parameter checks.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>

#include "sampling/disk.h"
#include "sampling/hemisphere.h"
#include "sampling/pcg32.h"
#include "sampling/sphere.h"

namespace warpcheck {
namespace {

const float kGeometricEdges[] = {0.0f, 0x1p-24f, 0.5f, kOneMinusEpsilon};

// NaN-safe closeness: NaN is never near anything.
::testing::AssertionResult near(double a, double b, double tol) {
    if (std::abs(a - b) <= tol) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << a << " vs " << b << " (tolerance " << tol << ")";
}

// Integral of a density over the (phi, z) rectangle [0, 2pi) x [z0, 1], midpoint
// rule on a fine grid; dA = dphi dz on the unit sphere.
double integrate_spherical(const std::function<float(Vector3f)>& pdf, double z0, int n = 800) {
    double sum = 0.0;
    const double dz = (1.0 - z0) / n, dphi = 2.0 * std::numbers::pi / n;
    for (int i = 0; i < n; ++i) {
        const double z = z0 + (i + 0.5) * dz, r = std::sqrt(1.0 - z * z);
        for (int j = 0; j < n; ++j) {
            const double phi = (j + 0.5) * dphi;
            sum += pdf({static_cast<float>(r * std::cos(phi)), static_cast<float>(r * std::sin(phi)),
                        static_cast<float>(z)});
        }
    }
    return sum * dz * dphi;
}

// Integral over the unit disk in polar coordinates (dA = r dr dphi).
double integrate_disk(const std::function<float(Point2f)>& pdf, int n = 800) {
    double sum = 0.0;
    const double dr = 1.0 / n, dphi = 2.0 * std::numbers::pi / n;
    for (int i = 0; i < n; ++i) {
        const double r = (i + 0.5) * dr;
        for (int j = 0; j < n; ++j) {
            const double phi = (j + 0.5) * dphi;
            sum += r * pdf({static_cast<float>(r * std::cos(phi)), static_cast<float>(r * std::sin(phi))});
        }
    }
    return sum * dr * dphi;
}

TEST(Disk, ConcentricKnownValues) {
    EXPECT_EQ(UniformDiskConcentric{}.sample({0.5f, 0.5f}), (Point2f{0.0f, 0.0f}));
    const Point2f right = UniformDiskConcentric{}.sample({1.0f, 0.5f});
    EXPECT_TRUE(near(right.x, 1.0, 1e-7));
    EXPECT_TRUE(near(right.y, 0.0, 1e-7));
    const Point2f top = UniformDiskConcentric{}.sample({0.5f, 1.0f});
    EXPECT_TRUE(near(top.x, 0.0, 1e-7));
    EXPECT_TRUE(near(top.y, 1.0, 1e-7));
    // The square's corner (1,1) maps to the disk at 45 degrees.
    const Point2f corner = UniformDiskConcentric{}.sample({1.0f, 1.0f});
    EXPECT_TRUE(near(corner.x, std::sqrt(0.5), 1e-6));
    EXPECT_TRUE(near(corner.y, std::sqrt(0.5), 1e-6));
}

TEST(Disk, DensitiesIntegrateToOne) {
    EXPECT_TRUE(near(integrate_disk([](Point2f x) { return UniformDiskConcentric{}.pdf(x); }), 1.0, 1e-3));
    EXPECT_TRUE(near(integrate_disk([](Point2f x) { return UniformDiskPolar{}.pdf(x); }), 1.0, 1e-3));
}

// u.y is the azimuth phi / (2 pi) for every warp here but the concentric disk,
// so it is periodic: u.y just below 1 and 0 name the same directions (float
// 2 pi * u.y can round past 2 pi), and the distance is measured around the circle.
template <typename Sample, typename Invert>
void expect_round_trip(Sample sample, Invert invert, double tol, bool periodic_y = true) {
    Pcg32 rng(11, 5);
    auto one = [&](Point2f u) {
        const Point2f back = invert(sample(u));
        double dy = std::abs(static_cast<double>(back.y) - u.y);
        if (periodic_y) dy = std::min(dy, 1.0 - dy);
        EXPECT_TRUE(near(back.x, u.x, tol)) << "u = (" << u.x << ", " << u.y << ")";
        EXPECT_TRUE(near(dy, 0.0, tol)) << "u = (" << u.x << ", " << u.y << ") -> " << back.y;
    };
    for (int i = 0; i < 20000; ++i) {
        const float a = rng.next_float();
        one({a, rng.next_float()});
    }
    // Edges where the warp is injective: away from the centre / poles.
    for (float a : {0x1p-24f, 0.25f, kOneMinusEpsilon})
        for (float b : kGeometricEdges) one({a, b});
}

TEST(Disk, RoundTrips) {
    expect_round_trip([](Point2f u) { return UniformDiskPolar{}.sample(u); },
                      [](Point2f x) { return UniformDiskPolar{}.invert(x); }, 1e-5);
    expect_round_trip([](Point2f u) { return UniformDiskConcentric{}.sample(u); },
                      [](Point2f x) { return UniformDiskConcentric{}.invert(x); }, 1e-5, false);
}

TEST(Hemisphere, KnownValues) {
    EXPECT_FLOAT_EQ(CosineHemisphere{}.pdf({0.0f, 0.0f, 1.0f}), static_cast<float>(1.0 / std::numbers::pi));
    EXPECT_FLOAT_EQ(UniformHemisphere{}.pdf({0.0f, 0.0f, 1.0f}), static_cast<float>(0.5 / std::numbers::pi));
    EXPECT_EQ(CosineHemisphere{}.pdf({0.0f, 0.0f, -1.0f}), 0.0f);
    EXPECT_EQ(UniformHemisphere{}.pdf({0.0f, 0.0f, -0.5f}), 0.0f);
    // The centre of the square is the pole for the cosine warp.
    const Vector3f pole = CosineHemisphere{}.sample({0.5f, 0.5f});
    EXPECT_EQ(pole, (Vector3f{0.0f, 0.0f, 1.0f}));
    const Vector3f v = UniformHemisphere{}.sample({0.25f, 0.25f});
    EXPECT_TRUE(near(v.z, 0.25, 1e-7));
    EXPECT_TRUE(near(v.x, 0.0, 1e-6));
    EXPECT_TRUE(near(v.y, std::sqrt(1.0 - 0.0625), 1e-6));
}

TEST(Hemisphere, DensitiesIntegrateToOne) {
    EXPECT_TRUE(near(integrate_spherical([](Vector3f x) { return UniformHemisphere{}.pdf(x); }, 0.0), 1.0, 1e-4));
    EXPECT_TRUE(near(integrate_spherical([](Vector3f x) { return CosineHemisphere{}.pdf(x); }, 0.0), 1.0, 1e-4));
    for (float n : {0.0f, 1.0f, 7.5f}) {
        const CosinePowerHemisphere lobe(n);
        EXPECT_TRUE(near(integrate_spherical([&](Vector3f w) { return lobe.pdf(w); }, 0.0), 1.0, 1e-3)) << n;
    }
}

TEST(Hemisphere, CosinePowerMatchesItsSpecialCases) {
    const CosinePowerHemisphere one(1.0f);
    EXPECT_FLOAT_EQ(one.pdf({0.6f, 0.0f, 0.8f}), CosineHemisphere{}.pdf({0.6f, 0.0f, 0.8f}));
    const CosinePowerHemisphere zero(0.0f);
    EXPECT_FLOAT_EQ(zero.pdf({0.6f, 0.0f, 0.8f}), UniformHemisphere{}.pdf({0.6f, 0.0f, 0.8f}));
}

TEST(Hemisphere, RoundTrips) {
    expect_round_trip([](Point2f u) { return UniformHemisphere{}.sample(u); },
                      [](Vector3f x) { return UniformHemisphere{}.invert(x); }, 1e-5);
    expect_round_trip([](Point2f u) { return CosineHemisphere{}.sample(u); },
                      [](Vector3f x) { return CosineHemisphere{}.invert(x); }, 1e-5, false);
    const CosinePowerHemisphere lobe(4.0f);
    expect_round_trip([&](Point2f u) { return lobe.sample(u); }, [&](Vector3f v) { return lobe.invert(v); }, 1e-5);
}

TEST(Hemisphere, SamplesAreUnitLengthAndUpward) {
    Pcg32 rng(1, 1);
    for (int i = 0; i < 10000; ++i) {
        const float a = rng.next_float();
        const Point2f u{a, rng.next_float()};
        for (Vector3f v : {UniformHemisphere{}.sample(u), CosineHemisphere{}.sample(u)}) {
            ASSERT_TRUE(near(length(v), 1.0, 1e-6));
            ASSERT_GE(v.z, 0.0f);
        }
    }
}

TEST(Sphere, DensityAndRoundTrip) {
    EXPECT_TRUE(near(integrate_spherical([](Vector3f x) { return UniformSphere{}.pdf(x); }, -1.0), 1.0, 1e-4));
    expect_round_trip([](Point2f u) { return UniformSphere{}.sample(u); },
                      [](Vector3f x) { return UniformSphere{}.invert(x); }, 1e-5);
    EXPECT_EQ(UniformSphere{}.sample({0.0f, 0.3f}).z, 1.0f);
    EXPECT_EQ(UniformSphere{}.sample({0.5f, 0.3f}).z, 0.0f);
}

TEST(Cone, DensityIntegratesToOneOverTheCap) {
    for (float c : {-1.0f, -0.5f, 0.0f, 0.3f, 0.99f}) {
        const UniformCone cone(c);
        EXPECT_TRUE(near(integrate_spherical([&](Vector3f w) { return cone.pdf(w); }, -1.0, 1600), 1.0, 2e-3)) << c;
        expect_round_trip([&](Point2f u) { return cone.sample(u); }, [&](Vector3f v) { return cone.invert(v); },
                          c > 0.9f ? 1e-4 : 1e-5);
    }
}

TEST(Cone, SamplesStayInTheCap) {
    const UniformCone cone(0.3f);
    Pcg32 rng(2, 2);
    for (int i = 0; i < 10000; ++i) {
        const float a = rng.next_float();
        const Vector3f v = cone.sample({a, rng.next_float()});
        ASSERT_GT(cone.pdf(v), 0.0f);
        ASSERT_GE(v.z, 0.3f - 1e-6f);
    }
}

TEST(Parameters, InvalidValuesAreRejected) {
    EXPECT_THROW(UniformCone(1.0f), std::invalid_argument);
    EXPECT_THROW(UniformCone(1.5f), std::invalid_argument);
    EXPECT_THROW(UniformCone(-1.01f), std::invalid_argument);
    EXPECT_THROW(UniformCone{std::numeric_limits<float>::quiet_NaN()}, std::invalid_argument);
    EXPECT_NO_THROW(UniformCone(-1.0f));
    EXPECT_THROW(CosinePowerHemisphere(-0.5f), std::invalid_argument);
    EXPECT_THROW(CosinePowerHemisphere{std::numeric_limits<float>::infinity()}, std::invalid_argument);
    EXPECT_THROW(CosinePowerHemisphere{std::numeric_limits<float>::quiet_NaN()}, std::invalid_argument);
}

}  // namespace
}  // namespace warpcheck

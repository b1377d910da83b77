// The lights of sampling/light.h, each from a few reference points (near, far,
// grazing, behind, inside): the density integrates to 1 over the sphere, each
// sample's density, radiance and distance agree with pdf(), L() and the light's
// geometry, E[L / pdf] matches the integral of L, and the density is positive
// exactly where the ray hits the light. The test's own geometry and quadrature
// are in double and share no code with the header.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "sampling/light.h"
#include "sampling/pcg32.h"

namespace warpcheck {
namespace {

constexpr double kPiD = std::numbers::pi;

struct D3 {
    double x = 0.0, y = 0.0, z = 0.0;
};
D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator*(double s, D3 v) { return {s * v.x, s * v.y, s * v.z}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double norm(D3 v) { return std::sqrt(dot(v, v)); }
D3 unit(D3 v) { return (1.0 / norm(v)) * v; }
D3 d3(Vector3f v) { return {v.x, v.y, v.z}; }
Vector3f to_point(D3 p) { return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)}; }
// A direction as the light receives it: normalised in double, then rounded to float.
Vector3f f3(D3 v) {
    const D3 u = unit(v);
    return {static_cast<float>(u.x), static_cast<float>(u.y), static_cast<float>(u.z)};
}

// NaN-safe closeness: NaN is never near anything.
::testing::AssertionResult near(double a, double b, double tol) {
    if (std::abs(a - b) <= tol) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << a << " vs " << b << " (tolerance " << tol << ")";
}

// Collects failures of a per-sample rule and reports how many and the first one,
// instead of thousands of lines.
class Failures {
public:
    template <typename Describe>
    void check(bool ok, Describe describe) {
        if (ok) return;
        if (count_++ == 0) first_ = describe();
    }
    ::testing::AssertionResult result() const {
        if (count_ == 0) return ::testing::AssertionSuccess();
        return ::testing::AssertionFailure() << count_ << " failures; first: " << first_;
    }

private:
    int count_ = 0;
    std::string first_;
};

// ---- The test's own model of each light, in double ----

// Where the ray o + t w (w unit) first meets the light, t > 0, or -1 on a miss;
// `grow` scales the light about its centre by 1 + grow (negative shrinks), so
// that directions within rounding of the rim can be set aside.
using HitDistance = std::function<double(D3 o, D3 w, double grow)>;

// Visits the midpoints of an n x n grid over a chart of the directions from
// ref that meet the light, each such direction once: the unit direction and
// the solid angle of its cell. The chart's rim is the light's outline.
using Visit = std::function<void(D3 w, double solid_angle)>;
using Chart = std::function<void(D3 ref, int n, const Visit&)>;

struct Shape {
    HitDistance hit;
    Chart chart;
    D3 centre;            // of a bounding sphere
    double radius = 0.0;  // of that sphere
};

// Two unit vectors completing a right-handed basis with the unit n.
void basis(D3 n, D3& t1, D3& t2) {
    const D3 helper = std::abs(n.x) < 0.6 ? D3{1, 0, 0} : D3{0, 1, 0};
    t1 = unit(cross(helper, n));
    t2 = cross(n, t1);
}

// The directions within theta_cap of axis, as (1 - cos theta, phi) = (s (1 - cos theta_cap), 2 pi t).
struct Cap {
    D3 axis, t1, t2;
    double one_minus_cos = 2.0;

    static Cap around(D3 axis, double one_minus_cos) {
        Cap cap{axis, {}, {}, one_minus_cos};
        basis(axis, cap.t1, cap.t2);
        return cap;
    }
    D3 direction(double s, double t) const {
        const double omc = s * one_minus_cos;
        const double sin_theta = std::sqrt(std::max(0.0, omc * (2.0 - omc)));
        const double phi = 2.0 * kPiD * t;
        return (sin_theta * std::cos(phi)) * t1 + (sin_theta * std::sin(phi)) * t2 + (1.0 - omc) * axis;
    }
    bool contains(D3 w) const { return 0.5 * dot(w - axis, w - axis) <= one_minus_cos; }
};

// A cell of a planar light's surface at p (unit normal, area) as the direction
// from ref and the solid angle it subtends, |cos| area / dist^2.
void visit_surface(D3 ref, D3 p, D3 normal, double area, const Visit& visit) {
    const D3 d = p - ref;
    const double dist2 = dot(d, d);
    const D3 w = (1.0 / std::sqrt(dist2)) * d;
    visit(w, std::abs(dot(normal, w)) / dist2 * area);
}

Shape sphere_shape(Vector3f centre, float radius) {
    const D3 c = d3(centre);
    const double r = radius;
    auto hit = [c, r](D3 o, D3 w, double grow) {
        const double rg = r * (1.0 + grow);
        const D3 oc = c - o;
        const double b = dot(oc, w);
        const D3 perp = oc - b * w;
        const double disc = rg * rg - dot(perp, perp);
        if (disc < 0.0) return -1.0;
        const double near_root = b - std::sqrt(disc), far_root = b + std::sqrt(disc);
        return near_root > 0.0 ? near_root : far_root > 0.0 ? far_root : -1.0;
    };
    // From outside, the cone of directions that meets the sphere, charted by
    // (1 - cos theta, phi) about the direction to the centre (cells of equal
    // solid angle; the rim is the silhouette); from inside, every direction.
    auto chart = [c, r](D3 ref, int n, const Visit& visit) {
        const D3 oc = c - ref;
        const double d = norm(oc);
        const double sin2 = (r / d) * (r / d);
        const double one_minus_cos = d > r ? sin2 / (1.0 + std::sqrt(1.0 - sin2)) : 2.0;
        const Cap cap = Cap::around(d > 0.0 ? unit(oc) : D3{0, 0, 1}, one_minus_cos);
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j)
                visit(cap.direction((i + 0.5) / n, (j + 0.5) / n), 2.0 * kPiD * one_minus_cos / (double(n) * n));
    };
    return {hit, chart, c, r};
}

Shape triangle_shape(D3 p0, D3 p1, D3 p2) {
    const D3 v[3] = {p0, p1, p2};
    const D3 g = (1.0 / 3.0) * (v[0] + v[1] + v[2]);
    double reach = 0.0;
    for (const D3& p : v) reach = std::max(reach, norm(p - g));
    auto hit = [v, g](D3 o, D3 w, double grow) {
        D3 q[3];
        for (int k = 0; k < 3; ++k) q[k] = g + (1.0 + grow) * (v[k] - g);
        const D3 n = cross(q[1] - q[0], q[2] - q[0]);
        const double denom = dot(n, w);
        if (denom == 0.0) return -1.0;
        const double t = dot(n, q[0] - o) / denom;
        if (!(t > 0.0)) return -1.0;
        const D3 p = o + t * w;
        for (int k = 0; k < 3; ++k)
            if (dot(cross(q[(k + 1) % 3] - q[k], p - q[k]), n) < 0.0) return -1.0;
        return t;
    };
    // Charted by the triangle itself: p = p0 + s (1 - t) e1 + s t e2 over (s, t)
    // in [0,1]^2, dA = |e1 x e2| s ds dt, carried to directions by dw = |cos| dA / dist^2.
    auto chart = [v](D3 ref, int n, const Visit& visit) {
        const D3 e1 = v[1] - v[0], e2 = v[2] - v[0], normal = cross(e1, e2);
        const double twice_area = norm(normal);
        for (int i = 0; i < n; ++i) {
            const double s = (i + 0.5) / n;
            for (int j = 0; j < n; ++j) {
                const double t = (j + 0.5) / n;
                visit_surface(ref, v[0] + (s * (1.0 - t)) * e1 + (s * t) * e2, unit(normal),
                              twice_area * s / (double(n) * n), visit);
            }
        }
    };
    return {hit, chart, g, reach};
}

// The rectangle corner + a ex + b ey, a and b in [0, 1] (grown about its centre).
Shape rectangle_shape(D3 corner, D3 ex, D3 ey) {
    const D3 n = unit(cross(ex, ey)), g = corner + 0.5 * ex + 0.5 * ey;
    auto hit = [corner, ex, ey, n, g](D3 o, D3 w, double grow) {
        const double denom = dot(n, w);
        if (denom == 0.0) return -1.0;
        const double t = dot(n, corner - o) / denom;
        if (!(t > 0.0)) return -1.0;
        const D3 q = o + t * w - g;
        const double a = dot(q, ex) / dot(ex, ex), b = dot(q, ey) / dot(ey, ey);
        const double half = 0.5 * (1.0 + grow);
        return std::abs(a) <= half && std::abs(b) <= half ? t : -1.0;
    };
    // Charted by the rectangle itself (dA = |ex x ey| da db), carried to directions.
    auto chart = [corner, ex, ey, n](D3 ref, int cells, const Visit& visit) {
        const double area = norm(cross(ex, ey));
        for (int i = 0; i < cells; ++i)
            for (int j = 0; j < cells; ++j)
                visit_surface(ref, corner + ((i + 0.5) / cells) * ex + ((j + 0.5) / cells) * ey, n,
                              area / (double(cells) * cells), visit);
    };
    return {hit, chart, g, 0.5 * norm(ex + ey)};
}

Shape disk_shape(Vector3f centre, Vector3f normal, float radius) {
    const D3 c = d3(centre), n = unit(d3(normal));
    const double r = radius;
    auto hit = [c, n, r](D3 o, D3 w, double grow) {
        const double denom = dot(n, w);
        if (denom == 0.0) return -1.0;
        const double t = dot(n, c - o) / denom;
        if (!(t > 0.0)) return -1.0;
        const D3 p = o + t * w - c;
        return norm(p) <= r * (1.0 + grow) ? t : -1.0;
    };
    // Charted by the disk itself in polar cells (dA = rho drho dphi), carried to
    // directions by dw = |cos| dA / dist^2.
    auto chart = [c, n, r](D3 ref, int cells, const Visit& visit) {
        D3 t1, t2;
        basis(n, t1, t2);
        for (int i = 0; i < cells; ++i) {
            const double rho = r * (i + 0.5) / cells;
            for (int j = 0; j < cells; ++j) {
                const double phi = 2.0 * kPiD * (j + 0.5) / cells;
                visit_surface(ref, c + (rho * std::cos(phi)) * t1 + (rho * std::sin(phi)) * t2, n,
                              rho * (r / cells) * (2.0 * kPiD / cells), visit);
            }
        }
    };
    return {hit, chart, c, r};
}

// The cap around the light's bounding sphere seen from ref, its angle widened by
// `widen`; the whole sphere when ref is inside (or on) the bounding sphere.
Cap bounding_cap(const Shape& shape, Vector3f ref, double widen) {
    const D3 oc = shape.centre - d3(ref);
    const double d = norm(oc);
    if (d <= shape.radius * 1.001) return Cap::around(d > 0.0 ? unit(oc) : D3{0, 0, 1}, 2.0);
    const double theta = std::min(kPiD, widen * std::asin(shape.radius / d));
    return Cap::around(unit(oc), 1.0 - std::cos(theta));
}

// ---- Quadrature over the solid angle the light subtends ----

struct Quadrature {
    double value = 0.0;
    double error = 0.0;  // the estimated error of value
};

// The integral of f over the directions that meet the light, by the midpoint
// rule on the shape's chart of them (the sphere's cone; a planar light's own
// surface, each cell carried to the solid angle it subtends). Each direction
// is counted once, and f has no edge inside the chart (the chart's rim is the
// light's outline), so the rule converges as h^2: the value is the 512 x 512
// rule, its error estimate the difference from the 256 x 256 rule (about
// three times the finer rule's error). Directions that miss the light are the
// support test's (pdf = 0 there).
Quadrature integrate_over_light(const Shape& shape, Vector3f ref, const std::function<double(Vector3f)>& f) {
    auto rule = [&](int n) {
        double sum = 0.0;
        shape.chart(d3(ref), n, [&](D3 w, double solid_angle) { sum += f(f3(w)) * solid_angle; });
        return sum;
    };
    const double coarse = rule(256), fine = rule(512);
    return {fine, std::abs(fine - coarse)};
}

// ---- The checks shared by every geometric light ----

template <typename Light>
struct Case {
    std::string name;
    Light light;
    Shape shape;
    Vector3f ref;
    float Le;
};

// (a) The density integrates to 1 over the sphere: over the light's solid angle
// by the quadrature above, within its error estimate plus 1e-5 (the float
// density's rounding, relative ~1e-7 but growing as 1 / cos at grazing angles);
// elsewhere it is 0 (expect_support). The estimate must stay below 1e-4, so
// that the test sees a normalisation off by that much.
template <typename Light>
void expect_integrates_to_one(const Case<Light>& c) {
    const Quadrature q = integrate_over_light(c.shape, c.ref, [&](Vector3f w) {
        return double{c.light.pdf(c.ref, w)};
    });
    EXPECT_TRUE(near(q.value, 1.0, q.error + 1e-5)) << c.name;
    EXPECT_LT(q.error, 1e-4) << c.name << ": the quadrature does not resolve the light";
}

// (b) At 4096 sampled directions: a sample (pdf > 0, as every ref here sees
// the light), pdf(ref, wi) within 1e-3 relative of the returned pdf (float
// rounding of the two computations, ~1e-6, with room for grazing angles), L
// equal and positive, wi unit to 1e-6 (a few float ulps), and the distance that
// of the test's own double intersection along wi to 1e-4 relative.
template <typename Light>
void expect_samples_agree(const Case<Light>& c, uint64_t stream) {
    Pcg32 rng(stream, 1);
    Failures failures;
    for (int i = 0; i < 4096; ++i) {
        const Point2f u{rng.next_float(), rng.next_float()};
        const LightSample s = c.light.sample(c.ref, u);
        const float p = c.light.pdf(c.ref, s.wi), l = c.light.L(c.ref, s.wi);
        const D3 w = d3(s.wi);
        double t = c.shape.hit(d3(c.ref), unit(w), 0.0);
        if (t < 0.0) t = c.shape.hit(d3(c.ref), unit(w), 1e-6);  // on the rim, within rounding
        auto describe = [&] {
            std::ostringstream out;
            out << c.name << " u=(" << u.x << ", " << u.y << "): pdf " << s.pdf << " vs pdf() " << p << ", L "
                << s.L << " vs L() " << l << ", |wi| " << norm(w) << ", distance " << s.distance << " vs " << t;
            return out.str();
        };
        failures.check(s.pdf > 0.0f && std::isfinite(s.pdf), describe);
        failures.check(std::abs(p - s.pdf) <= 1e-3 * s.pdf, describe);
        failures.check(l == s.L && s.L == c.Le, describe);
        failures.check(std::abs(norm(w) - 1.0) <= 1e-6, describe);
        failures.check(t > 0.0 && std::abs(s.distance - t) <= 1e-4 * t, describe);
    }
    EXPECT_TRUE(failures.result());
}

// (c) E[L / pdf] over 2^16 samples against the quadrature of L: within 5
// standard errors plus the quadrature's error estimate and 1e-6 relative (a
// sampler uniform in solid angle has L / pdf constant and no sampling error).
template <typename Light>
void expect_estimate_matches(const Case<Light>& c, uint64_t stream) {
    const Quadrature q = integrate_over_light(c.shape, c.ref, [&](Vector3f w) {
        return double{c.light.L(c.ref, w)};
    });
    Pcg32 rng(stream, 2);
    const int n = 1 << 16;
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
        const LightSample s = c.light.sample(c.ref, {rng.next_float(), rng.next_float()});
        const double w = s.pdf > 0.0f ? double{s.L} / s.pdf : 0.0;
        sum += w;
        sum2 += w * w;
    }
    const double mean = sum / n;
    const double se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / (n - 1));
    EXPECT_TRUE(near(mean, q.value, 5.0 * se + q.error + 1e-6 * q.value)) << c.name;
    EXPECT_GT(q.value, 0.0) << c.name;
}

// (d) Support: 20000 directions in a cone 1.3 times as wide as the light's
// bounding sphere: pdf > 0 exactly where L > 0; a direction that hits the light
// shrunk by 1e-4 (the test's double intersection, clear of rounding at the rim)
// has pdf > 0 and L = Le, one that misses it grown by 1e-4 has pdf = 0; at
// least 50 of each kind (a grazing light is a thin sliver of the cone). Outside the cone, 20000 directions spread over the sphere have
// pdf = 0 and L = 0.
template <typename Light>
void expect_support(const Case<Light>& c, uint64_t stream) {
    const Cap cone = bounding_cap(c.shape, c.ref, 1.3);
    const D3 o = d3(c.ref);
    Pcg32 rng(stream, 3);
    Failures failures;
    int hits = 0, misses = 0;
    for (int i = 0; i < 20000; ++i) {
        const Vector3f wf = f3(cone.direction(rng.next_double(), rng.next_double()));
        const float p = c.light.pdf(c.ref, wf), l = c.light.L(c.ref, wf);
        const bool inside = c.shape.hit(o, d3(wf), -1e-4) > 0.0, outside = c.shape.hit(o, d3(wf), 1e-4) < 0.0;
        hits += inside;
        misses += outside;
        auto describe = [&] {
            std::ostringstream out;
            out << c.name << " wi=(" << wf.x << ", " << wf.y << ", " << wf.z << "): pdf " << p << ", L " << l
                << (inside ? " (hits)" : outside ? " (misses)" : "");
            return out.str();
        };
        failures.check(p >= 0.0f && std::isfinite(p) && (p > 0.0f) == (l > 0.0f), describe);
        if (inside) failures.check(p > 0.0f && l == c.Le, describe);
        if (outside) failures.check(p == 0.0f && l == 0.0f, describe);
    }
    EXPECT_TRUE(failures.result());
    EXPECT_GE(hits, 50) << c.name;
    if (cone.one_minus_cos < 2.0) {
        EXPECT_GE(misses, 50) << c.name;
    }
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        // A Fibonacci lattice: z uniform, phi advancing by the golden angle.
        const double z = 1.0 - (2.0 * i + 1.0) / n, r = std::sqrt(1.0 - z * z);
        const double phi = i * kPiD * (3.0 - std::sqrt(5.0));
        const D3 w{r * std::cos(phi), r * std::sin(phi), z};
        if (cone.contains(w)) continue;
        const Vector3f wf = f3(w);
        failures.check(c.light.pdf(c.ref, wf) == 0.0f && c.light.L(c.ref, wf) == 0.0f, [&] {
            return c.name + ": nonzero outside the cone";
        });
    }
    EXPECT_TRUE(failures.result());
}

template <typename Light>
void expect_all(const std::vector<Case<Light>>& cases, void (*check)(const Case<Light>&, uint64_t)) {
    for (std::size_t i = 0; i < cases.size(); ++i) check(cases[i], 100 + i);
}

// ---- The lights and their reference points ----

const Vector3f kSphereCentre{0.3f, -0.2f, 4.0f};
constexpr float kSphereRadius = 1.0f;

std::vector<Case<SphereLight>> sphere_cases_outside() {
    const SphereLight light(kSphereCentre, kSphereRadius, 2.5f);
    const Shape shape = sphere_shape(kSphereCentre, kSphereRadius);
    return {{"far", light, shape, {0.0f, 1.0f, -20.0f}, 2.5f},
            {"near", light, shape, {0.3f, -0.2f, 2.5f}, 2.5f},
            // 2% of the radius above the surface: the cone is nearly a hemisphere
            // and its rim rays graze the sphere.
            {"grazing", light, shape, {0.3f, 0.82f, 4.0f}, 2.5f}};
}

std::vector<Case<SphereLight>> sphere_cases_inside() {
    const SphereLight light(kSphereCentre, kSphereRadius, 2.5f);
    const Shape shape = sphere_shape(kSphereCentre, kSphereRadius);
    return {{"inside", light, shape, {0.5f, 0.1f, 4.3f}, 2.5f},
            {"centre", light, shape, kSphereCentre, 2.5f},
            {"inside near the surface", light, shape, {0.3f, -0.2f, 4.9f}, 2.5f}};
}

const Vector3f kT0{-1.0f, -1.0f, 2.0f}, kT1{1.5f, -0.8f, 2.2f}, kT2{0.1f, 1.2f, 3.0f};

template <typename Light>
std::vector<Case<Light>> triangle_cases() {
    const Light light(kT0, kT1, kT2, 1.5f);
    const Shape shape = triangle_shape(d3(kT0), d3(kT1), d3(kT2));
    // Grazing: 0.05 off the plane, beyond an edge, so every ray meets it at a shallow angle.
    const D3 n = unit(cross(d3(kT1) - d3(kT0), d3(kT2) - d3(kT0)));
    const D3 g = (1.0 / 3.0) * (d3(kT0) + d3(kT1) + d3(kT2));
    const D3 beyond = g + 2.0 * (0.5 * (d3(kT0) + d3(kT1)) - g) + 0.05 * n;
    // Behind: on the other side of the two-sided triangle.
    return {{"near", light, shape, {0.1f, 0.0f, 0.0f}, 1.5f},
            {"far", light, shape, {2.0f, 3.0f, -15.0f}, 1.5f},
            {"behind", light, shape, {0.3f, 0.0f, 6.0f}, 1.5f},
            {"grazing", light, shape, to_point(beyond), 1.5f}};
}

const Vector3f kDiskCentre{0.5f, 0.0f, 3.0f}, kDiskNormal{0.0f, 0.4f, -1.0f};
constexpr float kDiskRadius = 1.2f;

std::vector<Case<DiskLight>> disk_cases() {
    const DiskLight light(kDiskCentre, kDiskNormal, kDiskRadius, 0.8f);
    const Shape shape = disk_shape(kDiskCentre, kDiskNormal, kDiskRadius);
    const D3 n = unit(d3(kDiskNormal));
    const D3 t = unit(cross(n, D3{1, 0, 0}));
    const D3 grazing = d3(kDiskCentre) + 1.6 * kDiskRadius * t + 0.05 * n;
    return {{"near", light, shape, {0.2f, 0.3f, 0.5f}, 0.8f},
            {"far", light, shape, {-4.0f, 2.0f, -20.0f}, 0.8f},
            {"behind", light, shape, {0.6f, 0.5f, 5.0f}, 0.8f},
            {"grazing", light, shape, to_point(grazing), 0.8f}};
}

// ---- Sphere ----

TEST(Light, SphereFromOutsideIntegratesToOne) {
    for (const auto& c : sphere_cases_outside()) expect_integrates_to_one(c);
}

TEST(Light, SphereFromInsideIntegratesToOne) {
    for (const auto& c : sphere_cases_inside()) expect_integrates_to_one(c);
}

TEST(Light, SphereSamplesAgreeWithPdfAndRadiance) {
    expect_all(sphere_cases_outside(), expect_samples_agree<SphereLight>);
    expect_all(sphere_cases_inside(), expect_samples_agree<SphereLight>);
}

TEST(Light, SphereEstimateMatchesQuadrature) {
    expect_all(sphere_cases_outside(), expect_estimate_matches<SphereLight>);
    expect_all(sphere_cases_inside(), expect_estimate_matches<SphereLight>);
}

TEST(Light, SphereSupportIsWhereTheRayHits) {
    expect_all(sphere_cases_outside(), expect_support<SphereLight>);
    expect_all(sphere_cases_inside(), expect_support<SphereLight>);
}

// A far small sphere: 1 - cos theta_max is r^2 / (2 d^2) to first order, which
// 1 - sqrt(1 - r^2/d^2) in float loses entirely below r/d ~ 3e-4. The density
// must match the exact cone's, and the samples must still hit the sphere.
TEST(Light, SphereFarAndSmallKeepsItsDensity) {
    for (double ratio : {1e-2, 1e-3, 1e-4}) {
        const float d = static_cast<float>(1.0 / ratio);
        const SphereLight light({0.0f, 0.0f, d}, 1.0f, 1.0f);
        const double sin2 = ratio * ratio, cos_max = std::sqrt(1.0 - sin2);
        const double expected = 1.0 / (2.0 * kPiD * sin2 / (1.0 + cos_max));
        Pcg32 rng(7, 9);
        Failures failures;
        for (int i = 0; i < 1000; ++i) {
            const LightSample s = light.sample({0, 0, 0}, {rng.next_float(), rng.next_float()});
            failures.check(std::abs(s.pdf - expected) <= 1e-5 * expected && s.L == 1.0f &&
                               light.pdf({0, 0, 0}, s.wi) == s.pdf,
                           [&] { return "r/d " + std::to_string(ratio) + ": pdf " + std::to_string(s.pdf); });
        }
        EXPECT_TRUE(failures.result());
    }
}

// ---- Triangle, by area ----

TEST(Light, TriangleIntegratesToOne) {
    for (const auto& c : triangle_cases<TriangleLight>()) expect_integrates_to_one(c);
}

TEST(Light, TriangleSamplesAgreeWithPdfAndRadiance) {
    expect_all(triangle_cases<TriangleLight>(), expect_samples_agree<TriangleLight>);
}

TEST(Light, TriangleEstimateMatchesQuadrature) {
    expect_all(triangle_cases<TriangleLight>(), expect_estimate_matches<TriangleLight>);
}

TEST(Light, TriangleSupportIsWhereTheRayHits) {
    expect_all(triangle_cases<TriangleLight>(), expect_support<TriangleLight>);
}

// A ref in the triangle's plane sees it edge-on: no sample, and no density.
TEST(Light, TriangleGivesNoSampleFromItsPlane) {
    const TriangleLight light({0, 0, 1}, {1, 0, 1}, {0, 1, 1}, 1.0f);
    const SphericalTriangleLight spherical({0, 0, 1}, {1, 0, 1}, {0, 1, 1}, 1.0f);
    for (Vector3f ref : {Vector3f{2, 2, 1}, Vector3f{0.2f, 0.2f, 1}}) {
        const LightSample s = light.sample(ref, {0.3f, 0.6f});
        EXPECT_EQ(s.pdf, 0.0f);
        EXPECT_EQ(spherical.sample(ref, {0.3f, 0.6f}).pdf, 0.0f);
        EXPECT_EQ(light.pdf(ref, f3(D3{-1, -1, 0})), 0.0f);
        EXPECT_EQ(light.L(ref, f3(D3{-1, -1, 0})), 0.0f);
    }
}

// ---- Triangle, by solid angle ----

// The solid angle of the triangle p0 p1 p2 from o, by Eriksson's form of Van
// Oosterom and Strackee (unnormalised vectors), independent of the header's.
double triangle_solid_angle(D3 o, D3 p0, D3 p1, D3 p2) {
    const D3 a = p0 - o, b = p1 - o, c = p2 - o;
    const double la = norm(a), lb = norm(b), lc = norm(c);
    const double triple = dot(a, cross(b, c));
    return 2.0 * std::atan2(std::abs(triple), la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la);
}

TEST(Light, SphericalTriangleIntegratesToOne) {
    for (const auto& c : triangle_cases<SphericalTriangleLight>()) expect_integrates_to_one(c);
}

TEST(Light, SphericalTriangleSamplesAgreeWithPdfAndRadiance) {
    expect_all(triangle_cases<SphericalTriangleLight>(), expect_samples_agree<SphericalTriangleLight>);
}

TEST(Light, SphericalTriangleEstimateMatchesQuadrature) {
    expect_all(triangle_cases<SphericalTriangleLight>(), expect_estimate_matches<SphericalTriangleLight>);
}

TEST(Light, SphericalTriangleSupportIsWhereTheRayHits) {
    expect_all(triangle_cases<SphericalTriangleLight>(), expect_support<SphericalTriangleLight>);
}

// Uniform in solid angle: the density is 1 / Omega (to 1e-5: double math
// rounded once to float), and the four triangles cut by the edges' midpoints
// each get their share Omega_k / Omega of 2^16 samples within 5 standard errors,
// from a ref near (Omega ~ 0.5), far (~8e-4), just above the area-sampling
// cut-off (~2e-5), and nearly in the plane (~6.27).
TEST(Light, SphericalTriangleIsUniformInSolidAngle) {
    const D3 v[3] = {d3(kT0), d3(kT1), d3(kT2)};
    const D3 g = (1.0 / 3.0) * (v[0] + v[1] + v[2]);
    const D3 n = unit(cross(v[1] - v[0], v[2] - v[0]));
    const std::vector<D3> refs = {{0.1, 0.0, 0.0}, {2.0, 3.0, -60.0}, g - 380.0 * n, g + 0.003 * n};
    const D3 m[3] = {0.5 * (v[0] + v[1]), 0.5 * (v[1] + v[2]), 0.5 * (v[2] + v[0])};
    const D3 parts[4][3] = {{v[0], m[0], m[2]}, {m[0], v[1], m[1]}, {m[2], m[1], v[2]}, {m[0], m[1], m[2]}};
    std::vector<Shape> part_shapes;
    for (const auto& part : parts) part_shapes.push_back(triangle_shape(part[0], part[1], part[2]));
    const SphericalTriangleLight light(kT0, kT1, kT2, 1.0f);
    for (const D3& ref_d : refs) {
        const Vector3f ref = to_point(ref_d);
        const D3 o = d3(ref);
        const double omega = triangle_solid_angle(o, v[0], v[1], v[2]);
        ASSERT_GT(omega, SphericalTriangleLight::kMinSolidAngle);
        ASSERT_LT(omega, SphericalTriangleLight::kMaxSolidAngle);
        const int n_samples = 1 << 16;
        int counts[4] = {};
        Pcg32 rng(21, 5);
        Failures failures;
        for (int i = 0; i < n_samples; ++i) {
            const LightSample s = light.sample(ref, {rng.next_float(), rng.next_float()});
            failures.check(std::abs(s.pdf * omega - 1.0) <= 1e-5, [&] { return std::to_string(s.pdf * omega); });
            for (int k = 0; k < 4; ++k)
                if (part_shapes[k].hit(o, unit(d3(s.wi)), 0.0) > 0.0) {
                    ++counts[k];
                    break;
                }
        }
        EXPECT_TRUE(failures.result()) << "Omega " << omega;
        for (int k = 0; k < 4; ++k) {
            const double p = triangle_solid_angle(o, parts[k][0], parts[k][1], parts[k][2]) / omega;
            const double sd = std::sqrt(n_samples * p * (1.0 - p));
            EXPECT_TRUE(near(counts[k], n_samples * p, 5.0 * sd)) << "Omega " << omega << ", part " << k;
        }
    }
}

// Where Omega is outside [kMinSolidAngle, kMaxSolidAngle] the light samples by
// area: the same directions and densities as TriangleLight, bit for bit, from
// pdf() too; the samples still agree with pdf(), L() and the geometry.
TEST(Light, SphericalTriangleFallsBackToAreaSamplingOutsideItsRange) {
    const D3 v[3] = {d3(kT0), d3(kT1), d3(kT2)};
    const D3 g = (1.0 / 3.0) * (v[0] + v[1] + v[2]);
    const D3 n = unit(cross(v[1] - v[0], v[2] - v[0]));
    const SphericalTriangleLight spherical(kT0, kT1, kT2, 1.5f);
    const TriangleLight by_area(kT0, kT1, kT2, 1.5f);
    const std::vector<Case<SphericalTriangleLight>> cases = {
        {"tiny", spherical, triangle_shape(v[0], v[1], v[2]), to_point(g - 800.0 * n), 1.5f},
        {"nearly in the plane", spherical, triangle_shape(v[0], v[1], v[2]), to_point(g + 1e-3 * n), 1.5f}};
    for (const auto& c : cases) {
        const double omega = triangle_solid_angle(d3(c.ref), v[0], v[1], v[2]);
        EXPECT_TRUE(omega < SphericalTriangleLight::kMinSolidAngle || omega > SphericalTriangleLight::kMaxSolidAngle)
            << c.name << ": Omega " << omega;
        Pcg32 rng(31, 1);
        Failures failures;
        for (int i = 0; i < 1000; ++i) {
            const Point2f u{rng.next_float(), rng.next_float()};
            const LightSample a = spherical.sample(c.ref, u), b = by_area.sample(c.ref, u);
            failures.check(a.wi == b.wi && a.pdf == b.pdf && a.pdf > 0.0f &&
                               spherical.pdf(c.ref, a.wi) == by_area.pdf(c.ref, a.wi),
                           [&] { return c.name + ": pdf " + std::to_string(a.pdf) + " vs " + std::to_string(b.pdf); });
        }
        EXPECT_TRUE(failures.result());
    }
    // Nearly in the plane every ray grazes, and the float sample point's own
    // rounding off the plane (~1e-7) moves the hit by ~1e-4 of the distance: the
    // full agreement check runs on the tiny case (pdf() agreed above for both).
    expect_samples_agree(cases[0], 120);
}

// invert(sample(u)) = u to 1e-4 in both regimes. What limits it is the float
// direction (~6e-8 rad): over a triangle ~5e-3 rad across (Omega ~ 2e-5) that
// is ~1e-5 of u, and the float barycentrics of the area regime from 800
// triangle sizes away are good to ~3e-5. Each map pinches one side of the
// square to a vertex, where the other coordinate is undefined and, near it,
// ill-conditioned (as the azimuth at a pole): Arvo's u.y = 0 is vertex p1 for
// every u.x, the square-root warp's u.x = 0 is p0 for every u.y. So u.x is
// compared where u.y >= 0.01 and u.y where u.x >= 0.05 (the square-root warp's
// u.y = b2 / sqrt(u.x) divides the barycentric's float error by sqrt(u.x)).
TEST(Light, SphericalTriangleInverseRoundTrips) {
    const D3 v[3] = {d3(kT0), d3(kT1), d3(kT2)};
    const D3 g = (1.0 / 3.0) * (v[0] + v[1] + v[2]);
    const D3 n = unit(cross(v[1] - v[0], v[2] - v[0]));
    const std::vector<D3> refs = {{0.1, 0.0, 0.0}, {0.3, 0.0, 6.0},  {2.0, 3.0, -60.0},
                                  g - 380.0 * n,   g + 0.003 * n,    g - 800.0 * n};
    const SphericalTriangleLight light(kT0, kT1, kT2, 1.0f);
    for (const D3& ref_d : refs) {
        const Vector3f ref = to_point(ref_d);
        Pcg32 rng(41, 3);
        Failures failures;
        for (int i = 0; i < 4096; ++i) {
            const Point2f u{rng.next_float(), rng.next_float()};
            const Point2f back = light.invert(ref, light.sample(ref, u).wi);
            failures.check((u.y < 0.01f || std::abs(back.x - u.x) <= 1e-4) &&
                               (u.x < 0.05f || std::abs(back.y - u.y) <= 1e-4),
                           [&] {
                std::ostringstream out;
                out << "ref (" << ref.x << ", " << ref.y << ", " << ref.z << "): u (" << u.x << ", " << u.y
                    << ") came back as (" << back.x << ", " << back.y << ")";
                return out.str();
            });
        }
        EXPECT_TRUE(failures.result());
    }
}

// ---- Rectangle, by solid angle ----

const Vector3f kR0{-0.4f, -0.3f, 2.0f}, kREx{1.2f, 0.0f, 0.5f}, kREy{0.0f, 0.9f, 0.0f};

std::vector<Case<SphericalRectangleLight>> rectangle_cases() {
    const SphericalRectangleLight light(kR0, kREx, kREy, 1.5f);
    const Shape shape = rectangle_shape(d3(kR0), d3(kREx), d3(kREy));
    const D3 n = unit(cross(d3(kREx), d3(kREy)));
    const D3 g = d3(kR0) + 0.5 * d3(kREx) + 0.5 * d3(kREy);
    // Grazing: 0.05 off the plane, beyond an edge.
    const D3 beyond = g + 1.2 * d3(kREx) + 0.05 * n;
    return {{"near", light, shape, {0.1f, 0.0f, 0.0f}, 1.5f},
            {"far", light, shape, {2.0f, 3.0f, -15.0f}, 1.5f},
            {"behind", light, shape, to_point(g + 3.0 * n), 1.5f},
            {"grazing", light, shape, to_point(beyond), 1.5f}};
}

// The solid angle of the rectangle from o, as two triangles (Van Oosterom and Strackee).
double rectangle_solid_angle(D3 o, D3 corner, D3 ex, D3 ey) {
    return triangle_solid_angle(o, corner, corner + ex, corner + ex + ey) +
           triangle_solid_angle(o, corner, corner + ex + ey, corner + ey);
}

TEST(Light, SphericalRectangleIntegratesToOne) {
    for (const auto& c : rectangle_cases()) expect_integrates_to_one(c);
}

TEST(Light, SphericalRectangleSamplesAgreeWithPdfAndRadiance) {
    expect_all(rectangle_cases(), expect_samples_agree<SphericalRectangleLight>);
}

TEST(Light, SphericalRectangleEstimateMatchesQuadrature) {
    expect_all(rectangle_cases(), expect_estimate_matches<SphericalRectangleLight>);
}

TEST(Light, SphericalRectangleSupportIsWhereTheRayHits) {
    expect_all(rectangle_cases(), expect_support<SphericalRectangleLight>);
}

// Uniform in solid angle: the density is 1 / Omega (to 1e-5), and the 16
// cells of a 4 x 4 grid on the rectangle each get their share of 2^16 samples
// within 5 standard errors, from a ref near, far (~1e-3 sr), just above the
// area-sampling cut-off and nearly in the plane. (A grid, not the quarters:
// the midlines split a view from above the centre symmetrically, where a
// sampler uniform in y instead of in the column's h still gets half on each
// side; the grid's outer cells see it.)
TEST(Light, SphericalRectangleIsUniformInSolidAngle) {
    const D3 c = d3(kR0), ex = d3(kREx), ey = d3(kREy);
    const D3 n = unit(cross(ex, ey)), g = c + 0.5 * ex + 0.5 * ey;
    const std::vector<D3> refs = {{0.1, 0.0, 0.0}, {2.0, 3.0, -30.0}, g - 300.0 * n, g + 0.003 * n};
    std::vector<D3> corners;
    std::vector<Shape> parts;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            corners.push_back(c + (0.25 * i) * ex + (0.25 * j) * ey);
            parts.push_back(rectangle_shape(corners.back(), 0.25 * ex, 0.25 * ey));
        }
    const SphericalRectangleLight light(kR0, kREx, kREy, 1.0f);
    for (const D3& ref_d : refs) {
        const Vector3f ref = to_point(ref_d);
        const D3 o = d3(ref);
        const double omega = rectangle_solid_angle(o, c, ex, ey);
        ASSERT_GT(omega, SphericalRectangleLight::kMinSolidAngle);
        ASSERT_LT(omega, SphericalRectangleLight::kMaxSolidAngle);
        const int n_samples = 1 << 16;
        int counts[16] = {};
        Pcg32 rng(23, 7);
        Failures failures;
        for (int i = 0; i < n_samples; ++i) {
            const LightSample s = light.sample(ref, {rng.next_float(), rng.next_float()});
            failures.check(std::abs(s.pdf * omega - 1.0) <= 1e-5, [&] { return std::to_string(s.pdf * omega); });
            for (int k = 0; k < 16; ++k)
                if (parts[k].hit(o, unit(d3(s.wi)), 0.0) > 0.0) {
                    ++counts[k];
                    break;
                }
        }
        EXPECT_TRUE(failures.result()) << "Omega " << omega;
        for (int k = 0; k < 16; ++k) {
            const double p = rectangle_solid_angle(o, corners[k], 0.25 * ex, 0.25 * ey) / omega;
            const double sd = std::sqrt(n_samples * p * (1.0 - p));
            EXPECT_TRUE(near(counts[k], n_samples * p, 5.0 * sd)) << "Omega " << omega << ", part " << k;
        }
    }
}

// invert(sample(u)) = u to 1e-4 from near, far, behind and nearly in the
// plane (the map has no pinched side: every u is compared), and in the area
// regime from 800 sizes away.
TEST(Light, SphericalRectangleInverseRoundTrips) {
    const D3 c = d3(kR0), ex = d3(kREx), ey = d3(kREy);
    const D3 n = unit(cross(ex, ey)), g = c + 0.5 * ex + 0.5 * ey;
    const std::vector<D3> refs = {{0.1, 0.0, 0.0}, {2.0, 3.0, -15.0}, g + 3.0 * n, g + 0.003 * n, g - 800.0 * n};
    const SphericalRectangleLight light(kR0, kREx, kREy, 1.0f);
    for (const D3& ref_d : refs) {
        const Vector3f ref = to_point(ref_d);
        Pcg32 rng(43, 5);
        Failures failures;
        for (int i = 0; i < 4096; ++i) {
            const Point2f u{rng.next_float(), rng.next_float()};
            const Point2f back = light.invert(ref, light.sample(ref, u).wi);
            failures.check(std::abs(back.x - u.x) <= 1e-4 && std::abs(back.y - u.y) <= 1e-4, [&] {
                std::ostringstream out;
                out << "ref (" << ref.x << ", " << ref.y << ", " << ref.z << "): u (" << u.x << ", " << u.y
                    << ") came back as (" << back.x << ", " << back.y << ")";
                return out.str();
            });
        }
        EXPECT_TRUE(failures.result());
    }
}

TEST(Light, SphericalRectangleRefusesEdgesThatAreNotPerpendicular) {
    EXPECT_THROW(SphericalRectangleLight({0, 0, 1}, {1, 0, 0}, {0.1f, 1, 0}, 1.0f), std::invalid_argument);
    EXPECT_THROW(SphericalRectangleLight({0, 0, 1}, {0, 0, 0}, {0, 1, 0}, 1.0f), std::invalid_argument);
    EXPECT_THROW(SphericalRectangleLight({0, 0, 1}, {1, 0, 0}, {0, 1, 0}, 0.0f), std::invalid_argument);
}

// ---- Disk ----

TEST(Light, DiskIntegratesToOne) {
    for (const auto& c : disk_cases()) expect_integrates_to_one(c);
}

TEST(Light, DiskSamplesAgreeWithPdfAndRadiance) { expect_all(disk_cases(), expect_samples_agree<DiskLight>); }

TEST(Light, DiskEstimateMatchesQuadrature) { expect_all(disk_cases(), expect_estimate_matches<DiskLight>); }

TEST(Light, DiskSupportIsWhereTheRayHits) { expect_all(disk_cases(), expect_support<DiskLight>); }

// ---- Environment map ----

struct EnvMap {
    std::string name;
    int width, height;
    std::vector<float> pixels;
    float at(int i, int j) const { return pixels[static_cast<std::size_t>(j * width + i)]; }
    // Solid angle of pixel row j's pixels: 2 pi / width (cos theta_j - cos theta_j+1).
    double pixel_solid_angle(int j) const {
        return 2.0 * kPiD / width * (std::cos(kPiD * j / height) - std::cos(kPiD * (j + 1) / height));
    }
    double integral_of_L() const {
        double sum = 0.0;
        for (int j = 0; j < height; ++j)
            for (int i = 0; i < width; ++i) sum += at(i, j) * pixel_solid_angle(j);
        return sum;
    }
};

// A varied map: values from 0.5 to 4.5, a zero row (2), a zero column (3) and a
// zero pixel, on 16 x 8.
EnvMap varied_map() {
    EnvMap m{"varied", 16, 8, {}};
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 16; ++i)
            m.pixels.push_back(j == 2 || i == 3 || (i == 9 && j == 5) ? 0.0f : 0.5f + float((7 * i + 3 * j) % 5));
    return m;
}

EnvMap zero_rows_map() {
    EnvMap m{"zero rows", 6, 5, {}};
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 6; ++i) m.pixels.push_back(j % 2 == 0 ? 0.0f : 1.0f + float(i));
    return m;
}

EnvMap single_pixel_map() {
    EnvMap m{"single lit pixel", 8, 4, std::vector<float>(32, 0.0f)};
    m.pixels[1 * 8 + 5] = 3.0f;  // column 5, row 1: phi in [5 pi/4, 3 pi/2), theta in [pi/4, pi/2)
    return m;
}

std::vector<EnvMap> env_maps() {
    return {varied_map(), {"one by one", 1, 1, {2.0f}}, zero_rows_map(), single_pixel_map()};
}

// The pixel of a direction by the test's own double arithmetic; `margin` is how
// far (in pixels) it lies from the nearest pixel border.
struct PixelOf {
    int i = 0, j = 0;
    double margin = 0.0;
};
PixelOf pixel_of(const EnvMap& m, Vector3f wf) {
    const D3 w = d3(wf);
    double phi = std::atan2(w.y, w.x);
    if (phi < 0.0) phi += 2.0 * kPiD;
    const double theta = std::atan2(std::hypot(w.x, w.y), w.z);
    const double x = phi / (2.0 * kPiD) * m.width, y = theta / kPiD * m.height;
    const int i = std::min(static_cast<int>(x), m.width - 1), j = std::min(static_cast<int>(y), m.height - 1);
    const double fx = x - i, fy = y - j;
    const double margin_x = m.width == 1 ? 1.0 : std::min(fx, 1.0 - fx);  // one column wraps onto itself
    return {i, j, std::min({margin_x, fy, 1.0 - fy})};
}

// The integral of f over the sphere on a (phi, theta) grid aligned with the
// pixels: one cell per pixel in phi (the density and L are constant there) and
// ceil(512 / height) in theta, each weighted by its exact solid angle and valued
// at its centre. Exact for L; for the density (c / sin theta within a pixel) each
// cell is off by 1 - sinc(dtheta / 2) ~ dtheta^2 / 24 <= 2e-6 relative.
double integrate_env(const EnvMap& m, const std::function<double(Vector3f)>& f) {
    const int k = (512 + m.height - 1) / m.height;
    const int rows = k * m.height;
    double sum = 0.0;
    for (int r = 0; r < rows; ++r) {
        const double t0 = kPiD * r / rows, t1 = kPiD * (r + 1) / rows, tm = 0.5 * (t0 + t1);
        for (int i = 0; i < m.width; ++i) {
            const double p0 = 2.0 * kPiD * i / m.width, p1 = 2.0 * kPiD * (i + 1) / m.width, pm = 0.5 * (p0 + p1);
            const D3 w{std::sin(tm) * std::cos(pm), std::sin(tm) * std::sin(pm), std::cos(tm)};
            sum += f(f3(w)) * (p1 - p0) * (std::cos(t0) - std::cos(t1));
        }
    }
    return sum;
}

TEST(Light, EnvironmentIntegratesToOne) {
    for (const EnvMap& m : env_maps()) {
        const EnvironmentLight light(m.width, m.height, m.pixels);
        const double total = integrate_env(m, [&](Vector3f w) { return double{light.pdf({}, w)}; });
        // 2e-6 from the quadrature, and the float density's rounding.
        EXPECT_TRUE(near(total, 1.0, 1e-5)) << m.name;
    }
}

// At 4096 samples: pdf() and L() agree with the sample, L is the value of the
// pixel the test finds for wi (unless wi is within 1e-5 of a pixel's border,
// where float rounding may pick the neighbour) and positive, wi is unit, the
// distance infinite.
TEST(Light, EnvironmentSamplesAgreeWithPdfAndRadiance) {
    const Vector3f ref{1.0f, -2.0f, 0.5f};  // ignored by an environment map
    for (const EnvMap& m : env_maps()) {
        const EnvironmentLight light(m.width, m.height, m.pixels);
        Pcg32 rng(51, 2);
        Failures failures;
        for (int i = 0; i < 4096; ++i) {
            const Point2f u{rng.next_float(), rng.next_float()};
            const LightSample s = light.sample(ref, u);
            const PixelOf px = pixel_of(m, s.wi);
            const float expected = px.margin > 1e-5 ? m.at(px.i, px.j) : s.L;
            failures.check(s.pdf > 0.0f && std::isfinite(s.pdf) && light.pdf(ref, s.wi) == s.pdf &&
                               light.L(ref, s.wi) == s.L && s.L == expected && s.L > 0.0f &&
                               std::abs(norm(d3(s.wi)) - 1.0) <= 1e-6 && std::isinf(s.distance),
                           [&] {
                               std::ostringstream out;
                               out << m.name << " u=(" << u.x << ", " << u.y << "): pdf " << s.pdf << " L " << s.L
                                   << " pixel (" << px.i << ", " << px.j << ") = " << m.at(px.i, px.j);
                               return out.str();
                           });
        }
        EXPECT_TRUE(failures.result());
    }
}

TEST(Light, EnvironmentEstimateMatchesQuadrature) {
    for (const EnvMap& m : env_maps()) {
        const EnvironmentLight light(m.width, m.height, m.pixels);
        const double integral = integrate_env(m, [&](Vector3f w) { return double{light.L({}, w)}; });
        EXPECT_TRUE(near(integral, m.integral_of_L(), 1e-6 * integral)) << m.name;
        Pcg32 rng(61, 4);
        const int n = 1 << 16;
        double sum = 0.0, sum2 = 0.0;
        for (int i = 0; i < n; ++i) {
            const LightSample s = light.sample({}, {rng.next_float(), rng.next_float()});
            const double w = s.pdf > 0.0f ? double{s.L} / s.pdf : 0.0;
            sum += w;
            sum2 += w * w;
        }
        const double mean = sum / n, se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / (n - 1));
        EXPECT_TRUE(near(mean, integral, 5.0 * se + 1e-6 * integral)) << m.name;
    }
}

// Over 20000 directions spread over the sphere: pdf > 0 exactly where L > 0,
// which is exactly where the test's pixel is lit (away from borders), and L is
// that pixel's value.
TEST(Light, EnvironmentSupportIsTheLitPixels) {
    for (const EnvMap& m : env_maps()) {
        const EnvironmentLight light(m.width, m.height, m.pixels);
        Failures failures;
        const int n = 20000;
        for (int k = 0; k < n; ++k) {
            const double z = 1.0 - (2.0 * k + 1.0) / n, r = std::sqrt(1.0 - z * z);
            const double phi = k * kPiD * (3.0 - std::sqrt(5.0));
            const Vector3f w = f3({r * std::cos(phi), r * std::sin(phi), z});
            const float p = light.pdf({}, w), l = light.L({}, w);
            const PixelOf px = pixel_of(m, w);
            failures.check(p >= 0.0f && std::isfinite(p) && (p > 0.0f) == (l > 0.0f), [&] { return m.name; });
            if (px.margin > 1e-5)
                failures.check(l == m.at(px.i, px.j), [&] {
                    return m.name + ": L " + std::to_string(l) + " vs pixel " + std::to_string(m.at(px.i, px.j));
                });
        }
        EXPECT_TRUE(failures.result());
    }
}

// A 1x1 map is one cell of the (u, v) square: directions uniform in (phi, theta),
// density 1 / (2 pi^2 sin theta), not uniform over the sphere: a quarter of the
// samples have theta < pi/4 (uniform over the sphere would give 0.146).
TEST(Light, EnvironmentOneByOneMapIsUniformInPhiAndTheta) {
    const EnvironmentLight light(1, 1, {2.0f});
    for (double theta : {0.05, 0.7, 1.5, 2.9}) {
        const D3 w{std::sin(theta) * std::cos(1.0), std::sin(theta) * std::sin(1.0), std::cos(theta)};
        const Vector3f wf = f3(w);
        EXPECT_TRUE(near(light.pdf({}, wf) * 2.0 * kPiD * kPiD * std::hypot(wf.x, wf.y), 1.0, 1e-5)) << theta;
        EXPECT_EQ(light.L({}, wf), 2.0f);
    }
    Pcg32 rng(71, 1);
    const int n = 1 << 16;
    int upper = 0;
    for (int i = 0; i < n; ++i) {
        const LightSample s = light.sample({}, {rng.next_float(), rng.next_float()});
        upper += std::atan2(std::hypot(s.wi.x, s.wi.y), s.wi.z) < 0.25 * kPiD;
    }
    EXPECT_TRUE(near(upper, 0.25 * n, 5.0 * std::sqrt(n * 0.25 * 0.75)));
}

// Rows of zeros (both pole rows among them) are never sampled, and the density
// is exactly 0 everywhere in them, poles included.
TEST(Light, EnvironmentZeroRowsAreNeverSampled) {
    const EnvMap m = zero_rows_map();
    const EnvironmentLight light(m.width, m.height, m.pixels);
    Pcg32 rng(81, 1);
    Failures failures;
    for (int i = 0; i < 1 << 14; ++i) {
        const LightSample s = light.sample({}, {rng.next_float(), rng.next_float()});
        const PixelOf px = pixel_of(m, s.wi);
        failures.check(s.pdf > 0.0f && px.j % 2 == 1, [&] { return "sampled row " + std::to_string(px.j); });
    }
    for (int j = 0; j < m.height; j += 2)
        for (int k = 1; k < 40; ++k) {  // inside the row: its borders may round into a lit row
            const double theta = kPiD * (j + k / 40.0) / m.height;
            for (int c = 0; c < 24; ++c) {
                const double phi = 2.0 * kPiD * (c + 0.5) / 24;
                const Vector3f w = f3({std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)});
                failures.check(light.pdf({}, w) == 0.0f && light.L({}, w) == 0.0f,
                               [&] { return "nonzero in zero row " + std::to_string(j); });
            }
        }
    EXPECT_TRUE(failures.result());
    EXPECT_EQ(light.pdf({}, {0, 0, 1}), 0.0f);
    EXPECT_EQ(light.pdf({}, {0, 0, -1}), 0.0f);
}

// One lit pixel takes every sample, in the place the layout says: column 5 of
// 8 is phi in [5 pi/4, 3 pi/2], row 1 of 4 is theta in [pi/4, pi/2].
TEST(Light, EnvironmentSingleLitPixelTakesEverySample) {
    const EnvMap m = single_pixel_map();
    const EnvironmentLight light(m.width, m.height, m.pixels);
    Pcg32 rng(91, 1);
    Failures failures;
    for (int i = 0; i < 1 << 14; ++i) {
        const LightSample s = light.sample({}, {rng.next_float(), rng.next_float()});
        double phi = std::atan2(double{s.wi.y}, double{s.wi.x});
        if (phi < 0.0) phi += 2.0 * kPiD;
        const double theta = std::atan2(std::hypot(double{s.wi.x}, double{s.wi.y}), double{s.wi.z});
        const double slack = 1e-6;
        failures.check(s.L == 3.0f && phi >= 1.25 * kPiD - slack && phi <= 1.5 * kPiD + slack &&
                           theta >= 0.25 * kPiD - slack && theta <= 0.5 * kPiD + slack,
                       [&] { return "phi " + std::to_string(phi) + " theta " + std::to_string(theta); });
    }
    EXPECT_TRUE(failures.result());
}

// The density uses wi's own theta: within one pixel of the top row,
// pdf * sin theta is the same at theta = 0.02 and 0.7 (so pdf differs by 30x),
// which the row centre's sin would not give.
TEST(Light, EnvironmentDensityFollowsTheDirectionsOwnTheta) {
    const EnvironmentLight light(4, 1, {1.0f, 2.0f, 0.0f, 1.0f});
    const float high = light.pdf({}, f3({std::sin(0.02) * std::cos(2.0), std::sin(0.02) * std::sin(2.0), std::cos(0.02)}));
    const float low = light.pdf({}, f3({std::sin(0.7) * std::cos(2.0), std::sin(0.7) * std::sin(2.0), std::cos(0.7)}));
    EXPECT_TRUE(near(high * std::sin(0.02) / (low * std::sin(0.7)), 1.0, 1e-5));
    EXPECT_TRUE(near(high, 4.0 / 4.0 * 2.0 / (2.0 * kPiD * kPiD * std::sin(0.02)), 1e-5 * high));
}

// invert(sample(u)) = u to 1e-4. u.x is the azimuth, undefined at the poles and
// ill-conditioned near them (a float direction's 6e-8 rad is 6e-8 / sin theta
// of azimuth): it is compared only where sin theta > 1e-2.
TEST(Light, EnvironmentInverseRoundTrips) {
    for (const EnvMap& m : env_maps()) {
        const EnvironmentLight light(m.width, m.height, m.pixels);
        Pcg32 rng(101, 1);
        Failures failures;
        for (int i = 0; i < 4096; ++i) {
            const Point2f u{rng.next_float(), rng.next_float()};
            const LightSample s = light.sample({}, u);
            const Point2f back = light.invert({}, s.wi);
            const bool azimuth_defined = std::hypot(s.wi.x, s.wi.y) > 1e-2f;
            const float dx = std::abs(back.x - u.x), wrapped = std::min(dx, 1.0f - dx);
            failures.check((!azimuth_defined || wrapped <= 1e-4f) && std::abs(back.y - u.y) <= 1e-4f, [&] {
                std::ostringstream out;
                out << m.name << ": u (" << u.x << ", " << u.y << ") came back as (" << back.x << ", " << back.y << ")";
                return out.str();
            });
        }
        EXPECT_TRUE(failures.result());
    }
}

// ---- Parameters ----

TEST(Light, InvalidParametersThrow) {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    using E = std::invalid_argument;
    EXPECT_THROW(SphereLight({nan, 0, 0}, 1.0f, 1.0f), E);
    EXPECT_THROW(SphereLight({0, inf, 0}, 1.0f, 1.0f), E);
    for (float r : {0.0f, -1.0f, nan, inf, 1e30f}) EXPECT_THROW(SphereLight({0, 0, 0}, r, 1.0f), E) << r;
    for (float le : {0.0f, -1.0f, nan, inf}) EXPECT_THROW(SphereLight({0, 0, 0}, 1.0f, le), E) << le;

    EXPECT_THROW(TriangleLight({0, 0, 0}, {1, 1, 1}, {2, 2, 2}, 1.0f), E);  // collinear
    EXPECT_THROW(TriangleLight({0, 0, 0}, {0, 0, 0}, {1, 0, 0}, 1.0f), E);  // coincident
    EXPECT_THROW(TriangleLight({0, 0, nan}, {1, 0, 0}, {0, 1, 0}, 1.0f), E);
    EXPECT_THROW(TriangleLight({0, 0, 0}, {inf, 0, 0}, {0, 1, 0}, 1.0f), E);
    EXPECT_THROW(TriangleLight({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0.0f), E);
    EXPECT_THROW(SphericalTriangleLight({0, 0, 0}, {1, 1, 1}, {2, 2, 2}, 1.0f), E);
    EXPECT_THROW(SphericalTriangleLight({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, nan), E);

    EXPECT_THROW(DiskLight({0, 0, 0}, {0, 0, 0}, 1.0f, 1.0f), E);  // no normal
    EXPECT_THROW(DiskLight({0, 0, 0}, {nan, 0, 1}, 1.0f, 1.0f), E);
    EXPECT_THROW(DiskLight({inf, 0, 0}, {0, 0, 1}, 1.0f, 1.0f), E);
    for (float r : {0.0f, -2.0f, nan, inf}) EXPECT_THROW(DiskLight({0, 0, 0}, {0, 0, 1}, r, 1.0f), E) << r;
    EXPECT_THROW(DiskLight({0, 0, 0}, {0, 0, 1}, 1.0f, -1.0f), E);

    EXPECT_THROW(EnvironmentLight(0, 0, {}), E);                       // empty image
    EXPECT_THROW(EnvironmentLight(0, 4, {}), E);
    EXPECT_THROW(EnvironmentLight(-2, -3, std::vector<float>(6, 1.0f)), E);
    EXPECT_THROW(EnvironmentLight(2, 2, {1.0f, 1.0f, 1.0f}), E);       // wrong pixel count
    EXPECT_THROW(EnvironmentLight(2, 1, {1.0f, -0.5f}), E);            // negative pixel
    EXPECT_THROW(EnvironmentLight(2, 1, {1.0f, nan}), E);
    EXPECT_THROW(EnvironmentLight(2, 1, {inf, 1.0f}), E);
    EXPECT_THROW(EnvironmentLight(2, 2, std::vector<float>(4, 0.0f)), E);  // all zero
    // Valid edge cases construct.
    EXPECT_NO_THROW(EnvironmentLight(1, 1, {0.5f}));
    EXPECT_NO_THROW(SphereLight({0, 0, 0}, 1e-6f, 1e6f));
}

}  // namespace
}  // namespace warpcheck

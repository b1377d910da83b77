// Lights seen from a reference point: sample(ref, u) draws a direction wi from
// ref towards the light, with its density in SOLID ANGLE at ref; pdf(ref, wi) is
// that density for any direction; L(ref, wi) is the radiance arriving at ref
// along wi (the light's own ray intersection). The shape is pbrt-v4's
// Light::SampleLi / PDF_Li reduced to one reference point and one float of radiance.
//
// The support rule: every geometric light here emits from both sides, and pdf()
// and L() decide "the ray hits the light" with the same float intersection, so
// that pdf > 0 exactly where L > 0. As in pbrt, sample() returns the density and
// radiance of the point it drew, computed along its own path: a direction that
// rounding puts a hair outside the light (at a rim or an edge, where the
// intersection along the rounded direction misses) is returned as it is, and
// pdf() and L() are 0 there. The checks allow for such samples within a float
// step of the silhouette, and count them. Inputs u in [0,1)^2.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <cstddef>
#include <limits>
#include <numbers>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "sampling/bsdf.h"  // Frame
#include "sampling/disk.h"
#include "sampling/light_sample.h"
#include "sampling/math.h"
#include "sampling/piecewise_constant.h"
#include "sampling/sphere.h"
#include "sampling/vector.h"

namespace warpcheck {

namespace detail {

inline void require_finite(Vector3f v, const std::string& what) {
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        throw std::invalid_argument(what + " must be finite");
}

inline void require_radiance(float Le, const std::string& light) {
    // Le > 0: with Le = 0, L would be 0 where pdf > 0 and the support rule would fail.
    if (!(Le > 0.0f) || !std::isfinite(Le))
        throw std::invalid_argument(light + ": Le must be positive and finite, got " + std::to_string(Le));
}

/// Where a ray from ref along the unit wi meets the light: t > 0 on a hit (t = 0
/// means a miss), with |cos| of the angle between wi and the light's normal there.
struct RayHit {
    float t = 0.0f;
    float abs_cos = 0.0f;
    float b1 = 0.0f, b2 = 0.0f;  ///< barycentrics of p1 and p2 (triangles only)
    bool hit() const { return t > 0.0f; }
};

/// The sample towards a point drawn by area on a planar light (unit normal n,
/// area A): the direction, the area density converted to solid angle at ref,
/// dist^2 / (|cos at the light| A), and the distance; no sample where the
/// point is ref or seen edge-on.
inline LightSample toward_area_point(Vector3f ref, Vector3f point, Vector3f n, float area, float Le) {
    const Vector3f d = point - ref;
    const float dist2 = dot(d, d);
    const float dist = std::sqrt(dist2);
    const Vector3f wi = (1.0f / dist) * d;
    const float abs_cos = std::abs(dot(n, wi));
    if (!(dist > 0.0f && abs_cos > 0.0f)) return {};
    return {wi, dist2 / (abs_cos * area), Le, dist};
}

/// Whether a planar light is seen edge-on within the float resolution of a
/// direction from a point at offset d from one of its points (n its unit
/// normal, `extent` at least the distance from that point to any other of
/// the light), from the height h = n . d and d . d:
///  - the height below its own rounding, |h| <= 2^-21 |d| (computed in float
///    from a rounded difference, it is off by a few ulps of |d|, so its sign
///    is not determined): the point lies in the light's plane as far as
///    float can tell;
///  - or the light's angular height under 2^-21 rad (8 ulps of a unit
///    vector's components) from wherever it is seen: at most extent |h| / D^2
///    for D = |d| - extent, the nearest the light can be (only where D > 0).
/// No float direction then resolves the light: a ray along one may meet it
/// or not by rounding, and its sampled directions land on either side of it
/// at random. Such a light gives no sample and a pdf of 0.
inline bool seen_edge_on(float height, float d2, float extent) {
    const double h = height, dd = d2, e = extent;
    if (h * h <= 0x1p-42 * dd) return true;
    const double near = std::sqrt(dd) - e;
    return near > 0.0 && h * h * e * e <= 0x1p-42 * near * near * near * near;
}
inline bool seen_edge_on(Vector3f n, Vector3f d, float extent) { return seen_edge_on(dot(n, d), dot(d, d), extent); }

/// A triangle's geometry: the area warp, the ray intersection and the change
/// of measure from area to solid angle, shared by the two triangle lights.
class Triangle {
public:
    Triangle(Vector3f p0, Vector3f p1, Vector3f p2, const std::string& light)
        : p0_(p0), e1_(p1 - p0), e2_(p2 - p0) {
        require_finite(p0, light + ": p0");
        require_finite(p1, light + ": p1");
        require_finite(p2, light + ": p2");
        const Vector3f normal = cross(e1_, e2_);
        twice_area_ = length(normal);
        // Relative to the edges: a sliver whose smallest angle's sine is below
        // 2^-20 has a normal made of rounding error.
        if (!(twice_area_ > 0x1p-20f * length(e1_) * length(e2_)) || !std::isfinite(twice_area_))
            throw std::invalid_argument(light + ": degenerate triangle (its vertices are collinear or coincide)");
        n_ = (1.0f / twice_area_) * normal;
        area_ = 0.5f * twice_area_;
        extent_ = std::max({length(e1_), length(e2_), length(e2_ - e1_)});
    }

    Vector3f p0() const { return p0_; }
    Vector3f p1() const { return p0_ + e1_; }
    Vector3f p2() const { return p0_ + e2_; }
    float area() const { return area_; }

    /// Whether the triangle is seen edge-on from ref within float resolution (seen_edge_on).
    bool in_plane(Vector3f ref) const { return seen_edge_on(n_, ref - p0_, extent_); }

    /// Uniform by area, the square-root warp: b1 = s (1 - u.y), b2 = s u.y with
    /// s = sqrt(u.x), so the point p0 + b1 e1 + b2 e2 has density 1/area.
    Vector3f sample_area(Point2f u) const {
        const float s = std::sqrt(u.x);
        return p0_ + (s * (1.0f - u.y)) * e1_ + (s * u.y) * e2_;
    }

    /// The u that sample_area maps to the point with barycentrics (b1, b2).
    static Point2f invert_area(float b1, float b2) {
        const float s = b1 + b2;
        const float uy = s > 0.0f ? b2 / s : 0.0f;
        return {std::clamp(s * s, 0.0f, kOneMinusEpsilon), std::clamp(uy, 0.0f, kOneMinusEpsilon)};
    }

    /// Möller–Trumbore, two-sided, edges included. det = e1 . (wi x e2) = -wi . (e1 x e2),
    /// so |cos| at the light is |det| / |e1 x e2|, nonzero whenever det is.
    RayHit intersect(Vector3f ref, Vector3f wi) const {
        const Vector3f pvec = cross(wi, e2_);
        const float det = dot(e1_, pvec);
        if (det == 0.0f) return {};
        const float inv_det = 1.0f / det;
        const Vector3f tvec = ref - p0_;
        const float b1 = dot(tvec, pvec) * inv_det;
        if (!(b1 >= 0.0f && b1 <= 1.0f)) return {};
        const Vector3f qvec = cross(tvec, e1_);
        const float b2 = dot(wi, qvec) * inv_det;
        if (!(b2 >= 0.0f && b1 + b2 <= 1.0f)) return {};
        const float t = dot(e2_, qvec) * inv_det;
        // Edge-on last (tvec is ref - p0): a quadrature evaluates millions of directions, most of them misses.
        if (!(t > 0.0f) || seen_edge_on(dot(n_, tvec), dot(tvec, tvec), extent_)) return {};
        return {t, std::abs(det) / twice_area_, b1, b2};
    }

    /// Area density 1/area converted to solid angle at ref: dist^2 / (|cos| area).
    float area_pdf(const RayHit& h) const { return h.hit() ? h.t * h.t / (h.abs_cos * area_) : 0.0f; }

    /// One area sample converted to solid angle at the point drawn: dist^2 /
    /// (|cos at the light| area), whether or not the rounded direction's own
    /// intersection finds the triangle.
    LightSample sample_by_area(Vector3f ref, Point2f u, float Le) const {
        if (in_plane(ref)) return {};
        return toward_area_point(ref, sample_area(u), n_, area_, Le);
    }

    /// The distance along wi from ref to the triangle's plane (0 where wi is parallel to it).
    float plane_distance(Vector3f ref, Vector3f wi) const {
        const float c = dot(n_, wi);
        return c != 0.0f ? dot(n_, p0_ - ref) / c : 0.0f;
    }

private:
    Vector3f p0_, e1_, e2_, n_;
    float twice_area_ = 0.0f, area_ = 0.0f, extent_ = 0.0f;
};

/// A 3-vector of doubles for the spherical triangle's trigonometry (see there).
struct Vec3d {
    double x = 0.0, y = 0.0, z = 0.0;
};
inline Vec3d to_double(Vector3f v) { return {v.x, v.y, v.z}; }
inline Vec3d operator+(Vec3d a, Vec3d b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3d operator-(Vec3d a, Vec3d b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3d operator*(double s, Vec3d v) { return {s * v.x, s * v.y, s * v.z}; }
inline double dot(Vec3d a, Vec3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3d cross(Vec3d a, Vec3d b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline double length(Vec3d v) { return std::sqrt(dot(v, v)); }
inline Vec3d normalize(Vec3d v) { return (1.0 / length(v)) * v; }

/// The angle between two vectors, atan2(|a x b|, a . b): accurate at every angle
/// (acos of the dot product loses half the digits near 0 and pi).
inline double angle_between(Vec3d a, Vec3d b) { return std::atan2(length(cross(a, b)), dot(a, b)); }

/// Solid angle of the spherical triangle of the unit vectors a, b, c (Van
/// Oosterom and Strackee 1983): tan(Omega / 2) = |a . (b x c)| / (1 + a.b + b.c + c.a).
/// No cancellation for small triangles, unlike the spherical excess alpha + beta + gamma - pi.
inline double solid_angle(Vec3d a, Vec3d b, Vec3d c, double triple) {
    return 2.0 * std::atan2(std::abs(triple), 1.0 + dot(a, b) + dot(b, c) + dot(c, a));
}

}  // namespace detail

/// A sphere of radius r and radiance Le. From outside (|ref - centre| > r):
/// uniform over the cone of directions that meets the sphere, density
/// 1 / (2 pi (1 - cos theta_max)) per solid angle, sin^2 theta_max = r^2 / d^2;
/// distance is the nearest intersection. From inside (d <= r): uniform by AREA
/// over the sphere, converted to solid angle: dist^2 / (|cos at the light| 4 pi r^2).
class SphereLight {
public:
    SphereLight(Vector3f center, float radius, float Le) : c_(center), r_(radius), Le_(Le) {
        detail::require_finite(center, "sphere_light: center");
        if (!(radius > 0.0f) || !std::isfinite(radius * radius))
            throw std::invalid_argument("sphere_light: radius must be positive and finite (with a finite square), got " +
                                        std::to_string(radius));
        detail::require_radiance(Le, "sphere_light");
    }

    LightSample sample(Vector3f ref, Point2f u) const {
        const Vector3f oc = c_ - ref;
        if (!outside(oc)) return sample_inside(ref, u);
        const Cone cone = cone_at(oc);
        const Frame frame = Frame::around(cone.axis);
        // Uniform in cos theta over the cap; sin theta from 1 - cos theta, which
        // keeps its digits when the cone is narrow (cos theta rounds to 1 there).
        const float one_minus_cos = u.x * cone.one_minus_cos_max;
        const float sin_theta = safe_sqrt(one_minus_cos * (2.0f - one_minus_cos));
        const SinCos phi = sin_cos(kTwoPi * u.y);
        const Vector3f wi = frame.to_world(sin_theta * phi.cos, sin_theta * phi.sin, 1.0f - one_minus_cos);
        // At the cone's rim the rounded wi may graze past the sphere: the
        // distance is then the tangent point's, sqrt(d^2 - r^2).
        const detail::RayHit h = intersect(ref, wi);
        const float d = length(oc);
        return {wi, cone.pdf, Le_, h.hit() ? h.t : safe_sqrt((d - r_) * (d + r_))};
    }

    /// The cone's density where the ray hits (outside), the converted area density (inside); 0 on a miss.
    float pdf(Vector3f ref, Vector3f wi) const {
        const detail::RayHit h = intersect(ref, wi);
        if (!h.hit()) return 0.0f;
        const Vector3f oc = c_ - ref;
        if (outside(oc)) return cone_at(oc).pdf;
        return h.t * h.t / (h.abs_cos * 4.0f * kPi * r_ * r_);
    }

    float L(Vector3f ref, Vector3f wi) const { return intersect(ref, wi).hit() ? Le_ : 0.0f; }

private:
    struct Cone {
        Vector3f axis;
        float one_minus_cos_max = 0.0f;
        float pdf = 0.0f;
    };

    /// The one test of which regime applies, shared by sample and pdf.
    bool outside(Vector3f oc) const { return dot(oc, oc) > r_ * r_; }

    Cone cone_at(Vector3f oc) const {
        const float d = length(oc);
        // sin^2 from r/d and cos from (d - r)(d + r): neither cancels, for a far
        // small sphere (r/d -> 0) or a near one (d -> r). 1 - cos = sin^2 / (1 + cos).
        const float sin_max = r_ / d;
        const float sin2_max = sin_max * sin_max;
        const float cos_max = std::min(safe_sqrt((d - r_) * (d + r_)) / d, 1.0f);
        const float one_minus_cos_max = sin2_max / (1.0f + cos_max);
        return {(1.0f / d) * oc, one_minus_cos_max, 1.0f / (kTwoPi * one_minus_cos_max)};
    }

    LightSample sample_inside(Vector3f ref, Point2f u) const {
        const Vector3f n = UniformSphere{}.sample(u);
        const Vector3f d = (c_ + r_ * n) - ref;
        const float dist2 = dot(d, d);
        const float dist = std::sqrt(dist2);
        const Vector3f wi = (1.0f / dist) * d;
        const float abs_cos = std::abs(dot(wi, n));
        if (!(dist > 0.0f && abs_cos > 0.0f) || !intersect(ref, wi).hit()) return {};
        return {wi, dist2 / (abs_cos * 4.0f * kPi * r_ * r_), Le_, dist};
    }

    /// The ray ref + t wi against the sphere, t > 0: the nearest root from outside, the
    /// only positive root from inside. The perpendicular from the centre to the
    /// ray, oc - (oc . wi) wi, is computed as a vector, which keeps the discriminant
    /// r^2 - |perp|^2 accurate where d^2 - (oc . wi)^2 would cancel. abs_cos is
    /// |cos| at the light, sqrt(disc) / r.
    detail::RayHit intersect(Vector3f ref, Vector3f wi) const {
        const Vector3f oc = c_ - ref;
        const float b = dot(oc, wi);
        const Vector3f perp = oc - b * wi;
        const float r2 = r_ * r_;
        const float disc = r2 - dot(perp, perp);
        if (!(disc >= 0.0f)) return {};
        const float sqrt_disc = std::sqrt(disc);
        const float d = length(oc);
        float t;
        if (outside(oc)) {
            if (!(b > 0.0f)) return {};
            t = (d - r_) * (d + r_) / (b + sqrt_disc);  // the near root as c / q: no cancellation
        } else {
            t = b >= 0.0f ? b + sqrt_disc : (r_ - d) * (r_ + d) / (sqrt_disc - b);
        }
        if (!(t > 0.0f) || !(sqrt_disc > 0.0f)) return {};
        return {t, sqrt_disc / r_};
    }

    Vector3f c_;
    float r_, Le_;
};

/// A triangle of radiance Le, sampled uniformly by AREA (the square-root warp)
/// and converted to solid angle: density dist^2 / (|cos theta_light| area). No
/// sample from a ref in the triangle's plane.
class TriangleLight {
public:
    TriangleLight(Vector3f p0, Vector3f p1, Vector3f p2, float Le) : tri_(p0, p1, p2, "triangle_light"), Le_(Le) {
        detail::require_radiance(Le, "triangle_light");
    }

    LightSample sample(Vector3f ref, Point2f u) const { return tri_.sample_by_area(ref, u, Le_); }
    float pdf(Vector3f ref, Vector3f wi) const { return tri_.area_pdf(tri_.intersect(ref, wi)); }
    float L(Vector3f ref, Vector3f wi) const { return tri_.intersect(ref, wi).hit() ? Le_ : 0.0f; }

private:
    detail::Triangle tri_;
    float Le_;
};

/// A triangle of radiance Le, sampled uniformly by SOLID ANGLE at ref (Arvo
/// 1995, "Stratified sampling of spherical triangles"): density 1 / Omega.
/// Outside [kMinSolidAngle, kMaxSolidAngle] it falls back to area sampling, and
/// the density is then the area density converted to solid angle; pdf() applies
/// the same rule, decided by Omega at ref alone.
class SphericalTriangleLight {
public:
    /// Below this (steradians) the triangle is sampled by area. Arvo's map runs in
    /// double here, so it keeps its accuracy far below pbrt-v4's float cut-off
    /// (3e-4); what limits it is the float direction it returns: at 1e-5 sr (a
    /// triangle ~5e-3 rad across) a float direction's 6e-8 rad step is ~1e-5 of the
    /// triangle, and area sampling is uniform in solid angle to ~0.5% anyway.
    static constexpr double kMinSolidAngle = 1e-5;
    /// Above this (2 pi - 0.013) the triangle fills nearly a hemisphere: ref is
    /// within ~1e-3 of the triangle's size from its plane, inside its outline.
    /// There the angles tend to pi and Arvo's q tends to 0 / 0; the double map
    /// still held to 2 pi - 1e-4 in our tests, but closer than that the float
    /// directions it returns graze the triangle and lose its uniformity.
    static constexpr double kMaxSolidAngle = 6.27;

    SphericalTriangleLight(Vector3f p0, Vector3f p1, Vector3f p2, float Le)
        : tri_(p0, p1, p2, "spherical_triangle_light"), Le_(Le) {
        detail::require_radiance(Le, "spherical_triangle_light");
    }

    LightSample sample(Vector3f ref, Point2f u) const {
        if (tri_.in_plane(ref)) return {};
        const View& view = view_from(ref);
        if (!view.by_solid_angle) return tri_.sample_by_area(ref, u, Le_);
        const detail::Vec3d w = arvo(view, u);
        const Vector3f wi{static_cast<float>(w.x), static_cast<float>(w.y), static_cast<float>(w.z)};
        return {wi, static_cast<float>(1.0 / view.omega), Le_, tri_.plane_distance(ref, wi)};
    }

    float pdf(Vector3f ref, Vector3f wi) const {
        const detail::RayHit h = tri_.intersect(ref, wi);
        if (!h.hit()) return 0.0f;
        const View& view = view_from(ref);
        return view.by_solid_angle ? static_cast<float>(1.0 / view.omega) : tri_.area_pdf(h);
    }

    float L(Vector3f ref, Vector3f wi) const { return tri_.intersect(ref, wi).hit() ? Le_ : 0.0f; }

    /// The u that sample maps to wi (Arvo's map run backwards, defined for
    /// any direction, so a sample rounded a hair off the triangle's edge still
    /// comes back to its u); in the area regime, the square-root warp's
    /// inverse, (0, 0) for a wi that misses.
    Point2f invert(Vector3f ref, Vector3f wi) const {
        if (tri_.in_plane(ref) || !(std::isfinite(wi.x) && std::isfinite(wi.y) && std::isfinite(wi.z))) return {};
        const View& view = view_from(ref);
        if (view.by_solid_angle) return arvo_inverse(view, detail::normalize(detail::to_double(wi)));
        const detail::RayHit h = tri_.intersect(ref, wi);
        return h.hit() ? detail::Triangle::invert_area(h.b1, h.b2) : Point2f{};
    }

private:
    /// The triangle seen from ref: unit vectors a, b, c to p0, p1, p2, its solid
    /// angle, the angle alpha at a and cos of the side ab. Double throughout: for a
    /// small triangle, Arvo's q is the cosine of an arc near 0 and sqrt(1 - q^2)
    /// keeps only half of q's digits, which float does not have to spare.
    struct View {
        detail::Vec3d a, b, c;
        double omega = 0.0, alpha = 0.0, cos_c = 0.0;
        bool by_solid_angle = false;
    };

    const View& view_from(Vector3f ref) const {
        const Vector3f a = tri_.p0(), b = tri_.p1(), c = tri_.p2();
        return detail::memo_view<View>(std::array<float, 12>{a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z, ref.x, ref.y, ref.z},
                                       [&] { return compute_view(ref); });
    }

    View compute_view(Vector3f ref) const {
        using namespace detail;
        const Vec3d o = to_double(ref);
        const Vec3d pa = to_double(tri_.p0()) - o, pb = to_double(tri_.p1()) - o, pc = to_double(tri_.p2()) - o;
        View v;
        v.a = normalize(pa);
        v.b = normalize(pb);
        v.c = normalize(pc);
        // The triple product from the edges: (pa . (e1 x e2)) is the same determinant,
        // without the cancellation of crossing two nearly parallel long vectors.
        const double triple = dot(pa, cross(pb - pa, pc - pa)) / (length(pa) * length(pb) * length(pc));
        v.omega = solid_angle(v.a, v.b, v.c, triple);
        // The angle at a between the arcs towards b and c: between their tangents at a.
        v.alpha = angle_between(v.b - dot(v.a, v.b) * v.a, v.c - dot(v.a, v.c) * v.a);
        v.cos_c = dot(v.a, v.b);
        v.by_solid_angle = v.omega >= kMinSolidAngle && v.omega <= kMaxSolidAngle;
        return v;
    }

    /// Arvo's map: u.x picks the sub-triangle a b c' of area u.x Omega, with c' on
    /// the arc ac (q = cos of the arc a c'); u.y picks the point on the arc b c'
    /// uniformly in 1 - cos of its distance from b, which is uniform in solid angle.
    static detail::Vec3d arvo(const View& v, Point2f u) {
        using namespace detail;
        const double area = static_cast<double>(u.x) * v.omega;
        const SinCosDouble sc = sin_cos_double(area - v.alpha);
        const double sin_alpha = std::sin(v.alpha), cos_alpha = std::cos(v.alpha);
        // Arvo's u = cos(area - alpha) - cos(alpha), as a product: no cancellation when area is small.
        const double uu = 2.0 * std::sin(0.5 * area) * std::sin(v.alpha - 0.5 * area);
        const double vv = sc.sin + sin_alpha * v.cos_c;
        const double q = std::clamp(((vv * sc.cos - uu * sc.sin) * cos_alpha - vv) /
                                        ((vv * sc.sin + uu * sc.cos) * sin_alpha), -1.0, 1.0);
        const Vec3d c_perp = normalize(v.c - dot(v.c, v.a) * v.a);
        const Vec3d c_hat = q * v.a + std::sqrt((1.0 - q) * (1.0 + q)) * c_perp;
        // 1 - z = u.y (1 - c'.b), with 1 - c'.b = |c' - b|^2 / 2 (no cancellation).
        const Vec3d cb = c_hat - v.b;
        const double one_minus_z = static_cast<double>(u.y) * 0.5 * dot(cb, cb);
        const Vec3d b_perp = normalize(c_hat - dot(c_hat, v.b) * v.b);
        return normalize((1.0 - one_minus_z) * v.b + std::sqrt(one_minus_z * (2.0 - one_minus_z)) * b_perp);
    }

    /// Arvo's map backwards: c' is where the great circle through b and w meets
    /// the arc ac; u.x is the area of a b c' over Omega, u.y = (1 - w.b) / (1 - c'.b).
    static Point2f arvo_inverse(const View& v, detail::Vec3d w) {
        using namespace detail;
        Vec3d c_hat = cross(cross(v.b, w), cross(v.a, v.c));
        const double len = length(c_hat);
        if (!(len > 0.0)) return {0.0f, 0.0f};  // w = b, which every u.x maps to from u.y = 0
        // Of the two points where the circles cross, the one on the arc ac (the short one).
        c_hat = (dot(c_hat, v.a + v.c) < 0.0 ? -1.0 / len : 1.0 / len) * c_hat;
        const double triple = dot(v.a, cross(v.b, c_hat));
        const double ux = solid_angle(v.a, v.b, c_hat, triple) / v.omega;
        const Vec3d wb = w - v.b, cb = c_hat - v.b;
        const double uy = dot(wb, wb) / dot(cb, cb);
        const double top = static_cast<double>(kOneMinusEpsilon);
        return {static_cast<float>(std::clamp(ux, 0.0, top)), static_cast<float>(std::clamp(uy, 0.0, top))};
    }

    detail::Triangle tri_;
    float Le_;
};

/// A rectangle of radiance Le (both sides emit) with a corner and two
/// perpendicular edges, sampled uniformly by SOLID ANGLE at ref (Ureña,
/// Fajardo and King 2013, "An area-preserving parametrization for spherical
/// rectangles"): density 1 / Omega. As the spherical triangle, it is sampled
/// by area outside [kMinSolidAngle, kMaxSolidAngle] (the density then the
/// area density converted to solid angle), and pdf() applies the same rule,
/// decided by Omega at ref alone. The map runs in double, for the reasons the
/// triangle's does.
class SphericalRectangleLight {
public:
    static constexpr double kMinSolidAngle = SphericalTriangleLight::kMinSolidAngle;
    static constexpr double kMaxSolidAngle = SphericalTriangleLight::kMaxSolidAngle;

    /// The rectangle corner + a ex + b ey, a and b in [0, 1]; ex and ey
    /// perpendicular to within 1e-6 of the product of their lengths.
    SphericalRectangleLight(Vector3f corner, Vector3f ex, Vector3f ey, float Le)
        : p_(corner), ex_(ex), ey_(ey), Le_(Le) {
        detail::require_finite(corner, "spherical_rectangle_light: corner");
        detail::require_finite(ex, "spherical_rectangle_light: ex");
        detail::require_finite(ey, "spherical_rectangle_light: ey");
        detail::require_radiance(Le, "spherical_rectangle_light");
        const float lx = length(ex), ly = length(ey);
        if (!(lx > 0.0f && ly > 0.0f) || !std::isfinite(lx * ly))
            throw std::invalid_argument("spherical_rectangle_light: the edges must have finite nonzero lengths");
        if (!(std::abs(dot(ex, ey)) <= 1e-6f * lx * ly))
            throw std::invalid_argument("spherical_rectangle_light: the edges must be perpendicular");
        n_ = normalize(cross(ex, ey));
        area_ = lx * ly;
        extent_ = std::sqrt(lx * lx + ly * ly);
        inv_lx2_ = 1.0f / (lx * lx);
        inv_ly2_ = 1.0f / (ly * ly);
    }

    LightSample sample(Vector3f ref, Point2f u) const {
        if (detail::seen_edge_on(n_, p_ - ref, extent_)) return {};
        const View& view = view_from(ref);
        if (!view.by_solid_angle) return sample_by_area(ref, u);
        const detail::Vec3d w = urena(view, u);
        const Vector3f wi{static_cast<float>(w.x), static_cast<float>(w.y), static_cast<float>(w.z)};
        const float cos_n = dot(wi, n_);
        return {wi, static_cast<float>(1.0 / view.omega), Le_, cos_n != 0.0f ? dot(n_, p_ - ref) / cos_n : 0.0f};
    }

    float pdf(Vector3f ref, Vector3f wi) const {
        const detail::RayHit h = intersect(ref, wi);
        if (!h.hit()) return 0.0f;
        const View& view = view_from(ref);
        return view.by_solid_angle ? static_cast<float>(1.0 / view.omega) : h.t * h.t / (h.abs_cos * area_);
    }

    float L(Vector3f ref, Vector3f wi) const { return intersect(ref, wi).hit() ? Le_ : 0.0f; }

    /// The u that sample maps to wi: the map run backwards, defined for any
    /// direction towards the rectangle's plane (its point there clamped into
    /// the rectangle), so a sample rounded a hair off an edge comes back to
    /// its u; in the area regime, the edge fractions of the hit; (0, 0) for a
    /// direction away from the plane.
    Point2f invert(Vector3f ref, Vector3f wi) const {
        if (detail::seen_edge_on(n_, p_ - ref, extent_) || !(std::isfinite(wi.x) && std::isfinite(wi.y) && std::isfinite(wi.z)))
            return {};
        const View& view = view_from(ref);
        const float top = kOneMinusEpsilon;
        if (!view.by_solid_angle) {
            const detail::RayHit h = intersect(ref, wi);
            return h.hit() ? Point2f{std::clamp(h.b1, 0.0f, top), std::clamp(h.b2, 0.0f, top)} : Point2f{};
        }
        return urena_inverse(view, detail::normalize(detail::to_double(wi)));
    }

private:
    /// The rectangle in a frame at ref: x and y along the edges, z towards
    /// the side ref is on (so that the rectangle lies at z0 < 0), the corners
    /// at (x0 or x1, y0 or y1, z0); the inner normals of the four planes
    /// through ref and an edge, the solid angle and the constants of the map.
    struct View {
        detail::Vec3d x, y, z;
        double x0 = 0.0, x1 = 0.0, y0 = 0.0, y1 = 0.0, z0 = 0.0;
        detail::Vec3d n0, n2;
        double b0 = 0.0, b1 = 0.0, k = 0.0, omega = 0.0;
        bool by_solid_angle = false;
    };

    const View& view_from(Vector3f ref) const {
        return detail::memo_view<View>(std::array<float, 12>{p_.x, p_.y, p_.z, ex_.x, ex_.y, ex_.z, ey_.x, ey_.y, ey_.z,
                                                             ref.x, ref.y, ref.z},
                                       [&] { return compute_view(ref); });
    }

    View compute_view(Vector3f ref) const {
        using namespace detail;
        View v;
        const Vec3d ex = to_double(ex_), ey = to_double(ey_);
        v.x = normalize(ex);
        v.y = normalize(ey);
        v.z = cross(v.x, v.y);
        const Vec3d d = to_double(p_) - to_double(ref);
        v.x0 = dot(d, v.x);
        v.y0 = dot(d, v.y);
        v.z0 = dot(d, v.z);
        if (v.z0 > 0.0) {
            v.z0 = -v.z0;
            v.z = -1.0 * v.z;
        }
        v.x1 = v.x0 + length(ex);
        v.y1 = v.y0 + length(ey);
        // The planes through ref and the edges y = y0, x = x1, y = y1, x = x0.
        v.n0 = normalize(Vec3d{0.0, v.z0, -v.y0});
        const Vec3d n1 = normalize(Vec3d{-v.z0, 0.0, v.x1});
        v.n2 = normalize(Vec3d{0.0, -v.z0, v.y1});
        const Vec3d n3 = normalize(Vec3d{v.z0, 0.0, -v.x0});
        // The rectangle's angles, each between two of the planes (atan2: accurate at every angle).
        const double g2 = angle_between(-1.0 * v.n2, n3), g3 = angle_between(-1.0 * n3, v.n0);
        v.b0 = v.n0.z;
        v.b1 = v.n2.z;
        v.k = 2.0 * std::numbers::pi - g2 - g3;
        v.omega = sub_angle(v, n1);
        v.by_solid_angle = v.omega >= kMinSolidAngle && v.omega <= kMaxSolidAngle;
        return v;
    }

    /// The solid angle of the part x0 <= x <= (the edge whose plane's normal is n1).
    static double sub_angle(const View& v, const detail::Vec3d& n1) {
        return detail::angle_between(-1.0 * v.n0, n1) + detail::angle_between(-1.0 * n1, v.n2) - v.k;
    }

    /// Ureña et al.'s map: u.x picks xu so that the part x0 <= x <= xu has
    /// solid angle u.x Omega; u.y picks yv uniformly in the cosine-like h of
    /// the column at xu, which is uniform in solid angle along it.
    static detail::Vec3d urena(const View& v, Point2f u) {
        using namespace detail;
        const double au = static_cast<double>(u.x) * v.omega + v.k;
        const double fu = (std::cos(au) * v.b0 - v.b1) / std::sin(au);
        const double cu = std::clamp(std::copysign(1.0, fu) / std::sqrt(fu * fu + v.b0 * v.b0), -1.0, 1.0);
        const double xu = std::clamp(-(cu * v.z0) / std::sqrt(std::max(0.0, (1.0 - cu) * (1.0 + cu))), v.x0, v.x1);
        const double dd = std::sqrt(xu * xu + v.z0 * v.z0);
        const double h0 = v.y0 / std::sqrt(dd * dd + v.y0 * v.y0), h1 = v.y1 / std::sqrt(dd * dd + v.y1 * v.y1);
        const double hv = h0 + static_cast<double>(u.y) * (h1 - h0);
        const double yv = hv * hv < 1.0 - 1e-12 ? hv * dd / std::sqrt((1.0 - hv) * (1.0 + hv)) : v.y1;
        return normalize(xu * v.x + yv * v.y + v.z0 * v.z);
    }

    /// The map backwards: wi's point (xu, yv) on the rectangle's plane, u.x
    /// the solid angle of the part x0 <= x <= xu over Omega, u.y where yv's h
    /// lies between the column's ends.
    static Point2f urena_inverse(const View& v, detail::Vec3d w) {
        using namespace detail;
        const double wz = dot(w, v.z);
        if (!(wz < 0.0)) return {};
        const double t = v.z0 / wz;
        const double xu = std::clamp(t * dot(w, v.x), v.x0, v.x1), yv = std::clamp(t * dot(w, v.y), v.y0, v.y1);
        const double ux = sub_angle(v, normalize(Vec3d{-v.z0, 0.0, xu})) / v.omega;
        const double dd = std::sqrt(xu * xu + v.z0 * v.z0);
        const double h0 = v.y0 / std::sqrt(dd * dd + v.y0 * v.y0), h1 = v.y1 / std::sqrt(dd * dd + v.y1 * v.y1);
        const double uy = (yv / std::sqrt(dd * dd + yv * yv) - h0) / (h1 - h0);
        const double top = static_cast<double>(kOneMinusEpsilon);
        return {static_cast<float>(std::clamp(ux, 0.0, top)), static_cast<float>(std::clamp(uy, 0.0, top))};
    }

    /// Uniform by area, converted to solid angle at the point drawn.
    LightSample sample_by_area(Vector3f ref, Point2f u) const {
        return detail::toward_area_point(ref, p_ + u.x * ex_ + u.y * ey_, n_, area_, Le_);
    }

    /// The ray against the rectangle's plane, then the hit's edge fractions
    /// (in b1 and b2), both in [0, 1] on a hit.
    detail::RayHit intersect(Vector3f ref, Vector3f wi) const {
        const float h = dot(n_, p_ - ref);
        const float cos_n = dot(wi, n_);
        if (cos_n == 0.0f) return {};
        const float t = h / cos_n;
        if (!(t > 0.0f)) return {};
        const Vector3f q = (ref + t * wi) - p_;
        const float a = dot(q, ex_) * inv_lx2_, b = dot(q, ey_) * inv_ly2_;
        if (!(a >= 0.0f && a <= 1.0f && b >= 0.0f && b <= 1.0f)) return {};
        const Vector3f d = p_ - ref;
        if (detail::seen_edge_on(h, dot(d, d), extent_)) return {};  // last: most directions miss
        return {t, std::abs(cos_n), a, b};
    }

    Vector3f p_, ex_, ey_, n_{};
    float Le_, area_ = 0.0f, extent_ = 0.0f, inv_lx2_ = 0.0f, inv_ly2_ = 0.0f;
};

/// A disk of radius r around center, facing along normal (both sides emit),
/// radiance Le: uniform by AREA (Shirley and Chiu's concentric map), converted
/// to solid angle: density dist^2 / (|cos theta_light| pi r^2). No sample from
/// a ref in the disk's plane.
class DiskLight {
public:
    DiskLight(Vector3f center, Vector3f normal, float radius, float Le) : c_(center), r_(radius), Le_(Le) {
        detail::require_finite(center, "disk_light: center");
        detail::require_finite(normal, "disk_light: normal");
        const float len = length(normal);
        if (!(len > 0.0f) || !std::isfinite(len))
            throw std::invalid_argument("disk_light: normal must be a nonzero finite vector");
        if (!(radius > 0.0f) || !std::isfinite(radius * radius))
            throw std::invalid_argument("disk_light: radius must be positive and finite (with a finite square), got " +
                                        std::to_string(radius));
        detail::require_radiance(Le, "disk_light");
        frame_ = Frame::around((1.0f / len) * normal);
        area_ = kPi * radius * radius;
    }

    LightSample sample(Vector3f ref, Point2f u) const {
        if (detail::seen_edge_on(frame_.n, c_ - ref, 2.0f * r_)) return {};
        const Point2f p = UniformDiskConcentric{}.sample(u);
        return detail::toward_area_point(ref, c_ + frame_.to_world(r_ * p.x, r_ * p.y, 0.0f), frame_.n, area_, Le_);
    }

    float pdf(Vector3f ref, Vector3f wi) const {
        const detail::RayHit h = intersect(ref, wi);
        return h.hit() ? h.t * h.t / (h.abs_cos * area_) : 0.0f;
    }

    float L(Vector3f ref, Vector3f wi) const { return intersect(ref, wi).hit() ? Le_ : 0.0f; }

private:
    /// The ray against the disk's plane (t = h / (wi . n), h the plane's signed
    /// distance from ref), then the hit point's distance from the centre.
    detail::RayHit intersect(Vector3f ref, Vector3f wi) const {
        const float h = dot(frame_.n, c_ - ref);
        const float cos_n = dot(wi, frame_.n);
        if (cos_n == 0.0f) return {};
        const float t = h / cos_n;
        if (!(t > 0.0f)) return {};
        const Vector3f q = (ref + t * wi) - c_;
        if (!(dot(q, q) <= r_ * r_)) return {};
        const Vector3f d = c_ - ref;
        if (detail::seen_edge_on(h, dot(d, d), 2.0f * r_)) return {};  // last: most directions miss
        return {t, std::abs(cos_n)};
    }

    Vector3f c_;
    float r_, Le_;
    Frame frame_{};
    float area_ = 0.0f;
};

/// An environment map of radiance, equirectangular: width x height pixels, row
/// major, row 0 at the top (theta = 0, +z), column 0 at phi = 0; pixel (i, j)
/// covers phi in [2 pi i / width, 2 pi (i + 1) / width) and theta in
/// [pi j / height, pi (j + 1) / height). L(ref, wi) is the pixel's value (ref is
/// ignored). Sampling picks (u, v) = (phi / 2 pi, theta / pi) from a 2D
/// piecewise-constant density p(u, v) with weights pixel * sin(theta at the
/// pixel row's centre); the density per solid angle is p(u, v) / (2 pi^2 sin theta).
///
/// The weight's sin is the row centre's, a choice that only shapes which pixels
/// are drawn how often; the density returned is not the weight but the
/// distribution actually drawn, so its sin theta is wi's own (dw = 2 pi^2
/// sin theta du dv), not the row centre's and not the row's mean: within a
/// pixel the directions are uniform in (u, v), hence denser near the poles.
/// A pixel of 0 has weight exactly 0: never drawn, density exactly 0 there.
class EnvironmentLight {
public:
    EnvironmentLight(int width, int height, std::vector<float> pixels)
        : width_(width), height_(height), pixels_(std::move(pixels)),
          dist_(weights(width_, height_, pixels_), width_, height_, 0.0f, 1.0f, 0.0f, 1.0f) {}

    LightSample sample(Vector3f ref, Point2f u) const {
        const PiecewiseConstant2D::Sample s = dist_.sample(u);
        // The density and radiance at the direction's own (u, v), as pdf() and
        // L() find them: where rounding moves a point across a pixel's border,
        // both are the neighbour's (pbrt returns the drawn cell's instead, which
        // at a border differs from its own PDF()). At a pole (sin theta = 0) the
        // density per solid angle is unbounded, and after a border into a black
        // pixel it is 0: no sample, as pbrt returns none.
        const Vector3f wi = direction(s.p);
        const float density = pdf(ref, wi);
        if (!(density > 0.0f)) return {};
        return {wi, density, L(ref, wi), std::numeric_limits<float>::infinity()};
    }

    /// p(u, v) / (2 pi^2 sin theta), sin theta of wi itself. 0 at the poles, where
    /// sin theta = 0 and the density is unbounded (a set of no solid angle).
    float pdf(Vector3f, Vector3f wi) const {
        if (!finite(wi)) return 0.0f;
        const float sin_theta = std::hypot(wi.x, wi.y);
        if (!(sin_theta > 0.0f)) return 0.0f;
        const float density = dist_.pdf(uv_of(wi, sin_theta)) / (2.0f * kPi * kPi * sin_theta);
        return std::isfinite(density) ? density : 0.0f;
    }

    float L(Vector3f, Vector3f wi) const {
        if (!finite(wi)) return 0.0f;
        const Point2f uv = uv_of(wi);
        return pixels_[static_cast<std::size_t>(row(uv)) * static_cast<std::size_t>(width_) +
                       static_cast<std::size_t>(column(uv))];
    }

    /// The u that sample maps to wi: the 2D distribution's inverse at wi's (u, v).
    Point2f invert(Vector3f, Vector3f wi) const { return finite(wi) ? dist_.invert(uv_of(wi)) : Point2f{}; }

private:
    static std::vector<float> weights(int width, int height, const std::vector<float>& pixels) {
        if (width < 1 || height < 1)
            throw std::invalid_argument("environment_light: the image is empty (" + std::to_string(width) + " x " +
                                        std::to_string(height) + ")");
        const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
        if (pixels.size() != n)
            throw std::invalid_argument("environment_light: needs width * height = " + std::to_string(n) +
                                        " pixels, got " + std::to_string(pixels.size()));
        std::vector<float> w(n);
        bool lit = false;
        for (std::size_t k = 0; k < n; ++k) {
            const float p = pixels[k];
            if (!(p >= 0.0f) || !std::isfinite(p))
                throw std::invalid_argument("environment_light: pixels must be finite and >= 0, got " +
                                            std::to_string(p) + " at index " + std::to_string(k));
            if (p == 0.0f) continue;
            lit = true;
            // The row centre's sin in double: in float, pi (j + 1/2) / height can round
            // past pi for the last row of a tall map and give a negative sin.
            const double row_centre = (static_cast<double>(k / static_cast<std::size_t>(width)) + 0.5) / height;
            const float weight = static_cast<float>(p * std::sin(std::numbers::pi * row_centre));
            // A lit pixel keeps a positive weight even if the product underflows (support rule).
            w[k] = std::max(weight, std::numeric_limits<float>::denorm_min());
        }
        if (!lit) throw std::invalid_argument("environment_light: every pixel is 0 (nothing to sample)");
        return w;
    }

    /// Whether every component is finite: a NaN direction has no pixel (and would index none).
    static bool finite(Vector3f w) { return std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z); }

    /// The direction of (u, v): phi = 2 pi u, theta = pi v. The lower half takes
    /// theta from pi (1 - v) (exact subtraction): float pi * v would round past
    /// pi near v = 1, and sin there would come out negative, flipping phi.
    static Vector3f direction(Point2f uv) {
        const SinCos phi = sin_cos(kTwoPi * uv.x);
        const bool upper = uv.y <= 0.5f;
        const SinCos theta = sin_cos(kPi * (upper ? uv.y : 1.0f - uv.y));
        const float cos_theta = upper ? theta.cos : -theta.cos;
        return {theta.sin * phi.cos, theta.sin * phi.sin, cos_theta};
    }

    /// (u, v) of a unit direction: phi / 2 pi in [0, 1), theta / pi in [0, 1], theta
    /// from atan2(sin, cos), accurate at the poles where acos(z) is not.
    /// sin_theta: hypot(x, y), where the caller has it already.
    static Point2f uv_of(Vector3f wi) { return uv_of(wi, std::hypot(wi.x, wi.y)); }
    static Point2f uv_of(Vector3f wi, float sin_theta) {
        const float theta = std::atan2(sin_theta, wi.z);
        return {azimuth_to_unit(wi.x, wi.y), std::clamp(theta * kInvPi, 0.0f, 1.0f)};
    }

    // The pixel of (u, v) as the 2D distribution finds it, so that L, pdf and sample agree.
    int column(Point2f uv) const { return dist_.conditional(0).offset(uv.x); }
    int row(Point2f uv) const { return dist_.marginal().offset(uv.y); }

    int width_, height_;
    std::vector<float> pixels_;
    PiecewiseConstant2D dist_;
};

}  // namespace warpcheck

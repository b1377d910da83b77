// The kinds of domain, one struct each: its geometry (measure, membership,
// boundary, name) and its binning parameterisation (the parameter rectangle
// (u, v) that the chi-square cells divide uniformly, and the maps between it and
// the domain). chi2/domain.h lists what a kind must provide.
//
// Parameters per kind (cell measure = du dv * jacobian):
//   Interval      u = x                              jacobian 1
//   HalfLine      u = t, x = a + s t / (1 - t)       jacobian s / (1 - t)^2
//                 (the last cell, t in [t_last, 1), is the tail to infinity)
//   Box           (u, v) = (x, y)                    jacobian 1
//   Disk          (u, v) = (phi, r^2)                jacobian 1/2 (r dr dphi = d(r^2) dphi / 2)
//   SphericalCap  (u, v) = (phi, z = cos theta)      jacobian 1 (dA = dphi dz on the unit sphere);
//                 z read off x and y near the poles (SphericalCap::polar_height)
//   LowerHalfLine u = t, x = b - s (1 - t) / t       jacobian s / t^2
//                 (the mirror of HalfLine, increasing in x: the first cell,
//                 t in [0, t_1), is the tail to minus infinity)
//   RealLine      u = t, w = 2 t - 1, x = c + s w / (1 - |w|)   jacobian 2 s / (1 - |w|)^2
//                 (HalfLine's map on each side of the centre c: half the cells
//                 lie within s of c; the first and the last cell are the tails)
//   (s is BinResolution::half_line_scale, c BinResolution::line_center.)
//   Triangle      (u, v) = (s, t), x = (1 - sqrt s) A + sqrt s ((1 - t) B + t C)
//                 jacobian = the triangle's area (constant: equal-area cells)
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "chi2/domain_parts.h"

namespace warpcheck::chi2 {

/// [a, b], length measure.
struct Interval {
    double a = 0.0, b = 1.0;

    static constexpr int kPointDimension = 1;
    static constexpr bool kAzimuthal = false;
    double measure() const { return b - a; }
    DomainSlack slack() const { return {kDomainTolerance * std::max({b - a, std::abs(a), std::abs(b)}), 0.0}; }
    bool contains(const DomainPoint& p, const DomainSlack& s) const { return p[0] >= a - s.x && p[0] <= b + s.x; }
    bool on_boundary(const DomainPoint& p) const { return p[0] == a || p[0] == b; }
    std::string describe() const { return "interval [" + std::to_string(a) + ", " + std::to_string(b) + "]"; }

    BinResolution default_resolution() const { return {200, 1}; }
    ParamRect parameter_bounds() const { return {a, b, 0.0, 1.0}; }
    DomainPoint point_at(double u, double /*v*/, const BinResolution&) const { return {u, 0.0, 0.0}; }
    double jacobian(double, double, const BinResolution&) const { return 1.0; }
    std::array<double, 2> parameters_of(const DomainPoint& p, const BinResolution&) const { return {p[0], 0.5}; }
    double cell_measure(const ParamRect& r, const BinResolution&) const { return r.u1 - r.u0; }
    bool on_parameter_boundary(double u, double /*v*/) const { return u <= a || u >= b; }
    std::array<double, 2> parameter_slack(const DomainSlack& s) const { return {s.x, 0.0}; }
    std::string u_label() const { return "x"; }
    std::string v_label() const { return ""; }
    double cell_position(const ParamRect& r, const BinResolution&) const { return 0.5 * (r.u0 + r.u1); }
};

/// [a, inf), length measure; binned through t = d / (s + d), d = x - a.
struct HalfLine {
    double a = 0.0;

    static constexpr int kPointDimension = 1;
    static constexpr bool kAzimuthal = false;
    double measure() const { return std::numeric_limits<double>::infinity(); }
    DomainSlack slack() const { return {kDomainTolerance * std::max(1.0, std::abs(a)), 0.0}; }
    bool contains(const DomainPoint& p, const DomainSlack& s) const { return p[0] >= a - s.x && std::isfinite(p[0]); }
    bool on_boundary(const DomainPoint& p) const { return p[0] == a; }
    std::string describe() const { return "half-line [" + std::to_string(a) + ", inf)"; }

    BinResolution default_resolution() const { return {200, 1}; }
    ParamRect parameter_bounds() const { return {0.0, 1.0, 0.0, 1.0}; }
    DomainPoint point_at(double u, double /*v*/, const BinResolution& r) const {
        return {a + r.half_line_scale * u / (1.0 - u), 0.0, 0.0};
    }
    double jacobian(double u, double /*v*/, const BinResolution& r) const {
        return r.half_line_scale / ((1.0 - u) * (1.0 - u));
    }
    std::array<double, 2> parameters_of(const DomainPoint& p, const BinResolution& r) const {
        const double d = std::max(0.0, p[0] - a);
        return {d / (r.half_line_scale + d), 0.5};
    }
    double cell_measure(const ParamRect& r, const BinResolution& res) const {
        if (r.u1 >= 1.0) return std::numeric_limits<double>::infinity();  // the tail cell
        const double s = res.half_line_scale;
        return s * r.u1 / (1.0 - r.u1) - s * r.u0 / (1.0 - r.u0);
    }
    bool on_parameter_boundary(double u, double /*v*/) const { return u <= 0.0; }
    /// t = d / (s + d) moves by at most d/s per unit of d: the relative tolerance in t.
    std::array<double, 2> parameter_slack(const DomainSlack&) const { return {kDomainTolerance, 0.0}; }
    std::string u_label() const { return "x"; }
    std::string v_label() const { return ""; }
    /// The centre of a cell in x, and for the tail cell its left edge.
    double cell_position(const ParamRect& r, const BinResolution& res) const {
        const double t = r.u1 >= 1.0 ? r.u0 : 0.5 * (r.u0 + r.u1);
        return point_at(t, 0.5, res)[0];
    }
};

/// [x0, x1] x [y0, y1], area measure.
struct Box {
    double x0 = 0.0, x1 = 1.0;
    double y0 = 0.0, y1 = 1.0;

    static constexpr int kPointDimension = 2;
    static constexpr bool kAzimuthal = false;
    double measure() const { return (x1 - x0) * (y1 - y0); }
    DomainSlack slack() const {
        return {kDomainTolerance * std::max({x1 - x0, std::abs(x0), std::abs(x1)}),
                kDomainTolerance * std::max({y1 - y0, std::abs(y0), std::abs(y1)})};
    }
    bool contains(const DomainPoint& p, const DomainSlack& s) const {
        return p[0] >= x0 - s.x && p[0] <= x1 + s.x && p[1] >= y0 - s.y && p[1] <= y1 + s.y;
    }
    bool on_boundary(const DomainPoint& p) const { return p[0] == x0 || p[0] == x1 || p[1] == y0 || p[1] == y1; }
    std::string describe() const { return "box"; }

    BinResolution default_resolution() const { return {32, 32}; }
    ParamRect parameter_bounds() const { return {x0, x1, y0, y1}; }
    DomainPoint point_at(double u, double v, const BinResolution&) const { return {u, v, 0.0}; }
    double jacobian(double, double, const BinResolution&) const { return 1.0; }
    std::array<double, 2> parameters_of(const DomainPoint& p, const BinResolution&) const { return {p[0], p[1]}; }
    double cell_measure(const ParamRect& r, const BinResolution&) const { return (r.u1 - r.u0) * (r.v1 - r.v0); }
    bool on_parameter_boundary(double u, double v) const { return u <= x0 || u >= x1 || v <= y0 || v >= y1; }
    std::array<double, 2> parameter_slack(const DomainSlack& s) const { return {s.x, s.y}; }
    std::string u_label() const { return "x"; }
    std::string v_label() const { return "y"; }
    double cell_position(const ParamRect& r, const BinResolution&) const { return 0.5 * (r.u0 + r.u1); }
};

/// Azimuthal kinds (kAzimuthal) have u = phi in [0, 2 pi) and a point
/// (radius(v) cos phi, radius(v) sin phi, height(v)); Binning finds their phi
/// column by its own fast atan2 and asks them only for v (v_of).
inline constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// phi in [0, 2 pi) with the exact atan2.
inline double exact_phi(double x, double y) {
    double phi = std::atan2(y, x);
    if (phi < 0.0) phi += kTwoPi;
    return phi >= kTwoPi ? 0.0 : phi;
}

/// The unit disk, area measure; binned in (phi, r^2), equal-area rows.
struct Disk {
    static constexpr int kPointDimension = 2;
    static constexpr bool kAzimuthal = true;
    double measure() const { return std::numbers::pi; }
    DomainSlack slack() const { return {kDomainTolerance, kDomainTolerance}; }
    bool contains(const DomainPoint& p, const DomainSlack& s) const { return std::hypot(p[0], p[1]) <= 1.0 + s.x; }
    /// contains() squared, without the square root, for the binning loop.
    bool bin_contains(const DomainPoint& p, const DomainSlack& s) const {
        return p[0] * p[0] + p[1] * p[1] <= (1.0 + s.x) * (1.0 + s.x);
    }
    bool on_boundary(const DomainPoint& p) const { return p[0] * p[0] + p[1] * p[1] >= 1.0; }
    std::string describe() const { return "unit disk"; }

    BinResolution default_resolution() const { return {32, 32}; }
    ParamRect parameter_bounds() const { return {0.0, kTwoPi, 0.0, 1.0}; }
    /// The ring at parameter v: its radius and height.
    std::array<double, 2> ring(double v) const { return {std::sqrt(v), 0.0}; }
    double v_of(const DomainPoint& p) const { return p[0] * p[0] + p[1] * p[1]; }
    double jacobian(double, double, const BinResolution&) const { return 0.5; }
    double cell_measure(const ParamRect& r, const BinResolution&) const {
        return 0.5 * (r.u1 - r.u0) * (r.v1 - r.v0);
    }
    bool on_parameter_boundary(double /*u*/, double v) const { return v >= 1.0; }
    std::array<double, 2> parameter_slack(const DomainSlack& s) const { return {kTwoPi * kDomainTolerance, s.y}; }
    std::string u_label() const { return "phi"; }
    std::string v_label() const { return "r^2"; }
};

/// Directions with z >= z_min, solid angle (sphere: z_min = -1, hemisphere: 0);
/// binned in (phi, z = cos theta), equal solid-angle rows.
struct SphericalCap {
    double z_min = -1.0;

    static constexpr int kPointDimension = 3;
    static constexpr bool kAzimuthal = true;
    double measure() const { return 2.0 * std::numbers::pi * (1.0 - z_min); }
    DomainSlack slack() const { return {kDomainTolerance, kDomainTolerance}; }
    bool contains(const DomainPoint& p, const DomainSlack& s) const {
        const double len = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        return std::abs(len - 1.0) <= s.x && p[2] >= z_min - s.x;
    }
    /// contains() with |len - 1| <= tol as len^2 in [(1 - tol)^2, (1 + tol)^2], for the binning loop.
    bool bin_contains(const DomainPoint& p, const DomainSlack& s) const {
        const double len2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
        return len2 >= (1.0 - s.x) * (1.0 - s.x) && len2 <= (1.0 + s.x) * (1.0 + s.x) && p[2] >= z_min - s.x;
    }
    bool on_boundary(const DomainPoint& p) const { return z_min > -1.0 && p[2] <= z_min; }
    std::string describe() const {
        if (z_min == -1.0) return "sphere";
        if (z_min == 0.0) return "hemisphere";
        return "spherical cap z >= " + std::to_string(z_min);
    }

    BinResolution default_resolution() const { return {32, 32}; }
    ParamRect parameter_bounds() const { return {0.0, kTwoPi, z_min, 1.0}; }
    std::array<double, 2> ring(double v) const { return {std::sqrt(std::max(0.0, 1.0 - v * v)), v}; }
    /// z = cos theta of a point. Near the poles it is read off x and y, as
    /// 1 - (x^2 + y^2) / (1 + z) (and -1 + (x^2 + y^2) / (1 - z) below): a
    /// float z there is 2^-24 from the next (a lobe of 1e-6 sr spans a few
    /// dozen values of it), while x and y keep their float resolution however
    /// close to the pole, and a direction's distance from it, 1 - |z| =
    /// (x^2 + y^2) / (1 + |z|) on the unit sphere, is known to 2^-22 of itself
    /// (chi2/float_band.h). Where |z| < 1/2, z's own float step (2^-25 at
    /// most, 2^-24 of 1 - |z|) is finer than that, and z is used.
    static double polar_height(const DomainPoint& p) {
        const double z = p[2];
        if (z >= 0.5) return 1.0 - (p[0] * p[0] + p[1] * p[1]) / (1.0 + z);
        if (z <= -0.5) return -1.0 + (p[0] * p[0] + p[1] * p[1]) / (1.0 - z);
        return z;
    }
    double v_of(const DomainPoint& p) const { return polar_height(p); }
    double jacobian(double, double, const BinResolution&) const { return 1.0; }
    double cell_measure(const ParamRect& r, const BinResolution&) const { return (r.u1 - r.u0) * (r.v1 - r.v0); }
    bool on_parameter_boundary(double /*u*/, double v) const { return z_min > -1.0 && v <= z_min; }
    std::array<double, 2> parameter_slack(const DomainSlack& s) const { return {kTwoPi * kDomainTolerance, s.y}; }
    std::string u_label() const { return "phi"; }
    std::string v_label() const { return "cos theta"; }
};

/// (-inf, b], length measure; binned through t = s / (s + d), d = b - x, so
/// that t (the parameter) grows with x as on every other line.
struct LowerHalfLine {
    double b = 0.0;

    static constexpr int kPointDimension = 1;
    static constexpr bool kAzimuthal = false;
    double measure() const { return std::numeric_limits<double>::infinity(); }
    DomainSlack slack() const { return {kDomainTolerance * std::max(1.0, std::abs(b)), 0.0}; }
    bool contains(const DomainPoint& p, const DomainSlack& s) const { return p[0] <= b + s.x && std::isfinite(p[0]); }
    bool on_boundary(const DomainPoint& p) const { return p[0] == b; }
    std::string describe() const { return "half-line (-inf, " + std::to_string(b) + "]"; }

    BinResolution default_resolution() const { return {200, 1}; }
    ParamRect parameter_bounds() const { return {0.0, 1.0, 0.0, 1.0}; }
    DomainPoint point_at(double u, double /*v*/, const BinResolution& r) const {
        return {b - r.half_line_scale * (1.0 - u) / u, 0.0, 0.0};
    }
    double jacobian(double u, double /*v*/, const BinResolution& r) const { return r.half_line_scale / (u * u); }
    std::array<double, 2> parameters_of(const DomainPoint& p, const BinResolution& r) const {
        const double d = std::max(0.0, b - p[0]);
        return {r.half_line_scale / (r.half_line_scale + d), 0.5};
    }
    double cell_measure(const ParamRect& r, const BinResolution& res) const {
        if (r.u0 <= 0.0) return std::numeric_limits<double>::infinity();  // the tail cell
        const double s = res.half_line_scale;
        return s * (1.0 - r.u0) / r.u0 - s * (1.0 - r.u1) / r.u1;
    }
    bool on_parameter_boundary(double u, double /*v*/) const { return u >= 1.0; }
    /// t = s / (s + d) moves by at most d/s per unit of d, as HalfLine's.
    std::array<double, 2> parameter_slack(const DomainSlack&) const { return {kDomainTolerance, 0.0}; }
    std::string u_label() const { return "x"; }
    std::string v_label() const { return ""; }
    /// The centre of a cell in x, and for the tail cell its right edge.
    double cell_position(const ParamRect& r, const BinResolution& res) const {
        const double t = r.u0 <= 0.0 ? r.u1 : 0.5 * (r.u0 + r.u1);
        return point_at(t, 0.5, res)[0];
    }
};

/// The whole real line, length measure; binned through w = d / (s + |d|),
/// d = x - c, t = (w + 1) / 2.
struct RealLine {
    static constexpr int kPointDimension = 1;
    static constexpr bool kAzimuthal = false;
    double measure() const { return std::numeric_limits<double>::infinity(); }
    DomainSlack slack() const { return {kDomainTolerance, 0.0}; }
    bool contains(const DomainPoint& p, const DomainSlack&) const { return std::isfinite(p[0]); }
    bool on_boundary(const DomainPoint&) const { return false; }
    std::string describe() const { return "real line (-inf, inf)"; }

    BinResolution default_resolution() const { return {200, 1}; }
    ParamRect parameter_bounds() const { return {0.0, 1.0, 0.0, 1.0}; }
    DomainPoint point_at(double u, double /*v*/, const BinResolution& r) const {
        const double w = 2.0 * u - 1.0;
        return {r.line_center + r.half_line_scale * w / (1.0 - std::abs(w)), 0.0, 0.0};
    }
    double jacobian(double u, double /*v*/, const BinResolution& r) const {
        const double m = 1.0 - std::abs(2.0 * u - 1.0);
        return 2.0 * r.half_line_scale / (m * m);
    }
    std::array<double, 2> parameters_of(const DomainPoint& p, const BinResolution& r) const {
        const double d = p[0] - r.line_center;
        return {0.5 * (d / (r.half_line_scale + std::abs(d)) + 1.0), 0.5};
    }
    double cell_measure(const ParamRect& r, const BinResolution& res) const {
        if (r.u0 <= 0.0 || r.u1 >= 1.0) return std::numeric_limits<double>::infinity();  // a tail cell
        return point_at(r.u1, 0.5, res)[0] - point_at(r.u0, 0.5, res)[0];
    }
    bool on_parameter_boundary(double, double) const { return false; }
    /// t moves by at most 1/(2 s) per unit of x; the slack is absolute in x.
    std::array<double, 2> parameter_slack(const DomainSlack&) const { return {kDomainTolerance, 0.0}; }
    std::string u_label() const { return "x"; }
    std::string v_label() const { return ""; }
    /// The centre of a cell in x, and for a tail cell its inner edge.
    double cell_position(const ParamRect& r, const BinResolution& res) const {
        const double t = r.u0 <= 0.0 ? r.u1 : r.u1 >= 1.0 ? r.u0 : 0.5 * (r.u0 + r.u1);
        return point_at(t, 0.5, res)[0];
    }
};

/// The triangle with vertices a, b, c (either orientation), area measure;
/// binned through (s, t) in [0, 1]^2 -> (1 - sqrt s) A + sqrt s ((1 - t) B + t C):
/// sqrt s is the distance from A towards the edge BC (as a fraction of the
/// way), t the position along that segment, and every cell has the area
/// du dv * area() (the map's jacobian is constant), as the disk's rows in r^2.
struct Triangle {
    std::array<double, 2> a{0.0, 0.0}, b{1.0, 0.0}, c{0.0, 1.0};

    static constexpr int kPointDimension = 2;
    static constexpr bool kAzimuthal = false;
    /// Twice the signed area: cross(b - a, c - a).
    double cross() const { return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]); }
    double measure() const { return 0.5 * std::abs(cross()); }
    /// As the box's slack, over the triangle's bounding box.
    DomainSlack slack() const {
        const double x0 = std::min({a[0], b[0], c[0]}), x1 = std::max({a[0], b[0], c[0]});
        const double y0 = std::min({a[1], b[1], c[1]}), y1 = std::max({a[1], b[1], c[1]});
        return {kDomainTolerance * std::max({x1 - x0, std::abs(x0), std::abs(x1)}),
                kDomainTolerance * std::max({y1 - y0, std::abs(y0), std::abs(y1)})};
    }
    /// Barycentric coordinates of p with respect to (b, c): p = a + lb (b - a) + lc (c - a).
    std::array<double, 2> barycentric(const DomainPoint& p) const {
        const double dx = p[0] - a[0], dy = p[1] - a[1], k = cross();
        return {(dx * (c[1] - a[1]) - dy * (c[0] - a[0])) / k, ((b[0] - a[0]) * dy - (b[1] - a[1]) * dx) / k};
    }
    /// How far p lies outside the edge from e0 to e1 (the third vertex is
    /// `other`): the distance along the edge's outward unit normal n, less the
    /// slack projected onto n (|n_x| s.x + |n_y| s.y); <= 0 within the slack.
    static double beyond_edge(const DomainPoint& p, const std::array<double, 2>& e0, const std::array<double, 2>& e1,
                              const std::array<double, 2>& other, const DomainSlack& s) {
        double nx = e1[1] - e0[1], ny = e0[0] - e1[0];
        const double len = std::hypot(nx, ny);
        nx /= len, ny /= len;
        if (nx * (other[0] - e0[0]) + ny * (other[1] - e0[1]) > 0.0) nx = -nx, ny = -ny;
        return nx * (p[0] - e0[0]) + ny * (p[1] - e0[1]) - (std::abs(nx) * s.x + std::abs(ny) * s.y);
    }
    bool contains(const DomainPoint& p, const DomainSlack& s) const {
        // Written so that NaN fails every comparison.
        return beyond_edge(p, a, b, c, s) <= 0.0 && beyond_edge(p, b, c, a, s) <= 0.0 &&
               beyond_edge(p, c, a, b, s) <= 0.0;
    }
    /// On an edge of the closed triangle: a barycentric coordinate exactly 0
    /// (or their sum exactly 1) with the others in [0, 1].
    bool on_boundary(const DomainPoint& p) const {
        const auto [lb, lc] = barycentric(p);
        const double la = 1.0 - lb - lc;
        const bool inside = lb >= 0.0 && lc >= 0.0 && la >= 0.0;
        return inside && (lb == 0.0 || lc == 0.0 || la == 0.0);
    }
    std::string describe() const {
        return "triangle (" + std::to_string(a[0]) + ", " + std::to_string(a[1]) + "), (" + std::to_string(b[0]) +
               ", " + std::to_string(b[1]) + "), (" + std::to_string(c[0]) + ", " + std::to_string(c[1]) + ")";
    }

    BinResolution default_resolution() const { return {32, 32}; }
    ParamRect parameter_bounds() const { return {0.0, 1.0, 0.0, 1.0}; }
    DomainPoint point_at(double u, double v, const BinResolution&) const {
        const double r = std::sqrt(u), wa = 1.0 - r, wb = r * (1.0 - v), wc = r * v;
        return {wa * a[0] + wb * b[0] + wc * c[0], wa * a[1] + wb * b[1] + wc * c[1], 0.0};
    }
    double jacobian(double, double, const BinResolution&) const { return measure(); }
    /// The inverse of point_at: r = lb + lc, t = lc / r (t = 0.5 at the vertex a, where it is arbitrary).
    std::array<double, 2> parameters_of(const DomainPoint& p, const BinResolution&) const {
        const auto [lb, lc] = barycentric(p);
        const double r = lb + lc;
        return {r * r, r > 0.0 ? lc / r : 0.5};
    }
    double cell_measure(const ParamRect& r, const BinResolution&) const {
        return (r.u1 - r.u0) * (r.v1 - r.v0) * measure();
    }
    /// s = 1 is the edge bc, t = 0 the edge ab, t = 1 the edge ac (s = 0 the vertex a).
    bool on_parameter_boundary(double u, double v) const { return u <= 0.0 || u >= 1.0 || v <= 0.0 || v >= 1.0; }
    /// The slack over the triangle's smallest height h: r moves by at most
    /// slack / h, s = r^2 by twice that, and t (at r near 1) by as much as r.
    std::array<double, 2> parameter_slack(const DomainSlack& s) const {
        const double longest = std::max({std::hypot(b[0] - a[0], b[1] - a[1]), std::hypot(c[0] - b[0], c[1] - b[1]),
                                         std::hypot(a[0] - c[0], a[1] - c[1])});
        const double h = 2.0 * measure() / longest, d = std::max(s.x, s.y) / h;
        return {2.0 * d, d};
    }
    std::string u_label() const { return "s = r^2"; }
    std::string v_label() const { return "t"; }
    double cell_position(const ParamRect& r, const BinResolution&) const { return 0.5 * (r.u0 + r.u1); }
};

}  // namespace warpcheck::chi2

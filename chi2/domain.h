// The sets that warps map onto, and the measure their densities refer to.
// Spherical domains are parameterised by (phi, z = cos theta): on the unit
// sphere dA = dphi dz, so a cell's area in those coordinates is its solid angle.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace warpcheck::chi2 {

/// Domain membership tolerance, relative to the domain's extent (see
/// Domain::slack): samples are computed in float, whose coordinates carry a
/// resolution of ~6e-8 relative plus a few ulps lost in trigonometry, so 1e-5 is
/// about 100 times the float resolution of the coordinates, while a wrong warp
/// misplaces samples by far more.
inline constexpr double kDomainTolerance = 1e-5;

enum class DomainKind {
    Interval,      ///< [a, b], length measure
    HalfLine,      ///< [a, inf), length measure
    Box,           ///< [x0, x1] x [y0, y1], area measure
    Disk,          ///< unit disk, area measure
    SphericalCap,  ///< directions with z >= z_min, solid angle (sphere: z_min = -1, hemisphere: 0)
};

/// A point of a domain: x for 1D domains, (x, y) for planar ones, (x, y, z) for spherical ones.
using DomainPoint = std::array<double, 3>;

struct Domain {
    DomainKind kind = DomainKind::Interval;
    double a = 0.0, b = 1.0;    ///< Interval [a, b]; HalfLine [a, inf)
    double x0 = 0.0, x1 = 1.0;  ///< Box
    double y0 = 0.0, y1 = 1.0;  ///< Box
    double z_min = -1.0;        ///< SphericalCap

    static Domain interval(double lo, double hi) {
        if (!(lo < hi) || !std::isfinite(lo) || !std::isfinite(hi))
            throw std::invalid_argument("interval domain needs finite a < b");
        Domain d;
        d.kind = DomainKind::Interval;
        d.a = lo;
        d.b = hi;
        return d;
    }
    static Domain half_line(double lo) {
        if (!std::isfinite(lo)) throw std::invalid_argument("half-line domain needs a finite start");
        Domain d;
        d.kind = DomainKind::HalfLine;
        d.a = lo;
        d.b = std::numeric_limits<double>::infinity();
        return d;
    }
    static Domain box(double bx0, double bx1, double by0, double by1) {
        if (!(bx0 < bx1) || !(by0 < by1)) throw std::invalid_argument("box domain needs x0 < x1 and y0 < y1");
        Domain d;
        d.kind = DomainKind::Box;
        d.x0 = bx0;
        d.x1 = bx1;
        d.y0 = by0;
        d.y1 = by1;
        return d;
    }
    static Domain unit_square() { return box(0.0, 1.0, 0.0, 1.0); }
    static Domain unit_disk() {
        Domain d;
        d.kind = DomainKind::Disk;
        return d;
    }
    static Domain spherical_cap(double zmin) {
        if (!(zmin >= -1.0 && zmin < 1.0)) throw std::invalid_argument("spherical cap needs -1 <= z_min < 1");
        Domain d;
        d.kind = DomainKind::SphericalCap;
        d.z_min = zmin;
        return d;
    }
    static Domain sphere() { return spherical_cap(-1.0); }
    static Domain hemisphere() { return spherical_cap(0.0); }

    /// Number of coordinates of a point (1, 2 or 3); the parametric dimension is
    /// 1 for intervals and 2 for everything else.
    int point_dimension() const {
        switch (kind) {
            case DomainKind::Interval:
            case DomainKind::HalfLine: return 1;
            case DomainKind::Box:
            case DomainKind::Disk: return 2;
            case DomainKind::SphericalCap: return 3;
        }
        return 0;
    }

    /// Total measure: length, area or solid angle (infinite for a half-line).
    double measure() const {
        switch (kind) {
            case DomainKind::Interval: return b - a;
            case DomainKind::HalfLine: return std::numeric_limits<double>::infinity();
            case DomainKind::Box: return (x1 - x0) * (y1 - y0);
            case DomainKind::Disk: return std::numbers::pi;
            case DomainKind::SphericalCap: return 2.0 * std::numbers::pi * (1.0 - z_min);
        }
        return 0.0;
    }

    /// How far outside the domain a point may lie and still count as inside,
    /// per coordinate: kDomainTolerance times the domain's extent (the largest of
    /// its width and its ends' magnitudes), or times the unit radius / length
    /// for disks and spheres.
    struct Slack {
        double x = 0.0, y = 0.0;
    };
    Slack slack() const {
        switch (kind) {
            case DomainKind::Interval: return {kDomainTolerance * std::max({b - a, std::abs(a), std::abs(b)}), 0.0};
            case DomainKind::HalfLine: return {kDomainTolerance * std::max(1.0, std::abs(a)), 0.0};
            case DomainKind::Box:
                return {kDomainTolerance * std::max({x1 - x0, std::abs(x0), std::abs(x1)}),
                        kDomainTolerance * std::max({y1 - y0, std::abs(y0), std::abs(y1)})};
            case DomainKind::Disk:
            case DomainKind::SphericalCap: return {kDomainTolerance, kDomainTolerance};
        }
        return {};
    }

    /// Whether p lies in the domain, within slack() of it: the one definition of
    /// domain membership that binning, the checks and the sweeps share. NaN
    /// coordinates are never contained.
    bool contains(const DomainPoint& p) const {
        const Slack s = slack();
        switch (kind) {
            case DomainKind::Interval: return p[0] >= a - s.x && p[0] <= b + s.x;
            case DomainKind::HalfLine: return p[0] >= a - s.x && std::isfinite(p[0]);
            case DomainKind::Box: return p[0] >= x0 - s.x && p[0] <= x1 + s.x && p[1] >= y0 - s.y && p[1] <= y1 + s.y;
            case DomainKind::Disk: return std::hypot(p[0], p[1]) <= 1.0 + s.x;
            case DomainKind::SphericalCap: {
                const double len = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
                return std::abs(len - 1.0) <= s.x && p[2] >= z_min - s.x;
            }
        }
        return false;
    }

    /// Whether p lies exactly on the domain's boundary (interval ends, box edges,
    /// the unit circle, the cap's rim). A density may vanish there legitimately:
    /// e.g. the cosine-weighted hemisphere has density 0 at z = 0, which a float
    /// warp reaches from the input u = 0 exactly.
    bool on_boundary(const DomainPoint& p) const {
        switch (kind) {
            case DomainKind::Interval: return p[0] == a || p[0] == b;
            case DomainKind::HalfLine: return p[0] == a;
            case DomainKind::Box: return p[0] == x0 || p[0] == x1 || p[1] == y0 || p[1] == y1;
            case DomainKind::Disk: return p[0] * p[0] + p[1] * p[1] >= 1.0;
            case DomainKind::SphericalCap: return z_min > -1.0 && p[2] <= z_min;
        }
        return false;
    }

    std::string describe() const;
};

inline std::string Domain::describe() const {
    switch (kind) {
        case DomainKind::Interval: return "interval [" + std::to_string(a) + ", " + std::to_string(b) + "]";
        case DomainKind::HalfLine: return "half-line [" + std::to_string(a) + ", inf)";
        case DomainKind::Box: return "box";
        case DomainKind::Disk: return "unit disk";
        case DomainKind::SphericalCap:
            if (z_min == -1.0) return "sphere";
            if (z_min == 0.0) return "hemisphere";
            return "spherical cap z >= " + std::to_string(z_min);
    }
    return "?";
}

}  // namespace warpcheck::chi2

namespace warpcheck::chi2 {

/// How finely the chi-square test bins a domain. Zero means "the default for
/// the domain" (see Binning). Cells are uniform in the domain's parameters:
///   Interval, HalfLine: `first` cells along the line (the half-line's last one
///                       is the tail cell, reaching to infinity);
///   Box:               `first` columns in x, `second` rows in y;
///   Disk:              `first` columns in phi, `second` rows in r^2 (equal area);
///   SphericalCap:      `first` columns in phi, `second` rows in z = cos theta
///                      (equal solid angle).
struct BinResolution {
    int first = 0;
    int second = 0;
    /// HalfLine only: the length scale s of the map t = d / (s + d), d = x - a,
    /// whose uniform cells in t in [0, 1) bin the half-line. Half the cells lie
    /// within s of the start; choose s near the distribution's median. Zero
    /// means 1 to Binning; the chi2 check derives it from the density instead.
    double half_line_scale = 0.0;
};

}  // namespace warpcheck::chi2

// The sets that warps map onto, and the measure their densities refer to.
// Spherical domains are parameterised by (phi, z = cos theta): on the unit
// sphere dA = dphi dz, so a cell's area in those coordinates is its solid angle.
//
// A Domain holds one kind (chi2/domain_kinds.h) in a std::variant and forwards
// to it. To add a kind (as the whole real line and (-inf, b] were added):
//   1. write its struct in chi2/domain_kinds.h, with
//        kPointDimension (1, 2 or 3) and kAzimuthal (see below);
//        measure(), slack(), contains(p, slack), on_boundary(p), describe();
//        and its binning map: default_resolution(), parameter_bounds(),
//        jacobian(u, v, res) (the measure density, a function of u alone: the
//        cubature weights a column of nodes by one value), cell_measure(rect, res),
//        on_parameter_boundary(u, v),
//        parameter_slack(slack) (the membership slack in parameter units),
//        u_label(), v_label(); and
//        - if kAzimuthal is false: point_at(u, v, res), parameters_of(p, res)
//          (its inverse) and cell_position(rect, res) (a cell's centre along u
//          in the domain's own coordinate, for 1D plots);
//        - if kAzimuthal is true (u = phi in [0, 2 pi)): ring(v) -> {radius,
//          height} and v_of(p); Binning supplies phi.
//      Optionally bin_contains(p, slack): the same set as contains, in the
//      form the binning loop prefers (e.g. squared radii);
//   2. add it to Domain::Shape below, with a factory.
// (The triangle was added this way: binning, quadrature and the checks took it
// unchanged.)
// Nothing else switches on the kind: callers ask is<Kind>().
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <variant>

#include "chi2/domain_kinds.h"
#include "chi2/domain_parts.h"

namespace warpcheck::chi2 {

class Domain {
public:
    using Shape = std::variant<Interval, HalfLine, Box, Disk, SphericalCap, LowerHalfLine, RealLine, Triangle>;
    using Slack = DomainSlack;

    Domain() = default;
    static Domain interval(double lo, double hi) {
        if (!(lo < hi) || !std::isfinite(lo) || !std::isfinite(hi))
            throw std::invalid_argument("interval domain needs finite a < b");
        return Domain(Interval{lo, hi});
    }
    static Domain half_line(double lo) {
        if (!std::isfinite(lo)) throw std::invalid_argument("half-line domain needs a finite start");
        return Domain(HalfLine{lo});
    }
    /// (-inf, b]: the half-line below b.
    static Domain lower_half_line(double hi) {
        if (!std::isfinite(hi)) throw std::invalid_argument("lower half-line domain needs a finite end");
        return Domain(LowerHalfLine{hi});
    }
    /// The whole real line (-inf, inf).
    static Domain real_line() { return Domain(RealLine{}); }
    static Domain box(double bx0, double bx1, double by0, double by1) {
        if (!(bx0 < bx1) || !(by0 < by1)) throw std::invalid_argument("box domain needs x0 < x1 and y0 < y1");
        return Domain(Box{bx0, bx1, by0, by1});
    }
    static Domain unit_square() { return box(0.0, 1.0, 0.0, 1.0); }
    static Domain unit_disk() { return Domain(Disk{}); }
    static Domain spherical_cap(double zmin) {
        if (!(zmin >= -1.0 && zmin < 1.0)) throw std::invalid_argument("spherical cap needs -1 <= z_min < 1");
        return Domain(SphericalCap{zmin});
    }
    static Domain sphere() { return spherical_cap(-1.0); }
    /// The triangle with vertices a, b, c (area measure), e.g. a light's
    /// triangle or half of a quad: its area must be positive and finite.
    static Domain triangle(std::array<double, 2> a, std::array<double, 2> b, std::array<double, 2> c) {
        const Triangle t{a, b, c};
        const double area = t.measure();
        const bool finite = std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(b[0]) && std::isfinite(b[1]) &&
                            std::isfinite(c[0]) && std::isfinite(c[1]);
        if (!finite || !(area > 0.0) || !std::isfinite(area))
            throw std::invalid_argument("triangle domain needs three finite vertices that span a positive area");
        return Domain(t);
    }
    static Domain hemisphere() { return spherical_cap(0.0); }

    const Shape& shape() const { return shape_; }
    template <typename Kind>
    bool is() const {
        return std::holds_alternative<Kind>(shape_);
    }
    template <typename Kind>
    const Kind& as() const {
        return std::get<Kind>(shape_);
    }
    /// Whether u is the azimuth phi in [0, 2 pi) (disk, spherical caps).
    bool azimuthal() const {
        return std::visit([](const auto& k) { return k.kAzimuthal; }, shape_);
    }

    /// The ends of a line: Interval [a, b], HalfLine [a, inf), LowerHalfLine
    /// (-inf, b], RealLine (-inf, inf). Not defined for 2D domains.
    double a() const {
        if (const auto* i = std::get_if<Interval>(&shape_)) return i->a;
        if (const auto* h = std::get_if<HalfLine>(&shape_)) return h->a;
        if (is<LowerHalfLine>() || is<RealLine>()) return -std::numeric_limits<double>::infinity();
        throw std::logic_error("Domain::a: " + describe() + " is not a line");
    }
    double b() const {
        if (const auto* i = std::get_if<Interval>(&shape_)) return i->b;
        if (const auto* l = std::get_if<LowerHalfLine>(&shape_)) return l->b;
        if (is<HalfLine>() || is<RealLine>()) return std::numeric_limits<double>::infinity();
        throw std::logic_error("Domain::b: " + describe() + " is not a line");
    }
    /// Whether the domain is a line with at least one infinite end.
    bool unbounded_line() const { return is<HalfLine>() || is<LowerHalfLine>() || is<RealLine>(); }

    /// Number of coordinates of a point (1, 2 or 3); the parametric dimension is
    /// 1 for intervals and 2 for everything else.
    int point_dimension() const {
        return std::visit([](const auto& k) { return k.kPointDimension; }, shape_);
    }

    /// Total measure: length, area or solid angle (infinite for a half-line).
    double measure() const {
        return std::visit([](const auto& k) { return k.measure(); }, shape_);
    }

    /// How far outside the domain a point may lie and still count as inside,
    /// per coordinate: kDomainTolerance times the domain's extent (the largest of
    /// its width and its ends' magnitudes), or times the unit radius / length
    /// for disks and spheres.
    Slack slack() const {
        return std::visit([](const auto& k) { return k.slack(); }, shape_);
    }

    /// Whether p lies in the domain, within slack() of it: the one definition of
    /// domain membership that binning, the checks and the sweeps share. NaN
    /// coordinates are never contained.
    bool contains(const DomainPoint& p) const {
        return std::visit([&](const auto& k) { return k.contains(p, k.slack()); }, shape_);
    }

    /// Whether p lies exactly on the domain's boundary (interval ends, box edges,
    /// the unit circle, the cap's rim). A density may vanish there legitimately:
    /// e.g. the cosine-weighted hemisphere has density 0 at z = 0, which a float
    /// warp reaches from the input u = 0 exactly.
    bool on_boundary(const DomainPoint& p) const {
        return std::visit([&](const auto& k) { return k.on_boundary(p); }, shape_);
    }

    std::string describe() const {
        return std::visit([](const auto& k) { return k.describe(); }, shape_);
    }

private:
    explicit Domain(Shape shape) : shape_(shape) {}
    Shape shape_;
};

}  // namespace warpcheck::chi2

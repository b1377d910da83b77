// The small value types that every domain kind and the binning share: a point,
// the membership slack, a rectangle of parameter space, and the resolution of
// a binning.
#pragma once

#include <array>

namespace warpcheck::chi2 {

/// Domain membership tolerance, relative to the domain's extent (see
/// Domain::slack): samples are computed in float, whose coordinates carry a
/// resolution of ~6e-8 relative plus a few ulps lost in trigonometry, so 1e-5 is
/// about 100 times the float resolution of the coordinates, while a wrong warp
/// misplaces samples by far more.
inline constexpr double kDomainTolerance = 1e-5;

/// A point of a domain: x for 1D domains, (x, y) for planar ones, (x, y, z) for spherical ones.
using DomainPoint = std::array<double, 3>;

/// How far outside a domain a point may lie and still count as inside, per
/// coordinate (see Domain::slack).
struct DomainSlack {
    double x = 0.0, y = 0.0;
};

/// A rectangle of parameter space.
struct ParamRect {
    double u0 = 0.0, u1 = 1.0;
    double v0 = 0.0, v1 = 1.0;
};

/// How finely the chi-square test bins a domain. Zero means "the default for
/// the domain" (see Binning). Cells are uniform in the domain's parameters:
///   Interval, HalfLine, LowerHalfLine, RealLine: `first` cells along the line
///                       (an unbounded end's cell is its tail, reaching to infinity);
///   Box:               `first` columns in x, `second` rows in y;
///   Disk:              `first` columns in phi, `second` rows in r^2 (equal area);
///   SphericalCap:      `first` columns in phi, `second` rows in z = cos theta
///                      (equal solid angle).
struct BinResolution {
    int first = 0;
    int second = 0;
    /// Unbounded lines (HalfLine, LowerHalfLine, RealLine): the length scale s
    /// of the map t = d / (s + d), d = the distance from the start (or from
    /// line_center), whose uniform cells in t bin the line. Half the cells lie
    /// within s of the start (centre); choose s near the distribution's median
    /// distance. Zero means 1 to Binning; the checks derive it from the density
    /// instead (validate/checks/shared/line_resolution.h).
    double half_line_scale = 0.0;
    /// RealLine only: the centre c of the map above (where the cells are
    /// finest). The checks derive it from the warp when the case leaves it 0.
    double line_center = 0.0;
};

}  // namespace warpcheck::chi2

// The float resolution of a domain parameter: where the ideal (real-valued)
// point that a float output stands for can lie, seen through one parameter of
// the domain's binning (chi2/binning.h).
//
// A float warp's output is its ideal point moved by its own rounding: at best
// (correctly rounded) within one float step of each coordinate, and a few
// rounded operations whose terms are no larger than the result (pbrt's
// cos theta = (1 - u) + u cos_max: three roundings of half an ulp each, 1.25 ulp
// at most as measured over 2 10^7 inputs) stay within two float steps. The
// model here: every float coordinate of the output lies within `steps` float
// steps of the ideal point's. What that allows for the parameter:
//   - a parameter that is one float coordinate, or a monotone map of one
//     (x of intervals, boxes and lines, y of boxes, z = cos theta of spherical
//     caps): exactly the parameter of that coordinate moved `steps` floats
//     down and up (the floats' own spacing, binade by binade);
//   - phi = atan2(y, x) of the disk and spherical caps: |dphi| =
//     |x dy - y dx| / r^2 <= steps 2^-23 (|x||y| + |y||x|) / r^2 <= steps 2^-23,
//     to first order (a float step is at most 2^-23 of the value). The pole
//     x = y = 0 has no azimuth (its float neighbours point every way, and
//     rounding puts a whole neighbourhood of the pole onto it: 0.3% of a
//     0.25 degree cone's samples): its phi is NaN;
//   - r^2 = x^2 + y^2 of the disk: |d(r^2)| <= 2 steps 2^-23 r^2, to first order;
//   - z = cos theta of spherical caps (SphericalCap::polar_height): where
//     |z| < 1/2, z moved `steps` floats; nearer the poles, where it is read off
//     x and y as +-(1 - t), t = (x^2 + y^2) / (1 + |z|):
//     |dt| <= |d(x^2 + y^2)| / (1 + |z|) + t |dz| / (1 + |z|)
//          <= t steps (2^-22 + 2^-24 / 1.5) <= 5 steps 2^-24 t, to first order.
// The input's own quantisation (u on a float grid) moves a monotone warp's
// CDF by at most one input step, 2^-24 of the mass: far below any test's
// resolution up to 10^10 samples, and not modelled.
#pragma once

#include <array>
#include <string>

#include "chi2/binning.h"
#include "chi2/marginal_cdf.h"

namespace warpcheck::chi2 {

/// A parameter value and the range [lo, hi] of the ideal point's parameter.
struct ParameterBand {
    double value = 0.0;
    double lo = 0.0;
    double hi = 0.0;
    /// The azimuth's band crosses the point where the circle is cut (phi = 0):
    /// the ideal value lies in [lo, hi] modulo 2 pi, so on either end of the
    /// parameter range.
    bool wraps = false;
};

class FloatResolution {
public:
    /// Parameter `axis` (0 or 1, as in Binning::parameters_of) of `binning`'s
    /// domain, with every float coordinate within `steps` (>= 1) float steps.
    FloatResolution(const Binning& binning, int axis, int steps);

    /// The parameter of a float output; the same value as
    /// binning.parameters_of(the output in double)[axis], but NaN for the
    /// azimuth of the pole.
    double value(const std::array<float, 3>& p) const;
    /// The parameter and the range of the ideal point's parameter.
    ParameterBand band(const std::array<float, 3>& p) const;
    /// The half-width of the band at parameter value t (of a float output
    /// whose parameter is t, to float rounding): the larger side.
    double half_width_at(double t) const;
    /// Which float coordinate the parameter is a monotone map of (0, 1, 2), or
    /// -1 when it combines two (phi, r^2, a cap's z, a triangle's parameters).
    int coordinate() const { return kind_ == Kind::Coordinate ? coordinate_ : -1; }
    int steps() const { return steps_; }
    /// How the band is set, for a result's text: e.g. "2 float steps of z".
    std::string describe() const;

private:
    /// Probed: a parameter that mixes both coordinates through a map with no
    /// closed-form band (a triangle's (s, t)); its band is probed per point.
    enum class Kind { Coordinate, Azimuth, RadiusSquared, PolarHeight, Probed };
    ParameterBand probed_band(const std::array<float, 3>& p) const;
    double of_coordinate(float c) const;

    Binning binning_;
    int axis_ = 0;  ///< which parameter (read by Kind::Probed)
    int steps_ = 1;
    Kind kind_ = Kind::Coordinate;
    int coordinate_ = 0;
    bool mapped_ = false;  ///< the parameter is a map of the coordinate (lines), not the coordinate itself
};

/// The largest probability of `cdf` within a half-width of the float band of
/// `resolution` from a point, by a model: per strip of the tabulated CDF, its
/// density (the strip's mass over its width) times the band's half-width at
/// the strip's ends. It reads the density off the strips, which average it:
/// within a strip it may be higher by the strip's own variation.
double largest_band_probability(const FloatResolution& resolution, const MarginalCdf& cdf);

}  // namespace warpcheck::chi2

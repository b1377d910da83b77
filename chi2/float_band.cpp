#include "chi2/float_band.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace warpcheck::chi2 {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// The float `steps` floats above c (below for negative steps), by integer
/// steps on the float's bit pattern read as an ordered integer (negative
/// floats counted down from zero): the same as `steps` calls of nextafter,
/// without them. Infinity and NaN stay as they are; the largest float steps
/// up to infinity.
float step_floats(float c, int steps) {
    if (!std::isfinite(c)) return c;
    const auto bits = std::bit_cast<int32_t>(c);
    const int64_t ordered = bits < 0 ? -static_cast<int64_t>(bits & 0x7fffffff) : bits;
    const int64_t moved = ordered + steps;
    constexpr int64_t kInfinity = 0x7f800000;
    if (moved >= kInfinity) return std::numeric_limits<float>::infinity();
    if (moved <= -kInfinity) return -std::numeric_limits<float>::infinity();
    return std::bit_cast<float>(moved < 0 ? static_cast<int32_t>((-moved) | 0x80000000LL) : static_cast<int32_t>(moved));
}

/// The half-width of a cap's z band near a pole (|z| >= 1/2), where z is read
/// off x and y: 5 steps 2^-24 of 1 - |z| (see the header).
double polar_half_width(double z, double steps) { return 5.0 * steps * 0x1p-24 * (1.0 - std::abs(z)); }

}  // namespace

FloatResolution::FloatResolution(const Binning& binning, int axis, int steps)
    : binning_(binning), axis_(axis), steps_(steps) {
    if (steps < 1) throw std::invalid_argument("FloatResolution: steps must be at least 1");
    if (axis < 0 || axis >= binning.parameter_dimension())
        throw std::invalid_argument("FloatResolution: no such parameter");
    const Domain& d = binning.domain();
    if (d.is<Triangle>()) {
        kind_ = Kind::Probed;
    } else if (d.azimuthal()) {
        kind_ = axis == 0 ? Kind::Azimuth : d.is<Disk>() ? Kind::RadiusSquared : Kind::PolarHeight;
    } else {
        coordinate_ = axis;  // x of lines and boxes, y of boxes
        mapped_ = d.unbounded_line();
    }
}

double FloatResolution::of_coordinate(float c) const {
    if (!mapped_) return static_cast<double>(c);
    return binning_.parameters_of({static_cast<double>(c), 0.0, 0.0})[0];
}

double FloatResolution::value(const std::array<float, 3>& p) const {
    const double x = p[0], y = p[1];
    switch (kind_) {
        case Kind::Azimuth: return x == 0.0 && y == 0.0 ? std::nan("") : exact_phi(x, y);
        case Kind::RadiusSquared: return x * x + y * y;
        case Kind::PolarHeight: return SphericalCap::polar_height({x, y, static_cast<double>(p[2])});
        case Kind::Probed: return binning_.parameters_of({x, y, 0.0})[static_cast<std::size_t>(axis_)];
        case Kind::Coordinate: break;
    }
    return of_coordinate(p[static_cast<std::size_t>(coordinate_)]);
}

ParameterBand FloatResolution::band(const std::array<float, 3>& p) const {
    ParameterBand b;
    b.value = value(p);
    const double s = static_cast<double>(steps_);
    switch (kind_) {
        case Kind::Azimuth: {
            const double h = s * 0x1p-23;
            b.lo = b.value - h;
            b.hi = b.value + h;
            b.wraps = b.lo < 0.0 || b.hi >= kTwoPi;
            return b;
        }
        case Kind::RadiusSquared: {
            const double h = 2.0 * s * 0x1p-23 * b.value;
            b.lo = b.value - h;
            b.hi = b.value + h;
            return b;
        }
        case Kind::PolarHeight: {
            if (std::abs(p[2]) < 0.5f) {  // z itself (polar_height)
                b.lo = static_cast<double>(step_floats(p[2], -steps_));
                b.hi = static_cast<double>(step_floats(p[2], steps_));
                return b;
            }
            const double h = polar_half_width(b.value, s);
            b.lo = b.value - h;
            b.hi = b.value + h;
            return b;
        }
        case Kind::Probed: return probed_band(p);
        case Kind::Coordinate: break;
    }
    const float c = p[static_cast<std::size_t>(coordinate_)];
    b.lo = of_coordinate(step_floats(c, -steps_));
    b.hi = of_coordinate(step_floats(c, steps_));
    // A parameter that the map leaves undefined beyond the largest float (a
    // line's t of infinity) bounds nothing on that side.
    if (std::isnan(b.lo) && !std::isnan(b.value)) b.lo = -kInf;
    if (std::isnan(b.hi) && !std::isnan(b.value)) b.hi = kInf;
    return b;
}

/// The parameter's range over the 8 points with x and y each moved by
/// -steps, 0 or +steps floats: to first order the map is linear over so small
/// a box, so its extremes are at the box's corners and edges' midpoints.
ParameterBand FloatResolution::probed_band(const std::array<float, 3>& p) const {
    ParameterBand b;
    b.value = value(p);
    b.lo = b.hi = b.value;
    for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy) {
            const std::array<float, 3> q = {step_floats(p[0], dx * steps_), step_floats(p[1], dy * steps_), p[2]};
            const double v = value(q);
            if (std::isnan(v)) continue;
            b.lo = std::min(b.lo, v);
            b.hi = std::max(b.hi, v);
        }
    return b;
}

double FloatResolution::half_width_at(double t) const {
    const double s = static_cast<double>(steps_);
    switch (kind_) {
        case Kind::Azimuth: return s * 0x1p-23;
        case Kind::RadiusSquared: return 2.0 * s * 0x1p-23 * t;
        case Kind::PolarHeight: {
            if (std::abs(t) < 0.5) {
                const auto z = static_cast<float>(t);
                const double step = static_cast<double>(step_floats(std::abs(z), steps_)) - std::abs(z);
                return std::max(step, std::abs(z) - static_cast<double>(step_floats(std::abs(z), -steps_)));
            }
            return polar_half_width(t, s);
        }
        // Unbounded over the other parameter (a triangle's t near its first
        // vertex): no model, so every sample's band is probed.
        case Kind::Probed: return kInf;
        case Kind::Coordinate: break;
    }
    const double x = mapped_ ? binning_.point_at(t, 0.5)[0] : t;
    std::array<float, 3> p = {0.0f, 0.0f, 0.0f};
    p[static_cast<std::size_t>(coordinate_)] = static_cast<float>(x);
    const ParameterBand b = band(p);
    return std::max(b.hi - b.value, b.value - b.lo);
}

double largest_band_probability(const FloatResolution& resolution, const MarginalCdf& cdf) {
    double largest = 0.0;
    for (std::size_t j = 0; j + 1 < cdf.edges.size(); ++j) {
        const double width = cdf.edges[j + 1] - cdf.edges[j];
        if (!(width > 0.0)) continue;
        const double density = (cdf.cdf[j + 1] - cdf.cdf[j]) / width;
        const double h = std::max(resolution.half_width_at(cdf.edges[j]), resolution.half_width_at(cdf.edges[j + 1]));
        largest = std::max(largest, density * h);
    }
    return largest;
}

std::string FloatResolution::describe() const {
    const std::string n = std::to_string(steps_);
    switch (kind_) {
        case Kind::Azimuth: return "phi within " + n + " 2^-23";
        case Kind::RadiusSquared: return "r^2 within " + n + " 2^-22 of itself";
        case Kind::PolarHeight:
            return "z within " + n + (steps_ == 1 ? " float step" : " float steps") + ", or near a pole 1 - |z| within " +
                   std::to_string(5 * steps_) + " 2^-24 of itself (from x and y)";
        case Kind::Probed: return "x and y each within " + n + " float steps, probed";
        case Kind::Coordinate: break;
    }
    return n + (steps_ == 1 ? " float step of " : " float steps of ") + "xyz"[coordinate_];
}

}  // namespace warpcheck::chi2

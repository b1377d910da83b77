// A family of cases: one warp (or BSDF, or light) made at any point of its
// parameters. A grid registers the family's chosen points (case_grid.h); the
// family itself, kept by the registry, lets --fuzz make cases at the ends of
// the ranges its axes declare and anywhere between (validate/run/fuzz.h).
#pragma once

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "validate/api/warp_case.h"

namespace warpcheck {

/// The values a parameter may take beyond its grid, as the family declares
/// them: [lo, hi], each end included unless it is open (an open end is
/// approached, never reached: roughness 0 that the constructor refuses, g = 1).
/// Unset (the default): the axis takes its grid values only.
struct ParamRange {
    double lo = std::numeric_limits<double>::quiet_NaN();
    double hi = std::numeric_limits<double>::quiet_NaN();
    bool lo_open = false;
    bool hi_open = false;
    bool declared() const { return std::isfinite(lo) && std::isfinite(hi) && lo <= hi; }
    /// Whether v lies in the range, open ends excluded (NaN is in no range).
    bool contains(double v) const {
        return declared() && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
    }
};

/// One parameter of a grid, the values it takes, in order, and (where the
/// family declares them) the ranges --fuzz draws it from: one, or several
/// where a value between them is refused by design (theta_o = 90, wo on the
/// horizon, between [0, 90) and (90, 180]).
struct GridAxis {
    std::string name;
    std::vector<double> values;
    std::vector<ParamRange> ranges{};
};

/// One point of a grid: its parameters in axis order, looked up by name.
class GridPoint {
public:
    explicit GridPoint(std::vector<Parameter> params) : params_(std::move(params)) {}
    /// The value of the named axis; an unknown name is a std::invalid_argument.
    double operator[](std::string_view name) const {
        for (const Parameter& p : params_)
            if (p.name == name) return p.value;
        throw std::invalid_argument("grid point has no parameter " + std::string(name));
    }
    const std::vector<Parameter>& params() const { return params_; }

private:
    std::vector<Parameter> params_;
};

/// Makes the case of one grid point from `info` (the base info with the
/// point's parameters appended to its params, so the name is stable) and the
/// point: make_warp_case, make_bsdf_case or any other maker of a case.
using GridCaseMaker = std::function<std::unique_ptr<WarpCase>(WarpCaseInfo info, const GridPoint& point)>;

/// A family as its grid registered it: the base description, the axes and the maker.
struct CaseFamily {
    WarpCaseInfo base;
    std::vector<GridAxis> axes;
    GridCaseMaker make;
    /// Whether any axis declares a range (only such a family has anything to fuzz).
    bool fuzzable() const {
        for (const GridAxis& a : axes)
            if (!a.ranges.empty()) return true;
        return false;
    }
};

}  // namespace warpcheck

// Parameter families in one call: one warp registered over a grid of parameter
// values (many outgoing directions of a BSDF sampler, many roughnesses), each
// point a case with a stable name, family[axis=value,...], in the order the
// axes are given.
#pragma once

#include <cmath>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "validate/api/registry.h"
#include "validate/api/warp_case.h"

namespace warpcheck {

/// The points of the Cartesian product of the axes, the first axis varying
/// slowest, each with the axes' parameters only. Refused (declaration_error,
/// naming the family): an axis without values or with a non-finite one, or two
/// axes (or an axis and a parameter of `base`) of one name.
inline std::vector<GridPoint> grid_points(const WarpCaseInfo& base, const std::vector<GridAxis>& axes) {
    std::vector<std::string> problems, names;
    for (const Parameter& p : base.params) names.push_back(p.name);
    std::size_t count = 1;
    for (const GridAxis& axis : axes) {
        if (axis.values.empty()) problems.push_back("axis " + axis.name + " has no values");
        for (double v : axis.values)
            if (!std::isfinite(v)) problems.push_back("axis " + axis.name + " has a non-finite value");
        for (const std::string& n : names)
            if (n == axis.name) problems.push_back("two parameters are named " + axis.name);
        names.push_back(axis.name);
        count *= axis.values.size();
    }
    if (!problems.empty()) throw declaration_error("parameter grid of " + base.family, problems);
    std::vector<GridPoint> points;
    for (std::size_t index = 0; index < count; ++index) {
        std::vector<Parameter> point;
        std::size_t rest = index;
        for (std::size_t a = axes.size(); a-- > 0;) {
            point.insert(point.begin(), {axes[a].name, axes[a].values[rest % axes[a].values.size()]});
            rest /= axes[a].values.size();
        }
        points.emplace_back(std::move(point));
    }
    return points;
}


/// Registers make(info, point) for every point of grid_points(base, axes), and
/// the family itself (Registry::families, for --fuzz).
/// Refused, besides what grid_points refuses: a case whose name is not the one
/// the grid gives it (the maker must keep info.params).
inline void add_case_grid(Registry& registry, const WarpCaseInfo& base, const std::vector<GridAxis>& axes,
                          const GridCaseMaker& make) {
    for (const GridPoint& point : grid_points(base, axes)) {
        WarpCaseInfo info = base;
        info.params.insert(info.params.end(), point.params().begin(), point.params().end());
        const std::string expected = case_name(info.family, info.params);
        std::unique_ptr<WarpCase> warp = make(std::move(info), point);
        if (!warp || warp->name() != expected)
            throw declaration_error("parameter grid of " + base.family,
                                    {"the case of " + expected + " is " + (warp ? "named " + warp->name() : "null") +
                                     " (make it from the info given)"});
        registry.add_case(std::move(warp));
    }
    registry.add_family({base, axes, make});
}

}  // namespace warpcheck

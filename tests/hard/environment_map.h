// The catalogue's environment map as a warp: a hard::PiecewiseConstant2D's
// sample, pdf and inverse on warpcheck's points (`environment_zero_rows` and its
// twin in supports.cpp; the round trip's inverse-edge test derives its wrong
// inverses from it).
#pragma once

#include "piecewise.h"
#include "sampling/vector.h"

namespace hard {

struct EnvironmentMap {
    PiecewiseConstant2D map;

    warpcheck::Point2f sample(warpcheck::Point2f u) const {
        const auto p = map.sample(u.x, u.y);
        return {p.x, p.y};
    }
    float pdf(warpcheck::Point2f p) const { return map.pdf({p.x, p.y}); }
    warpcheck::Point2f invert(warpcheck::Point2f p) const {
        const auto u = map.invert({p.x, p.y});
        return {u.x, u.y};
    }
};

}  // namespace hard

#include "validate/checks/tabulated/tabulated_monotonicity.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>

#include "validate/checks/shared/input_chunks.h"

namespace warpcheck {
namespace {

constexpr int kGridPoints = 1 << 16;
constexpr std::size_t kPlotStride = 128;

/// The grid's input values, sorted and distinct: k 2^-16 and the edge values.
std::vector<float> grid_values() {
    std::vector<float> u = edge_values();
    for (int k = 0; k < kGridPoints; ++k) u.push_back(static_cast<float>(k) / kGridPoints);
    std::sort(u.begin(), u.end());
    u.erase(std::unique(u.begin(), u.end()), u.end());
    return u;
}

/// The finite coordinates in input order, with their inputs.
struct Trace {
    std::size_t inputs = 0;
    std::vector<double> u, x;
};

Trace trace(const WarpCase& warp, int input_coordinate, const std::function<double(const WarpOutput&)>& coordinate) {
    const std::vector<float> values = grid_values();
    std::vector<WarpInput> inputs(values.size());
    for (std::size_t i = 0; i < values.size(); ++i) {
        inputs[i].u = {0.5f, 0.5f};
        inputs[i].u[static_cast<std::size_t>(input_coordinate)] = values[i];
    }
    std::vector<WarpOutput> out(inputs.size());
    warp.sample(inputs, out);
    Trace t;
    t.inputs = values.size();
    for (std::size_t i = 0; i < out.size(); ++i) {
        const double x = coordinate ? coordinate(out[i]) : static_cast<double>(out[i][0]);
        if (!std::isfinite(x)) continue;
        t.u.push_back(values[i]);
        t.x.push_back(x);
    }
    return t;
}

}  // namespace

MonotonicityProbe probe_monotonicity(const WarpCase& warp, int input_coordinate,
                                     const std::function<double(const WarpOutput&)>& coordinate, double noise,
                                     std::optional<bool> direction) {
    const Trace t = trace(warp, input_coordinate, coordinate);
    MonotonicityProbe p;
    p.inputs = t.inputs;
    p.finite = t.x.size();
    if (t.x.empty()) return p;
    p.increasing = direction.value_or(t.x.back() >= t.x.front());
    // Against the furthest point reached so far, not the previous one: a slow
    // descent made of steps each within the noise is a fold all the same.
    double furthest = t.x.front();
    for (std::size_t i = 1; i < t.x.size(); ++i) {
        furthest = p.increasing ? std::max(furthest, t.x[i]) : std::min(furthest, t.x[i]);
        const double back = std::abs(furthest - t.x[i]);
        if (!(back > 0.0)) continue;
        if (back <= noise) ++p.behind_within_noise;
        if (back <= p.largest_step_back) continue;
        p.largest_step_back = back;
        if (back <= noise) continue;
        p.monotone = false;
        p.from_x = furthest;
        p.to_x = t.x[i];
        p.at_u = t.u[i];
    }
    for (std::size_t i = 0; i < t.x.size(); i += kPlotStride) {
        p.plot_u.push_back(t.u[i]);
        p.plot_x.push_back(t.x[i]);
    }
    return p;
}

}  // namespace warpcheck

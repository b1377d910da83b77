#include "validate/checks/shared/float_cell.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "sampling/float_bits.h"

namespace warpcheck {
namespace {

// The finite differences (measure_column). A step starts at 1/256 of the
// distance from u_j to the nearer edge of [0,1) (at least 4 floats of u_j):
// warps vary at worst on the scale of that distance (sqrt near 0, log near 1),
// where a central difference of that size is off by about (1/256)^2 of the
// slope. It grows 4x at a time, up to a quarter of the range, until x_k has
// moved by kMeasuredSpacings of its floats: the two values sample returns are
// each within a couple of floats of exact for a float warp, so the slope is
// then right within 4/32 = 1/8. The floats are counted between the two values
// (not as multiples of the spacing at x): at a binade's edge (z = 1 at the
// pole of a cone) the spacing above x is twice the spacing the values move
// through, and a 0.25 degree cone's z has only 160 floats over the whole input
// range (40 over a quarter of it, half of them in spacings of 1.0). Where sample rounds an intermediate value
// first (cos theta, then sin theta from it), its outputs stand still and then
// jump; the growing step spans a few such stairs, and the slope is their
// average within about a factor 2. The last step is a quarter of the range
// exactly (not the last power of 4 below it): a coordinate with few floats over
// the whole input range (cos theta of a 0.25 degree cone has 160) moves by 32
// of them only over such a step, which still measures its slope within 1/8. A
// coordinate that never moves by that much is taken not to depend on u_j.
constexpr double kFirstStep = 1.0 / 256.0;
constexpr double kStepGrowth = 4.0;
constexpr double kLargestStep = 0.25;
constexpr double kMeasuredSpacings = 32.0;
constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Steps from 4 * 2^-149 (u_j = 0) to 1/4, growing 4x: 74; a few more for slack.
constexpr std::size_t kMaxSteps = 80;

using Column = std::array<double, 3>;

/// The inputs of a step of size h along axis j: u - h and u + h where both lie
/// in [0,1), else one-sided toward the inside. False where neither side fits.
bool step_inputs(const WarpInput& u, int j, double h, WarpInput& lo, WarpInput& hi) {
    const auto a = static_cast<std::size_t>(j);
    const double c = u.u[a];
    const bool down = c - h >= 0.0, up = static_cast<float>(c + h) < 1.0f;
    if (!down && !up) return false;
    lo = u;
    hi = u;
    if (down) lo.u[a] = static_cast<float>(c - h);
    if (up) hi.u[a] = static_cast<float>(c + h);
    return true;
}

/// The number of floats from a to b (finite, either sign), by their ordered bit patterns.
double floats_between(float a, float b) {
    auto key = [](float f) {
        const auto bits = static_cast<int64_t>(float_to_bits(f) & ~kFloatSignMask);
        return float_sign_bit(f) ? -bits : bits;
    };
    return static_cast<double>(std::abs(key(a) - key(b)));
}

/// d x / d u_j at u, entry by entry at the smallest step where x_k moved by
/// kMeasuredSpacings floats (0 where it never did).
Column measure_column(const WarpCase& warp, const WarpInput& u, int j, int out_dims) {
    const auto a = static_cast<std::size_t>(j);
    const double c = u.u[a];
    std::array<WarpInput, 2 * kMaxSteps> in{};
    std::array<double, kMaxSteps> du{};
    std::size_t steps = 0;
    double h = std::min(std::max(kFirstStep * std::min(c, 1.0 - c), 4.0 * float_spacing(u.u[a])), kLargestStep);
    while (steps < kMaxSteps) {
        WarpInput lo, hi;
        if (!step_inputs(u, j, h, lo, hi)) break;
        const double width = static_cast<double>(hi.u[a]) - lo.u[a];
        if (width > 0.0) {
            in[2 * steps] = lo;
            in[2 * steps + 1] = hi;
            du[steps++] = width;
        }
        if (h >= kLargestStep) break;
        h = std::min(h * kStepGrowth, kLargestStep);
    }
    std::array<WarpOutput, 2 * kMaxSteps> out{};
    warp.sample(std::span<const WarpInput>(in.data(), 2 * steps), std::span<WarpOutput>(out.data(), 2 * steps));
    Column column{};
    for (int k = 0; k < out_dims; ++k) {
        const auto kk = static_cast<std::size_t>(k);
        for (std::size_t i = 0; i < steps; ++i) {
            const float lo = out[2 * i][kk], hi = out[2 * i + 1][kk];
            if (!std::isfinite(lo) || !std::isfinite(hi) || floats_between(lo, hi) < kMeasuredSpacings) continue;
            column[kk] = (static_cast<double>(hi) - lo) / du[i];
            break;
        }
    }
    return column;
}

/// The extents of the axes `axes` (the ones sample depends on): the
/// least-squares pull-back G^-1 J^T s (G = J^T J) and each coordinate's own
/// s_k / |J_kj|, whichever is larger. A 2x2 Gram matrix is inverted by hand.
void pull_back(FloatCell& cell, const std::array<double, 3>& s, const std::vector<int>& axes, int out_dims) {
    auto J = [&](int k, std::size_t a) { return cell.jacobian[static_cast<std::size_t>(k)][static_cast<std::size_t>(axes[a])]; };
    const std::size_t n = axes.size();
    double g[2][2] = {{0.0, 0.0}, {0.0, 0.0}};
    for (int k = 0; k < out_dims; ++k)
        for (std::size_t a = 0; a < n; ++a)
            for (std::size_t b = 0; b < n; ++b) g[a][b] += J(k, a) * J(k, b);
    const double det = n == 1 ? g[0][0] : g[0][0] * g[1][1] - g[0][1] * g[1][0];
    const double inv[2][2] = {{n == 1 ? 1.0 / det : g[1][1] / det, -g[0][1] / det}, {-g[1][0] / det, g[0][0] / det}};
    for (std::size_t a = 0; a < n; ++a) {
        double least_squares = 0.0, own = 0.0;
        for (int k = 0; k < out_dims; ++k) {
            double row = 0.0;  // (G^-1 J^T)[a][k]
            for (std::size_t b = 0; b < n; ++b) row += inv[a][b] * J(k, b);
            least_squares += std::abs(row) * s[static_cast<std::size_t>(k)];
            if (J(k, a) != 0.0) own = std::max(own, s[static_cast<std::size_t>(k)] / std::abs(J(k, a)));
        }
        const double extent = det > 0.0 && std::isfinite(least_squares) ? std::max(least_squares, own) : own;
        cell.extent[static_cast<std::size_t>(axes[a])] = std::isfinite(extent) ? extent : 0.0;
    }
}

}  // namespace

double float_spacing(float x) {
    const float a = std::abs(x);
    return static_cast<double>(next_float_up(a)) - static_cast<double>(a);
}

FloatCell measure_float_cell(const WarpCase& warp, const WarpInput& u, const WarpOutput& x, int in_dims,
                             int out_dims) {
    FloatCell cell;
    std::array<double, 3> s{};
    for (int k = 0; k < out_dims; ++k) s[static_cast<std::size_t>(k)] = float_spacing(x[static_cast<std::size_t>(k)]);
    std::vector<int> axes;  // those sample depends on
    for (int j = 0; j < in_dims; ++j) {
        const Column column = measure_column(warp, u, j, out_dims);
        bool moved = false;
        for (int k = 0; k < out_dims; ++k) {
            cell.jacobian[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)] = column[static_cast<std::size_t>(k)];
            moved = moved || column[static_cast<std::size_t>(k)] != 0.0;
        }
        if (moved)
            axes.push_back(j);
        else
            cell.extent[static_cast<std::size_t>(j)] = kInfinity;
    }
    if (!axes.empty()) pull_back(cell, s, axes, out_dims);
    return cell;
}

}  // namespace warpcheck

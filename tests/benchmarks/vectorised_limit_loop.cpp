// Built with -fno-math-errno and -fno-trapping-math (CMakeLists.txt): with
// errno, sqrt is a call guarded by a branch, and with trapping maths GCC keeps
// the selects as branches; either stops the vectoriser. Neither changes a value.
#include "vectorised_limit_loop.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "sampling/math.h"
#include "sampling/pcg32.h"

namespace warpcheck::bench {

namespace {
constexpr int S = 16;  // streams in lockstep: one AVX-512 register of floats

// PCG32's step and output in a 64-bit lane; the top 24 bits of the output times 2^-24.
inline float pcg32_float(uint64_t& state, uint64_t inc) {
    const uint64_t old = state;
    state = old * Pcg32::kMultiplier + inc;
    const uint64_t xorshifted = (((old >> 18u) ^ old) >> 27u) & 0xffffffffu, rot = old >> 59u;
    const uint64_t bits = ((xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u))) & 0xffffffffu;
    return static_cast<float>(static_cast<int64_t>(bits >> 8u)) * 0x1p-24f;
}

// One loop body per lane, from the draws to the cell, so the vectoriser keeps
// every value in registers (a loop per stage stored each stage to the stack:
// 300 against 350 M samples/s); kEdges = octant_cols - 1 column edges per
// octant, a constant so the comparisons unroll.
template <int kEdges>
[[gnu::target_clones("arch=x86-64-v4", "default")]] void limit_loop(uint64_t samples, const chi2::LanePlan& plan,
                                                                    std::vector<uint64_t>& counts) {
    alignas(64) uint64_t state[S], inc[S];
    for (int l = 0; l < S; ++l) {
        const Pcg32 rng(static_cast<uint64_t>(l), 3);
        state[l] = rng.state(), inc[l] = rng.increment();
    }
    float tan_edges[kEdges > 0 ? kEdges : 1] = {};
    for (int k = 0; k < kEdges; ++k) tan_edges[k] = static_cast<float>(plan.tan_edges[k]);
    const int32_t quadrant_cols = 2 * (kEdges + 1), cols = plan.cols;
    const float v0 = static_cast<float>(plan.v0), inv_dv = static_cast<float>(plan.inv_dv);
    const float last_row = static_cast<float>(plan.rows - 1);
    counts.assign(static_cast<std::size_t>(plan.rows * plan.cols), 0);
    for (uint64_t i = 0; i < samples; i += S) {
        alignas(64) int32_t cell[S];
        for (int l = 0; l < S; ++l) {
            const float u0 = pcg32_float(state[l], inc[l]), u1 = pcg32_float(state[l], inc[l]);
            const float a = 2.0f * u0 - 1.0f, b = 2.0f * u1 - 1.0f;
            const bool wide = std::abs(a) > std::abs(b);
            const float r = wide ? a : b;
            const float w = kPiOver4 * ((wide ? b : a) / (r != 0.0f ? r : 1.0f)), w2 = w * w;  // 0/1 at the centre
            const float sin_w =
                w + w * w2 * (-1.0f / 6 + w2 * (1.0f / 120 + w2 * (-1.0f / 5040 + w2 * (1.0f / 362880))));
            const float cos_w = 1.0f + w2 * (-0.5f + w2 * (1.0f / 24 + w2 * (-1.0f / 720 +
                                                                             w2 * (1.0f / 40320 - w2 * (1.0f / 3628800)))));
            // The wedge |a| > |b| has phi = w; the other phi = pi/2 - w, whose cos is sin w.
            const float x = r * (wide ? cos_w : sin_w), y = r * (wide ? sin_w : cos_w);
            const float z = std::sqrt(std::max(1.0f - x * x - y * y, 0.0f));
            const float ax = std::abs(x), ay = std::abs(y), hi = std::max(ax, ay), lo = std::min(ax, ay);
            int32_t j = 0;  // the octant column: tan of the angle to the nearer axis, lo / hi, against the edges
            for (int k = 0; k < kEdges; ++k) j += lo >= tan_edges[k] * hi ? 1 : 0;
            const int32_t row = static_cast<int32_t>(std::min(std::max((z - v0) * inv_dv, 0.0f), last_row));
            const int32_t q = ay > ax ? quadrant_cols - 1 - j : j;  // the column as lane_cells: mirrored by quadrant
            const int32_t mirrored = 2 * quadrant_cols - 1 - q;
            const int32_t col = x < 0.0f ? (y < 0.0f ? q + 2 * quadrant_cols : mirrored)
                                         : (y < 0.0f ? mirrored + 2 * quadrant_cols : q);
            cell[l] = row * cols + col;
        }
        for (int l = 0; l < S; ++l) ++counts[static_cast<std::size_t>(cell[l])];
    }
}

template <int... kEdges>
void dispatch(int edges, uint64_t samples, const chi2::LanePlan& plan, std::vector<uint64_t>& counts,
              std::integer_sequence<int, kEdges...>) {
    ((edges == kEdges ? limit_loop<kEdges>(samples, plan, counts) : void()), ...);
}
}  // namespace

void vectorised_limit_loop(uint64_t samples, const chi2::LanePlan& plan, std::vector<uint64_t>& counts) {
    dispatch(plan.octant_cols - 1, samples, plan, counts,
             std::make_integer_sequence<int, chi2::LanePlan::kMaxOctantCols>{});
}

}  // namespace warpcheck::bench

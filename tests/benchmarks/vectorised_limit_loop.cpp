// Built with -fno-math-errno and -fno-trapping-math (CMakeLists.txt): with
// errno, sqrt is a call guarded by a branch, and with trapping maths GCC keeps
// the selects as branches; either stops the vectoriser. Neither changes a value.
#include "vectorised_limit_loop.h"

#include <algorithm>
#include <cmath>

#include "sampling/math.h"
#include "sampling/pcg32.h"

namespace warpcheck::bench {

namespace {
constexpr int S = 16;  // streams in lockstep: one AVX-512 register of floats
}

[[gnu::target_clones("arch=x86-64-v4", "default")]] void vectorised_limit_loop(uint64_t samples,
                                                                               const chi2::LanePlan& plan,
                                                                               std::vector<uint64_t>& counts) {
    alignas(64) uint64_t state[S], inc[S];
    for (int l = 0; l < S; ++l) {
        const Pcg32 rng(static_cast<uint64_t>(l), 3);
        state[l] = rng.state(), inc[l] = rng.increment();
    }
    float tan_edges[chi2::LanePlan::kMaxOctantCols];
    for (int k = 0; k + 1 < plan.octant_cols; ++k) tan_edges[k] = static_cast<float>(plan.tan_edges[k]);
    const int quadrant_cols = 2 * plan.octant_cols;
    const float v0 = static_cast<float>(plan.v0), inv_dv = static_cast<float>(plan.inv_dv);
    const float last_row = static_cast<float>(plan.rows - 1);
    counts.assign(static_cast<std::size_t>(plan.rows * plan.cols), 0);
    for (uint64_t i = 0; i < samples; i += S) {
        alignas(64) float u[2][S], x[S], y[S], t[S];
        alignas(64) int32_t row[S], j[S] = {};
        for (int l = 0; l < S; ++l)
            for (float* d : {&u[0][l], &u[1][l]}) {  // PCG32's step and output, in 64-bit lanes
                const uint64_t old = state[l];
                state[l] = old * Pcg32::kMultiplier + inc[l];
                const uint64_t xorshifted = (((old >> 18u) ^ old) >> 27u) & 0xffffffffu, rot = old >> 59u;
                const uint64_t bits = ((xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u))) & 0xffffffffu;
                *d = static_cast<float>(static_cast<int64_t>(bits >> 8u)) * 0x1p-24f;
            }
        for (int l = 0; l < S; ++l) {
            const float a = 2.0f * u[0][l] - 1.0f, b = 2.0f * u[1][l] - 1.0f;
            const bool wide = std::abs(a) > std::abs(b);
            const float r = wide ? a : b;
            const float w = kPiOver4 * ((wide ? b : a) / (r != 0.0f ? r : 1.0f)), w2 = w * w;  // 0/1 at the centre
            const float sin_w = w + w * w2 * (-1.0f / 6 + w2 * (1.0f / 120 + w2 * (-1.0f / 5040 + w2 / 362880)));
            const float cos_w =
                1.0f + w2 * (-0.5f + w2 * (1.0f / 24 + w2 * (-1.0f / 720 + w2 * (1.0f / 40320 - w2 / 3628800))));
            // The wedge |a| > |b| has phi = w; the other phi = pi/2 - w, whose cos is sin w.
            x[l] = r * (wide ? cos_w : sin_w), y[l] = r * (wide ? sin_w : cos_w);
            const float z = std::sqrt(std::max(1.0f - x[l] * x[l] - y[l] * y[l], 0.0f));
            const float ax = std::abs(x[l]), ay = std::abs(y[l]), hi = std::max(ax, ay);
            t[l] = std::min(ax, ay) / (hi > 0.0f ? hi : 1.0f);
            row[l] = static_cast<int32_t>(std::min(std::max((z - v0) * inv_dv, 0.0f), last_row));
        }
        for (int k = 0; k + 1 < plan.octant_cols; ++k)
            for (int l = 0; l < S; ++l) j[l] += t[l] >= tan_edges[k] ? 1 : 0;
        for (int l = 0; l < S; ++l) {  // the column as lane_cells: the octant's, mirrored by quadrant
            const int32_t q = std::abs(y[l]) > std::abs(x[l]) ? quadrant_cols - 1 - j[l] : j[l];
            const int32_t mirrored = 2 * quadrant_cols - 1 - q;
            const int32_t col = x[l] < 0.0f ? (y[l] < 0.0f ? q + 2 * quadrant_cols : mirrored)
                                            : (y[l] < 0.0f ? mirrored + 2 * quadrant_cols : q);
            j[l] = row[l] * plan.cols + col;
        }
        for (int l = 0; l < S; ++l) ++counts[static_cast<std::size_t>(j[l])];
    }
}

}  // namespace warpcheck::bench

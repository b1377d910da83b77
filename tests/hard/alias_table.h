// Vose's alias table in float, as pbrt-v4's AliasTable samples it: u picks a
// bucket and a threshold decides between it and its alias; u is remapped to
// [0,1) within the chosen part for reuse. Plain math, nothing of warpcheck.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace hard {

struct AliasTable {
    std::vector<float> q;
    std::vector<uint32_t> alias;
    explicit AliasTable(const std::vector<float>& w) : q(w.size(), 1.0f), alias(w.size()) {
        const double total = std::accumulate(w.begin(), w.end(), 0.0);
        std::vector<double> scaled(w.size());
        std::vector<uint32_t> small, large;
        for (uint32_t i = 0; i < w.size(); ++i) {
            scaled[i] = w[i] * static_cast<double>(w.size()) / total;
            alias[i] = i;
            (scaled[i] < 1 ? small : large).push_back(i);
        }
        while (!small.empty() && !large.empty()) {
            const uint32_t s = small.back(), l = large.back();
            small.pop_back();
            q[s] = static_cast<float>(scaled[s]);
            alias[s] = l;
            scaled[l] -= 1 - scaled[s];
            if (scaled[l] < 1) large.pop_back(), small.push_back(l);
        }
    }
    /// The bucket and u remapped to [0,1) within it.
    std::pair<uint32_t, float> sample(float u) const {
        const float scaled = u * static_cast<float>(q.size());
        const uint32_t i = std::min(static_cast<uint32_t>(scaled), static_cast<uint32_t>(q.size() - 1));
        const float up = scaled - static_cast<float>(i);
        if (up < q[i]) return {i, std::fmin(up / q[i], 0x1.fffffep-1f)};
        return {alias[i], std::fmin((up - q[i]) / (1 - q[i]), 0x1.fffffep-1f)};
    }
};

}  // namespace hard

// Built with -fno-math-errno (validate/CMakeLists.txt), so that lanes::sqrt is
// one vector square root: the lanes never take the root of a negative number.
#include "validate/lane_sampling.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "validate/lane_cells.h"
#include "sampling/lane_warps.h"
#include "validate/check.h"

// Lane vectors are passed only between always_inline functions (sampling/lanes.h).
#pragma GCC diagnostic ignored "-Wpsabi"

namespace warpcheck {
namespace {

using lanes::F32;
using lanes::I64;

/// The lockstep loop of one group, for one warp's lane form: two sets of
/// lanes::kWidth lanes per step, independent, so that one set's long
/// latencies (divisions, square roots, the generators' multiply chains)
/// overlap with the other's work.
template <typename Kernel>
WARPCHECK_LANE void run_group(const Kernel& warp, const LaneGroup& g) {
    constexpr int W = lanes::kWidth;
    lanes::Pcg32Lanes rng_a, rng_b;
    std::memcpy(&rng_a.state, g.state, sizeof rng_a.state);
    std::memcpy(&rng_a.inc, g.inc, sizeof rng_a.inc);
    std::memcpy(&rng_b.state, g.state + W, sizeof rng_b.state);
    std::memcpy(&rng_b.inc, g.inc + W, sizeof rng_b.inc);
    const chi2::LanePlan& plan = *g.plan;
    const bool all_lanes = std::all_of(g.samples, g.samples + kLaneGroupChunks, [&](uint32_t n) { return n == g.steps; });
    const unsigned char* const zero = g.zero_cells;
    uint64_t* const counts = g.counts;
    alignas(64) int64_t cell[kLaneGroupChunks];
    for (uint32_t i = 0; i < g.steps; ++i) {
        // As draw_inputs: u.x from the first 64 bits, u.y from the next.
        const F32 a0 = lanes::uniform_float_from_bits(rng_a.next_u64());
        const F32 a1 = lanes::uniform_float_from_bits(rng_a.next_u64());
        const F32 b0 = lanes::uniform_float_from_bits(rng_b.next_u64());
        const F32 b1 = lanes::uniform_float_from_bits(rng_b.next_u64());
        const lanes::Points pa = warp(a0, a1), pb = warp(b0, b1);
        const I64 ca = lane_cells(plan, pa.x, pa.y, pa.z), cb = lane_cells(plan, pb.x, pb.y, pb.z);
        std::memcpy(cell, &ca, sizeof ca);
        std::memcpy(cell + W, &cb, sizeof cb);
        int64_t any_unclassified = 0;
        for (int l = 0; l < kLaneGroupChunks; ++l) any_unclassified |= cell[l];
        if (all_lanes && !zero && any_unclassified >= 0) {
            for (int l = 0; l < kLaneGroupChunks; ++l) ++counts[cell[l]];
            continue;
        }
        for (int l = 0; l < kLaneGroupChunks; ++l) {
            if (i >= g.samples[l]) continue;
            const int64_t k = cell[l];
            const lanes::Points& p = l < W ? pa : pb;
            const int m = l % W;
            if (k >= 0 && !(zero && zero[k])) ++counts[k];
            else g.unclassified->push_back({p.x[m], p.y[m], p.z[m]});
        }
    }
}

template <typename Kernel>
struct Entry {
    static constexpr Kernel kKernel{};
    [[gnu::target("arch=x86-64-v4")]] static void avx512(const void* kernel, const LaneGroup& g) {
        run_group(*static_cast<const Kernel*>(kernel), g);
    }
    static void portable(const void* kernel, const LaneGroup& g) { run_group(*static_cast<const Kernel*>(kernel), g); }
    static const LaneSampler& sampler() {
        static const LaneSampler s{&kKernel, &Entry::avx512, &Entry::portable};
        return s;
    }
};

}  // namespace

namespace builtin_lanes {
const LaneSampler& uniform_disk_polar() { return Entry<lanes::UniformDiskPolarLanes>::sampler(); }
const LaneSampler& uniform_disk_concentric() { return Entry<lanes::UniformDiskConcentricLanes>::sampler(); }
const LaneSampler& cosine_hemisphere() { return Entry<lanes::CosineHemisphereLanes>::sampler(); }
const LaneSampler& uniform_hemisphere() { return Entry<lanes::UniformHemisphereLanes>::sampler(); }
const LaneSampler& uniform_sphere() { return Entry<lanes::UniformSphereLanes>::sampler(); }
}  // namespace builtin_lanes

bool avx512_available() {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
           __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
           __builtin_cpu_supports("avx512vl");
}

LanePath auto_lane_path() { return avx512_available() ? LanePath::Avx512 : LanePath::Portable; }

const char* lane_path_name(LanePath path) {
    switch (path) {
        case LanePath::Auto: return lane_path_name(auto_lane_path());
        case LanePath::Avx512: return "avx512";
        case LanePath::Portable: return "portable";
    }
    return "?";
}

chi2::Histogram lane_histogram(const chi2::Binning& binning, uint64_t samples, std::size_t chunk_size,
                               const std::function<Pcg32(uint64_t chunk)>& chunk_rng, const LaneSampler& sampler,
                               std::span<const unsigned char> zero_cells, const chi2::ParallelFor& parallel_for,
                               LanePath path) {
    const std::optional<chi2::LanePlan> plan = binning.lane_plan();
    if (!plan) throw std::invalid_argument("lane_histogram: the binning has no lane plan");
    if (chunk_size == 0 || chunk_size > UINT32_MAX) throw std::invalid_argument("lane_histogram: bad chunk size");
    if (!zero_cells.empty() && zero_cells.size() != binning.cell_count())
        throw std::invalid_argument("lane_histogram: zero-cell mask of another binning");
    if (path == LanePath::Auto) path = auto_lane_path();
    if (path == LanePath::Avx512 && !avx512_available())
        throw std::runtime_error("lane_histogram: this processor has no AVX-512");
    const LaneSampler::GroupFn run = path == LanePath::Avx512 ? sampler.avx512 : sampler.portable;

    const std::size_t cells = binning.cell_count();
    // Without zero cells (the usual case) the lanes skip the per-sample lookup.
    const bool any_zero_cell = std::any_of(zero_cells.begin(), zero_cells.end(), [](unsigned char z) { return z != 0; });
    const uint64_t chunks = (samples + chunk_size - 1) / chunk_size;
    const uint64_t groups = (chunks + kLaneGroupChunks - 1) / kLaneGroupChunks;
    // Histograms as chi2::sample_histogram keeps them: a fixed number, each
    // taking every H-th group, merged in order (integer sums: any order agrees).
    const uint64_t hist_cap = std::clamp<uint64_t>((uint64_t{1} << 22) / std::max<std::size_t>(cells, 1), 1, 64);
    const auto histograms = static_cast<std::size_t>(std::max<uint64_t>(std::min(groups, hist_cap), 1));
    std::vector<chi2::Histogram> part(histograms);
    const chi2::ParallelFor& each = parallel_for ? parallel_for : chi2::ParallelFor(chi2::serial_for);
    each(histograms, [&](std::size_t h) {
        chi2::Histogram& hist = part[h];
        hist.counts.assign(cells, 0);
        std::vector<WarpOutput> unclassified;
        for (uint64_t g = h; g < groups; g += histograms) {
            LaneGroup group;
            group.plan = &*plan;
            group.zero_cells = any_zero_cell ? zero_cells.data() : nullptr;
            group.counts = hist.counts.data();
            group.unclassified = &unclassified;
            for (int l = 0; l < kLaneGroupChunks; ++l) {
                const uint64_t chunk = g * kLaneGroupChunks + static_cast<uint64_t>(l);
                // A lane past the last chunk steps a copy of the first and counts nothing.
                const Pcg32 rng = chunk_rng(chunk < chunks ? chunk : g * kLaneGroupChunks);
                group.state[l] = rng.state();
                group.inc[l] = rng.increment();
                if (chunk < chunks)
                    group.samples[l] = static_cast<uint32_t>(std::min<uint64_t>(chunk_size, samples - chunk * chunk_size));
                group.steps = std::max(group.steps, group.samples[l]);
            }
            run(sampler.kernel, group);
            binning.bin(std::span<const WarpOutput>(unclassified), hist, zero_cells);
            unclassified.clear();
        }
    });
    chi2::Histogram total;
    total.counts.assign(cells, 0);
    for (const chi2::Histogram& h : part) total.merge(h);
    return total;
}

}  // namespace warpcheck

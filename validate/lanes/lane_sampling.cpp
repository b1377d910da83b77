// The vectorised chi-square path's driver, and the portable build of its
// lockstep loops. Built with -fno-math-errno (validate/CMakeLists.txt), so that
// lanes::sqrt is a vector square root: the lanes never take the root of a
// negative number.
#include "validate/lanes/lane_sampling.h"

#include <algorithm>
#include <deque>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "chi2/chi2_test.h"
#include "validate/lanes/lane_kernels.h"

// Lane vectors pass only between always_inline functions (sampling/lanes.h).
#pragma GCC diagnostic ignored "-Wpsabi"

namespace warpcheck {

namespace lane_kernels {
// The portable build of the lockstep loops: this file is compiled for the baseline target.
#define WARPCHECK_DEFINE_GROUP_FN(name, Kernel) \
    void name##_portable(const void* kernel, const LaneGroup& g) { \
        run_group(*static_cast<const lanes::Kernel*>(kernel), g); \
    }
WARPCHECK_LANE_FORMS(WARPCHECK_DEFINE_GROUP_FN)
#undef WARPCHECK_DEFINE_GROUP_FN

void planar_portable(const void* warp, const LaneGroup& g) { run_planar_group(warp, g); }

void sample_planar(const void* warp, const float* u0, const float* u1, float* x, float* y, float* z, std::size_t n) {
    static_cast<const WarpCase*>(warp)->sample_planar(u0, u1, x, y, z, n);
}
}  // namespace lane_kernels

LaneSampler planar_lane_sampler(const WarpCase& warp) {
    return {&warp, &lane_kernels::planar_avx512, &lane_kernels::planar_avx2, &lane_kernels::planar_portable};
}

namespace builtin_lanes {
#define WARPCHECK_DEFINE_SAMPLER(name, Kernel)                                                      \
    const LaneSampler& name() {                                                                    \
        static constexpr lanes::Kernel kernel{};                                                    \
        static const LaneSampler sampler{&kernel, &lane_kernels::name##_avx512, &lane_kernels::name##_avx2, \
                                         &lane_kernels::name##_portable};                          \
        return sampler;                                                                            \
    }
WARPCHECK_PLAIN_LANE_FORMS(WARPCHECK_DEFINE_SAMPLER)
#undef WARPCHECK_DEFINE_SAMPLER

namespace {

/// The sampler of a lane form with parameters, one per distinct kernel (its
/// parameters), kept for the life of the process: cases point to it.
template <typename Kernel>
const LaneSampler& parameterised(const Kernel& kernel, LaneSampler::GroupFn avx512, LaneSampler::GroupFn avx2,
                                 LaneSampler::GroupFn portable) {
    struct Entry {
        Kernel kernel;
        LaneSampler sampler;
    };
    static std::mutex mutex;
    static std::deque<Entry> entries;  // a deque: elements never move
    const std::lock_guard lock(mutex);
    for (const Entry& e : entries)
        if (e.kernel == kernel) return e.sampler;
    Entry& e = entries.emplace_back(Entry{kernel, {}});
    e.sampler = {&e.kernel, avx512, avx2, portable};
    return e.sampler;
}

}  // namespace

const LaneSampler& uniform_cone(float cos_theta_max) {
    return parameterised(lanes::UniformConeLanes{cos_theta_max}, &lane_kernels::uniform_cone_avx512, &lane_kernels::uniform_cone_avx2,
                         &lane_kernels::uniform_cone_portable);
}

const LaneSampler& cosine_power_hemisphere(float exponent) {
    return parameterised(lanes::CosinePowerHemisphereLanes{exponent}, &lane_kernels::cosine_power_hemisphere_avx512, &lane_kernels::cosine_power_hemisphere_avx2,
                         &lane_kernels::cosine_power_hemisphere_portable);
}

const LaneSampler& trowbridge_reitz_normals(float alpha_x, float alpha_y) {
    return parameterised(lanes::TrowbridgeReitzNormalsLanes{alpha_x, alpha_y},
                         &lane_kernels::trowbridge_reitz_normals_avx512, &lane_kernels::trowbridge_reitz_normals_avx2,
                         &lane_kernels::trowbridge_reitz_normals_portable);
}

const LaneSampler& trowbridge_reitz_visible(const TrowbridgeReitzVisibleNormals& warp) {
    return parameterised(lanes::TrowbridgeReitzVisibleNormalsLanes(warp), &lane_kernels::trowbridge_reitz_visible_avx512, &lane_kernels::trowbridge_reitz_visible_avx2,
                         &lane_kernels::trowbridge_reitz_visible_portable);
}
}  // namespace builtin_lanes

bool avx512_available() {
#if !defined(__x86_64__)
    return false;
#else
    static const bool available = [] {  // asked by every chi-square check: once per process
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
               __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
               __builtin_cpu_supports("avx512vl");
    }();
    return available;
#endif
}

bool avx2_available() {
#if !defined(__x86_64__)
    return false;
#else
    static const bool available = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("x86-64-v3");
    }();
    return available;
#endif
}

LanePath auto_lane_path() {
    if (avx512_available()) return LanePath::Avx512;
    return avx2_available() ? LanePath::Avx2 : LanePath::Portable;
}

bool vector_lane_path_available() { return auto_lane_path() != LanePath::Portable; }

const char* lane_path_name(LanePath path) {
    switch (path) {
        case LanePath::Auto: return lane_path_name(auto_lane_path());
        case LanePath::Avx512: return "avx512";
        case LanePath::Avx2: return "avx2";
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
    if (path == LanePath::Avx2 && !avx2_available())
        throw std::runtime_error("lane_histogram: this processor has no AVX2 (x86-64-v3)");
    const LaneSampler::GroupFn run = path == LanePath::Avx512 ? sampler.avx512
                                     : path == LanePath::Avx2 ? sampler.avx2
                                                              : sampler.portable;

    const std::size_t cells = binning.cell_count();
    // Without zero cells (the usual case) the lanes skip the per-sample lookup.
    const bool any_zero_cell = std::any_of(zero_cells.begin(), zero_cells.end(), [](unsigned char z) { return z != 0; });
    const uint64_t chunks = (samples + chunk_size - 1) / chunk_size;
    const uint64_t groups = (chunks + kLaneGroupChunks - 1) / kLaneGroupChunks;
    // Histograms as chi2::sample_histogram keeps them: a fixed number, each
    // taking every H-th group, merged in order (integer sums: any order agrees).
    const std::size_t histograms = chi2::histogram_count(groups, cells);
    std::vector<chi2::Histogram> part(histograms);
    const chi2::ParallelFor& each = parallel_for ? parallel_for : chi2::ParallelFor(chi2::serial_for);
    each(histograms, [&](std::size_t h) {
        chi2::Histogram& hist = part[h];
        hist.counts.assign(cells, 0);
        // Room for every sample of a group, should none be classified; left
        // uninitialised (1.2 MB that zeroing would touch once per histogram).
        const auto unclassified = std::make_unique_for_overwrite<WarpOutput[]>(kLaneGroupChunks * chunk_size);
        std::size_t unclassified_count = 0;
        for (uint64_t g = h; g < groups; g += histograms) {
            LaneGroup group;
            group.plan = &*plan;
            group.zero_cells = any_zero_cell ? zero_cells.data() : nullptr;
            group.counts = hist.counts.data();
            group.unclassified = unclassified.get();
            group.unclassified_count = &unclassified_count;
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
            binning.bin(std::span<const WarpOutput>(unclassified.get(), unclassified_count), hist, zero_cells);
        }
    });
    chi2::Histogram total;
    total.counts.assign(cells, 0);
    for (const chi2::Histogram& h : part) total.merge(h);
    return total;
}

}  // namespace warpcheck

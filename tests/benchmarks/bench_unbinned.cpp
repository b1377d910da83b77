// The unbinned check's cost against what it cannot avoid (issue 36's target:
// a row of 10^6 samples at most 3 times the time of drawing them and sorting
// them once).
//   BM_UnbinnedRowVsDrawAndSort/k   the whole check as a worker runs it (one
//       thread, 10^6 samples, CDF tables, transforms, sorts, statistics) beside
//       the same samples drawn by the check's own path (map_input_chunks and
//       the case's batched sample) with one coordinate, mapped onto [0, 1] by its
//       range, sorted by the check's own radix sort (chi2::sort_unit_values:
//       std::sort takes about 4 times as long, and would flatter the check);
//       counter times_draw_and_sort = subject / reference (best of the rounds).
//   k: 0 cosine_hemisphere (two marginals on the sphere, float bands by the
//      model); 1 uniform_float_interval[a=-3,b=5] (one marginal, a band per
//      sample: the interval crosses 0, so float resolution varies along it);
//      2 trowbridge_reitz_visible[ax=0.3,ay=0.3,theta_o=60] (a lobe, a view).
// Run: build/test/tests/benchmarks/bench_unbinned
//
// Measured 2026-12-02, 2-core AMD EPYC (AVX-512), quiet: times_draw_and_sort
// 1.89 (199 ms against 105 ms), 0.75 (96 against 128: the interval's exact-float
// draws, sample_below_power_of_two, are most of both) and 2.09 (269 against 128).
// The draws are the scalar chunk path's, about 12 M samples/s for the cosine
// hemisphere; chi2's lanes draw, warp and bin it at 139 M/s on one thread
// (bench_chi2 --benchmark_filter=PerCore/1, the same day).
#include <algorithm>
#include <array>
#include <span>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "chi2/unbinned.h"
#include "paired_timing.h"
#include "support/builtin_case.h"
#include "validate/api/warp_case.h"
#include "validate/checks/check.h"
#include "validate/checks/checks.h"
#include "validate/checks/shared/input_chunks.h"
#include "validate/run/thread_pool.h"

namespace warpcheck {
namespace {

constexpr uint64_t kSamples = 1'000'000;
constexpr std::array<const char*, 3> kCases = {"cosine_hemisphere", "uniform_float_interval[a=-3,b=5]",
                                               "trowbridge_reitz_visible[ax=0.3,ay=0.3,theta_o=60]"};

/// The samples drawn as the check draws them, then the first coordinate of
/// every one, mapped onto [0, 1] by its range, sorted: the floor of any test
/// of the samples' law.
double draw_and_sort(const WarpCase& warp, const CheckContext& ctx) {
    const auto chunks = map_input_chunks<std::vector<WarpOutput>>(
        ctx, warp.input_kind(), kSamples, false, [&](std::size_t, std::span<const WarpInput> in) {
            std::vector<WarpOutput> out(in.size());
            warp.sample(in, out);
            return out;
        });
    std::vector<double> first;
    first.reserve(kSamples);
    for (const auto& chunk : chunks)
        for (const WarpOutput& o : chunk) first.push_back(o[0]);
    if (first.empty()) return 0.0;
    const auto [lo, hi] = std::minmax_element(first.begin(), first.end());
    const double a = *lo, w = *hi > *lo ? *hi - *lo : 1.0;
    for (double& x : first) x = std::clamp((x - a) / w, 0.0, 1.0);
    chi2::sort_unit_values(first);
    return first[first.size() / 2];
}

void BM_UnbinnedRowVsDrawAndSort(benchmark::State& state) {
    const std::string name = kCases[static_cast<std::size_t>(state.range(0))];
    const WarpCase& warp = testing::builtin_case(name);
    ThreadPool pool(1);
    RunOptions options;
    options.samples = kSamples;
    options.threads = 1;
    const CheckContext ctx(options, pool.executor(), stream_for(warp.name(), options.seed));
    const auto check = make_unbinned_check();
    bench::run_paired(
        state,
        [&] {
            const CheckResult r = check->run(warp, ctx);
            if (r.verdict != Verdict::Pass) state.SkipWithError(("check did not pass: " + r.message).c_str());
        },
        [&] { benchmark::DoNotOptimize(draw_and_sort(warp, ctx)); });
    state.counters["times_draw_and_sort"] = state.counters["subject_min_ms"] / state.counters["reference_min_ms"];
    state.SetLabel(name);
}
BENCHMARK(BM_UnbinnedRowVsDrawAndSort)
    ->Arg(0)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(5);

}  // namespace
}  // namespace warpcheck

BENCHMARK_MAIN();

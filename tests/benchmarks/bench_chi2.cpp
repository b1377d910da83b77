// The chi-square check's speed target: one check of a spherical 2D warp (the
// cosine hemisphere) with 10^7 samples, expected-count integration included,
// in under 0.2 s on 2 threads. The parts are measured apart as well:
//   BM_Chi2Check            the whole check as the runner calls it
//   BM_Chi2SampleAndBin     sampling + binning only (items/s = samples/s)
//   BM_Chi2BinOnly          binning only, of pre-drawn samples (items/s = samples/s)
//   BM_Chi2Integration      expected counts only, at the accuracy rule for 10^7 samples
// and, each beside the plain reference it is measured against (paired_timing.h;
// counter speedup = reference / subject, best of the rounds):
//   BM_Chi2CheckVsPbrt      the whole check on 2 threads vs the pbrt-style
//                           procedure (pbrt_style_chi2.h) on one
//   BM_DrawWarpBinPerCore   draw + warp + bin on one thread vs a plain scalar
//                           fused loop (PCG32, the warp, atan2, a grid index)
//   BM_DrawWarpBinVsLimitLoop  the lane path on one thread vs a plain loop left
//                           to the vectoriser (vectorised_limit_loop.h): the speed
//                           limit; counter times_limit_loop
//   BM_PlainWarpVsLanePath  a renderer's plain warp (arg 0, 1), and one written
//                           as a template over its float type (arg 2), vs the
//                           built-in lane form
// Run: build/test/tests/benchmarks/bench_chi2 --benchmark_filter='Vs|PerCore'
// (the draw + warp + bin ones: --benchmark_filter=DrawWarpBin)
//
// Measured 2026-11-23 (Release, g++ 12, 2-core AMD EPYC with AVX-512, shared
// with other builds), best of the rounds, before any vectorisation (issue 16):
//   load 9.8:  check 518 ms on 2 threads, pbrt-style 1472 ms on one: speedup 2.84;
//              draw+warp+bin 21.1 M samples/s on one thread, fused loop 10.8 M/s: 1.96
//   load 14.3: check 884 ms, pbrt-style 3050 ms: 3.45; 9.8 vs 4.8 M/s: 2.04
// With the vectorised path (validate/lanes/lane_sampling.h, three sets of 8 lanes),
// 16:47-16:52 UTC, machine otherwise idle (load 0.4-1.3, this benchmark itself),
// five runs of --benchmark_filter='Vs|PerCore' or 'PerCore/1':
//   check 37.1-38.6 ms on 2 threads, pbrt-style 834-858 ms on one: speedup 22.2-22.8;
//   draw+warp+bin 143-152 M samples/s on one thread (lanes, avx512; the
//   machine's own speed drifts ~5% between runs), fused loop 16-17 M/s;
//   the scalar chunk path (BM_DrawWarpBinPerCore/0) 28-31 M/s, the portable lane build 20-24 M/s.
// Second stop, 18:45-18:46 UTC, machine otherwise idle (load ~1, this
// benchmark itself), after Pcg32Lanes kept each step in its 64-bit lane
// (vprorvq instead of narrowing and widening): check 35.2 ms (min of 3) on 2
// threads vs pbrt-style 888 ms on one, speedup 25.2; draw+warp+bin 165-167 M
// samples/s on one thread (three runs; 151-152 M/s just before), fused loop
// 15.6 M/s; the scalar chunk path 27.2 M/s, the portable lane build 19.9 M/s.
// A fourth set of lanes measured the same (143-146 M/s beside 143-145 for three).
// Then with the unclassified-sample buffer left uninitialised (it was zeroed,
// 1.2 MB per histogram), 17:19 UTC, load 1.7, three runs: check 38.0-38.3 ms,
// speedup 23.3-23.4; draw+warp+bin 151.2-151.6 M samples/s on one thread.
// Issue 27 (2026-11-24): the pbrt-style reference now computes as pbrt-v4's
// bsdfs_test.cpp does (float, libm acosf/atan2f/sinf/cosf, a float cosine
// hemisphere; it was double acos/atan2 and the project's sin_cos, 1.4x slower
// than pbrt's own procedure), so the speedup printed is against pbrt's real cost.
// Issue 27, the speed limit (BM_DrawWarpBinVsLimitLoop), 05:44 UTC, machine
// shared (load 6 on 2 cores), three runs of --benchmark_filter=DrawWarpBin: lane
// path 77-79 M samples/s on one thread, the plain vectorised loop 196-220 M/s:
// times_limit_loop 2.5-2.8 (at load 2.5-2.8 before: 118 against 217-296 M/s, 1.9-2.5).
// Issue 27, one sitting on 2026-11-27, 08:27-08:32 UTC (load 0.6-2.0, nothing else
// running), --benchmark_filter='Vs|PerCore', this build beside the build of main
// when issue 27 was filed (61b7c31), which measured 117.7 M samples/s on the lane
// path here (168.9 when the issue was written: the machine is slower today, so
// compare ratios): lane path 107-110 M/s; the limit loop in one body per lane
// 265 M/s (321 in a run before): times_limit_loop 2.40 (2.74); a plain struct on
// the planar lane path 2.63x the lane form (2.69x in the old build; 2.47x the
// day before), on scalar chunks 5.34x; templated 1.03x; the whole check 11.3x
// the pbrt-style procedure (11.7x in the old build).
// Issue 16's targets: check <= 50 ms and >= 15x the pbrt-style procedure;
// >= 150 M samples/s per core.
#include <algorithm>
#include <cmath>
#include <memory>
#include <span>
#include <vector>

#include <benchmark/benchmark.h>

#include "chi2/chi2_test.h"
#include "support/builtin_case.h"
#include "paired_timing.h"
#include "pbrt_style_chi2.h"
#include "vectorised_limit_loop.h"
#include "sampling/hemisphere.h"
#include "validate/checks/check.h"
#include "validate/checks/checks.h"
#include "validate/lanes/lane_sampling.h"
#include "validate/api/float_template_warp.h"
#include "validate/run/thread_pool.h"
#include "validate/api/warp_case.h"

namespace warpcheck {
namespace {

constexpr uint64_t kSamples = 10'000'000;
constexpr unsigned kThreads = 2;

struct Fixture {
    const WarpCase* warp = &testing::builtin_case("cosine_hemisphere");
    ThreadPool pool;
    RunOptions options;
    explicit Fixture(unsigned threads = kThreads) : pool(threads) {
        options.samples = kSamples;
        options.threads = threads;
    }
    CheckContext context() { return CheckContext(options, pool.executor(), stream_for(warp->name(), options.seed)); }
    chi2::ParallelFor parallel() {
        return [this](std::size_t n, const std::function<void(std::size_t)>& body) { pool.parallel_for(n, body); };
    }
};

void BM_Chi2Check(benchmark::State& state) {
    Fixture f;
    const auto check = make_chi2_check();
    const CheckContext ctx = f.context();
    for (auto _ : state) {
        CheckResult r = check->run(*f.warp, ctx);
        benchmark::DoNotOptimize(r.p_value);
        if (r.verdict != Verdict::Pass) state.SkipWithError(("check did not pass: " + r.message).c_str());
    }
    state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kSamples));
}
BENCHMARK(BM_Chi2Check)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Chi2SampleAndBin(benchmark::State& state) {
    Fixture f;
    const CheckContext ctx = f.context();
    const chi2::Binning binning(f.warp->domain());
    const chi2::SampleChunk generate = chi2_sample_chunks(*f.warp, ctx);
    for (auto _ : state) {
        chi2::Histogram h = chi2::sample_histogram(binning, kSamples, 4096, generate, {}, f.parallel());
        benchmark::DoNotOptimize(h.counts.data());
    }
    state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kSamples));
}
BENCHMARK(BM_Chi2SampleAndBin)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Chi2BinOnly(benchmark::State& state) {
    Fixture f;
    const chi2::Binning binning(f.warp->domain());
    constexpr std::size_t kPoints = 1 << 20;
    std::vector<WarpInput> inputs(kPoints);
    std::vector<chi2::SamplePoint> points(kPoints);
    Pcg32 rng(1, 2);
    draw_inputs(rng, InputKind::Uniform2D, inputs);
    f.warp->sample(inputs, points);
    chi2::Histogram h;
    h.counts.assign(binning.cell_count(), 0);
    for (auto _ : state) {
        binning.bin(std::span<const chi2::SamplePoint>(points), h);
        benchmark::DoNotOptimize(h.counts.data());
    }
    state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kPoints));
}
BENCHMARK(BM_Chi2BinOnly)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Chi2Integration(benchmark::State& state) {
    Fixture f;
    const chi2::Binning binning(f.warp->domain());
    const WarpCase& warp = *f.warp;
    const chi2::BatchPdf pdf = [&](std::span<const chi2::DomainPoint> points, std::span<double> density) {
        std::vector<WarpOutput> x(points.size());
        for (std::size_t i = 0; i < points.size(); ++i)
            x[i] = {static_cast<float>(points[i][0]), static_cast<float>(points[i][1]), static_cast<float>(points[i][2])};
        warp.pdf(x, density);
    };
    chi2::QuadratureOptions q;
    q.sample_count = kSamples;
    for (auto _ : state) {
        chi2::CellIntegrals c = chi2::integrate_cells(binning, pdf, q, f.parallel());
        benchmark::DoNotOptimize(c.total);
        state.counters["evaluations"] = static_cast<double>(c.evaluations);
        state.counters["unconverged"] = static_cast<double>(c.unconverged_cells);
    }
}
BENCHMARK(BM_Chi2Integration)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Chi2CheckVsPbrt(benchmark::State& state) {
    Fixture f;
    const auto check = make_chi2_check();
    const CheckContext ctx = f.context();
    double pbrt_p = 0;
    bench::run_paired(
        state,
        [&] {
            CheckResult r = check->run(*f.warp, ctx);
            if (r.verdict != Verdict::Pass) state.SkipWithError(("check did not pass: " + r.message).c_str());
        },
        [&] {
            Pcg32 rng(7, 1);
            pbrt_p = bench::pbrt_style_chi2(rng, kSamples, bench::float_cosine_hemisphere,
                                            [](float, float, float z) { return z >= 0 ? z / kPi : 0.0f; });
        });
    state.counters["pbrt_style_p"] = pbrt_p;
}
BENCHMARK(BM_Chi2CheckVsPbrt)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(3);

// The plain reference: one PCG32 chain, the warp's scalar form, the cell of
// (phi, cos theta) on the check's default 32 x 32 grid by atan2 and a multiply.
uint64_t fused_scalar_loop(uint64_t samples, std::vector<uint64_t>& counts) {
    Pcg32 rng(3, 1);
    const CosineHemisphere warp;
    constexpr int kRes = 32;
    counts.assign(kRes * kRes, 0);
    uint64_t outside = 0;
    for (uint64_t i = 0; i < samples; ++i) {
        const float u0 = rng.next_float(), u1 = rng.next_float();
        const Vector3f v = warp.sample({u0, u1});
        float phi = std::atan2(v.y, v.x);
        if (phi < 0) phi += 6.2831853f;
        const int col = std::min(static_cast<int>(phi * (kRes / 6.2831853f)), kRes - 1);
        const int row = static_cast<int>(v.z * kRes);
        if (row < 0 || row >= kRes) {
            ++outside;
            continue;
        }
        ++counts[static_cast<std::size_t>(row * kRes + col)];
    }
    return outside;
}

// Draw + warp + bin on one thread, by the path `path` (0: the scalar chunk path
// that other 2D warps take; 1: the lane path the check takes, chosen at run
// time; 2: the lane path's portable build), beside the plain fused loop.
void BM_DrawWarpBinPerCore(benchmark::State& state) {
    Fixture f(1);
    const CheckContext ctx = f.context();
    const chi2::Binning binning(f.warp->domain());
    const chi2::SampleChunk generate = chi2_sample_chunks(*f.warp, ctx);
    const auto chunk_rng = [&](uint64_t chunk) { return ctx.chunk_rng(chunk); };
    const int path = static_cast<int>(state.range(0));
    std::vector<uint64_t> counts;
    bench::run_paired(
        state,
        [&] {
            chi2::Histogram h =
                path == 0 ? chi2::sample_histogram(binning, kSamples, 4096, generate, {}, f.parallel())
                          : lane_histogram(binning, kSamples, 4096, chunk_rng, *f.warp->info().lanes, {}, f.parallel(),
                                           path == 1 ? LanePath::Auto : LanePath::Portable);
            benchmark::DoNotOptimize(h.counts.data());
        },
        [&] { benchmark::DoNotOptimize(fused_scalar_loop(kSamples, counts)); });
    state.counters["subject_Msamples_per_s"] = 1e-3 * kSamples / state.counters["subject_min_ms"];
    state.counters["reference_Msamples_per_s"] = 1e-3 * kSamples / state.counters["reference_min_ms"];
    state.SetLabel(path == 0 ? "scalar chunks" : path == 1 ? std::string("lanes, ") + lane_path_name(LanePath::Auto)
                                                           : "lanes, portable");
}
BENCHMARK(BM_DrawWarpBinPerCore)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(5);

// The built-in lane path (the check's, chosen at run time) against the speed
// limit of a plain vectorised loop (vectorised_limit_loop), both on one thread:
// counter times_limit_loop = lane path / limit loop (best of the rounds; issue
// 27's target: at most 3). The two histograms are of the same grid and the
// same distribution: limit_vs_lanes_max_z is the largest difference of a
// cell's counts in standard deviations (about 4 for independent samples).
void BM_DrawWarpBinVsLimitLoop(benchmark::State& state) {
    Fixture f(1);
    const CheckContext ctx = f.context();
    const chi2::Binning binning(f.warp->domain());
    const auto chunk_rng = [&](uint64_t chunk) { return ctx.chunk_rng(chunk); };
    chi2::Histogram lanes;
    std::vector<uint64_t> limit;
    bench::run_paired(
        state,
        [&] {
            lanes = lane_histogram(binning, kSamples, 4096, chunk_rng, *f.warp->info().lanes, {}, f.parallel());
            benchmark::DoNotOptimize(lanes.counts.data());
        },
        [&] {
            bench::vectorised_limit_loop(kSamples, *binning.lane_plan(), limit);
            benchmark::DoNotOptimize(limit.data());
        });
    double max_z = 0.0;
    for (std::size_t c = 0; c < limit.size(); ++c) {
        const double a = static_cast<double>(lanes.counts[c]), b = static_cast<double>(limit[c]);
        if (a + b > 0) max_z = std::max(max_z, std::abs(a - b) / std::sqrt(a + b));
    }
    if (!(max_z < 6.0)) state.SkipWithError("the limit loop's histogram is not the lane path's distribution");
    state.counters["limit_vs_lanes_max_z"] = max_z;
    state.counters["times_limit_loop"] = 1.0 / state.counters["speedup"];
    state.counters["subject_Msamples_per_s"] = 1e-3 * kSamples / state.counters["subject_min_ms"];
    state.counters["reference_Msamples_per_s"] = 1e-3 * kSamples / state.counters["reference_min_ms"];
    state.SetLabel(std::string("lanes, ") + lane_path_name(LanePath::Auto) + " vs the limit loop");
}
BENCHMARK(BM_DrawWarpBinVsLimitLoop)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(5);

template <typename F>
struct Vec2 {
    F x, y;
};
template <typename F>
struct Vec3 {
    F x, y, z;
};

/// A renderer's cosine hemisphere written once as a template over its float
/// type (validate/api/float_template_warp.h): the concentric map lifted, with
/// the functions of warpcheck::lanes, which take a float or eight.
struct TemplatedCosineHemisphere {
    template <typename F>
    Vec3<F> sample(Vec2<F> u) const {
        const F a = 2.0f * u.x - 1.0f, b = 2.0f * u.y - 1.0f;
        const F size = lanes::abs(a) + lanes::abs(b);
        const F r = lanes::abs(a) > lanes::abs(b) ? a : b;
        const F ratio = (lanes::abs(a) > lanes::abs(b) ? b : a) / (size == 0.0f ? F{} + 1.0f : r);
        const F t = kPiOver4 * ratio;
        const auto sc = lanes::sin_cos(lanes::abs(a) > lanes::abs(b) ? t : kPiOver2 - t);
        const F x = size == 0.0f ? F{} : r * sc.cos, y = size == 0.0f ? F{} : r * sc.sin;
        return {x, y, lanes::safe_sqrt(1.0f - x * x - y * y)};
    }
    float pdf(Vector3f v) const { return CosineHemisphere{}.pdf(v); }
    Point2f invert(Vector3f v) const { return CosineHemisphere{}.invert(v); }
};

// A renderer's own 2D warp against the built-in lane path, on one thread:
// sampling + binning of 10^7 samples of the cosine hemisphere, the subject
// registered by make_warp_case (as through the installed package), no lane
// form; the reference the built-in case's lane form. Counter times_lane_path =
// subject / reference (best of the rounds; issue 27's targets: at most 2.5 for
// a plain warp, 1.3 for a template). Arg 0: a plain struct with sample/pdf on
// the planar lane path the chi-square check takes for it; arg 1: the same on
// the scalar chunk path it took before; arg 2: the warp written as a template
// over its float type, its lane instantiation on the planar lane path.
void BM_PlainWarpVsLanePath(benchmark::State& state) {
    Fixture f(1);
    const CheckContext ctx(f.options, f.pool.executor(), stream_for(f.warp->name(), f.options.seed));
    WarpCaseInfo info = f.warp->info();
    info.lanes = nullptr;
    const int kind = static_cast<int>(state.range(0));
    const auto subject = kind == 2 ? make_warp_case(info, TemplatedCosineHemisphere{})
                                   : make_warp_case(info, CosineHemisphere{});
    const chi2::Binning binning(f.warp->domain());
    const auto chunk_rng = [&](uint64_t chunk) { return ctx.chunk_rng(chunk); };
    const chi2::SampleChunk generate = chi2_sample_chunks(*subject, ctx);
    bench::run_paired(
        state,
        [&] {
            chi2::Histogram h =
                kind != 1 ? lane_histogram(binning, kSamples, 4096, chunk_rng, planar_lane_sampler(*subject), {},
                                           f.parallel())
                          : chi2::sample_histogram(binning, kSamples, 4096, generate, {}, f.parallel());
            benchmark::DoNotOptimize(h.counts.data());
        },
        [&] {
            chi2::Histogram h = lane_histogram(binning, kSamples, 4096, chunk_rng, *f.warp->info().lanes, {}, f.parallel());
            benchmark::DoNotOptimize(h.counts.data());
        });
    state.counters["times_lane_path"] = 1.0 / state.counters["speedup"];
    state.counters["subject_Msamples_per_s"] = 1e-3 * kSamples / state.counters["subject_min_ms"];
    state.counters["reference_Msamples_per_s"] = 1e-3 * kSamples / state.counters["reference_min_ms"];
    state.SetLabel(kind == 0   ? "plain struct, planar lane path"
                   : kind == 1 ? "plain struct, scalar chunks"
                               : "template over the float type, planar lane path");
}
BENCHMARK(BM_PlainWarpVsLanePath)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(5);

}  // namespace
}  // namespace warpcheck

BENCHMARK_MAIN();

// The chi-square check's speed target: one check of a spherical 2D warp (the
// cosine hemisphere) with 10^7 samples, expected-count integration included,
// in under 0.2 s on 2 threads. The parts are measured apart as well:
//   BM_Chi2Check            the whole check as the runner calls it
//   BM_Chi2SampleAndBin     sampling + binning only (items/s = samples/s)
//   BM_Chi2BinOnly          binning only, of pre-drawn samples (items/s = samples/s)
//   BM_Chi2Integration      expected counts only, at the accuracy rule for 10^7 samples
// Run: build-chi2/tests/benchmarks/bench_chi2 --benchmark_min_time=2
#include <span>
#include <vector>

#include <benchmark/benchmark.h>

#include "chi2/chi2_test.h"
#include "support/builtin_case.h"
#include "validate/check.h"
#include "validate/checks/checks.h"
#include "validate/thread_pool.h"
#include "validate/warp_case.h"

namespace warpcheck {
namespace {

constexpr uint64_t kSamples = 10'000'000;
constexpr unsigned kThreads = 2;

struct Fixture {
    const WarpCase* warp = &testing::builtin_case("cosine_hemisphere");
    ThreadPool pool{kThreads};
    RunOptions options;
    Fixture() {
        options.samples = kSamples;
        options.threads = kThreads;
    }
    CheckContext context() { return CheckContext(options, pool, stream_for(warp->name(), options.seed)); }
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
    const chi2::SampleChunk generate = [&](std::size_t chunk, std::span<chi2::SamplePoint> out) {
        std::vector<WarpInput> inputs(out.size());
        Pcg32 rng = ctx.chunk_rng(chunk);
        draw_inputs(rng, f.warp->input_kind(), inputs);
        f.warp->sample(inputs, out);
    };
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

}  // namespace
}  // namespace warpcheck

BENCHMARK_MAIN();

// The array code of the statistics engine, measured apart from sampling and
// quadrature (bench_chi2 measures the whole check):
//   BM_EvaluateChi2     observed, expected and residual arrays, pooling and
//                       Pearson's statistic of a cosine-hemisphere histogram
//                       (the engine's default binning, 10^7 samples)
//   BM_PearsonTest      pooling and Pearson's statistic alone, same cells
//   BM_UnbinnedPower    one uncached search for the drift an unbinned test
//                       (test = 0 KS, 1 Kuiper, 2 Anderson-Darling) detects
//                       with 90% power (1000 bridges x 511 points, bisected 20 times)
// Run: build/test/tests/benchmarks/bench_statistics --benchmark_min_time=2
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "chi2/binning.h"
#include "chi2/chi2_test.h"
#include "chi2/pearson.h"
#include "chi2/power.h"

namespace warpcheck {
namespace {

constexpr uint64_t kSamples = 10'000'000;

/// A histogram of the cosine-hemisphere density with Gaussian noise of the
/// Poisson size, and its cells' exact probabilities: the engine's input after
/// sampling and quadrature.
struct CosineCells {
    chi2::Binning binning{chi2::Domain::hemisphere()};
    chi2::Histogram histogram;
    chi2::CellIntegrals integrals;
    CosineCells() {
        const std::size_t cells = binning.cell_count();
        histogram.counts.resize(cells);
        integrals.probability.resize(cells);
        integrals.error.assign(cells, 0.0);
        std::mt19937_64 rng(7);
        std::normal_distribution<double> noise;
        for (std::size_t c = 0; c < cells; ++c) {
            // Cells span (phi, z = cos theta); the density z / pi integrates to (z1^2 - z0^2) dphi / (2 pi).
            const chi2::ParamRect r = binning.cell_rect(c);
            const double p = (r.v1 * r.v1 - r.v0 * r.v0) * (r.u1 - r.u0) / (2.0 * std::numbers::pi);
            integrals.probability[c] = p;
            integrals.total += p;
            const double e = p * static_cast<double>(kSamples);
            histogram.counts[c] = static_cast<uint64_t>(std::max(0.0, std::round(e + std::sqrt(e) * noise(rng))));
        }
    }
};

void BM_EvaluateChi2(benchmark::State& state) {
    const CosineCells cells;
    for (auto _ : state) {
        chi2::Chi2Outcome o = chi2::evaluate_chi2(cells.binning, cells.histogram, cells.integrals, kSamples, {});
        benchmark::DoNotOptimize(o.residual.data());
        if (!(o.p_value() > 1e-6)) state.SkipWithError("the cosine histogram should pass");
    }
    state.counters["cells"] = static_cast<double>(cells.binning.cell_count());
    state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * cells.binning.cell_count()));
}
BENCHMARK(BM_EvaluateChi2)->Unit(benchmark::kMicrosecond);

void BM_PearsonTest(benchmark::State& state) {
    const CosineCells cells;
    std::vector<double> observed(cells.histogram.counts.begin(), cells.histogram.counts.end());
    std::vector<double> expected(cells.integrals.probability);
    for (double& e : expected) e *= static_cast<double>(kSamples);
    for (auto _ : state) {
        chi2::PearsonResult r = chi2::pearson_test(observed, expected);
        benchmark::DoNotOptimize(r.statistic);
    }
    state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * observed.size()));
}
BENCHMARK(BM_PearsonTest)->Unit(benchmark::kMicrosecond);

void BM_UnbinnedPower(benchmark::State& state) {
    const auto test = static_cast<chi2::UnbinnedTest>(state.range(0));
    // Each iteration (of every repetition) asks for another level, so that the
    // per-level cache never answers.
    static double level = 1e-3;
    chi2::unbinned_tilt_for_power(test, level, kSamples);  // draws the bridges once
    for (auto _ : state) {
        level *= 1.0 + 1e-9;
        benchmark::DoNotOptimize(chi2::unbinned_tilt_for_power(test, level, kSamples));
    }
}
BENCHMARK(BM_UnbinnedPower)
    ->Unit(benchmark::kMillisecond)
    ->ArgName("test")
    ->Arg(static_cast<int>(chi2::UnbinnedTest::KolmogorovSmirnov))
    ->Arg(static_cast<int>(chi2::UnbinnedTest::Kuiper))
    ->Arg(static_cast<int>(chi2::UnbinnedTest::AndersonDarling));

}  // namespace
}  // namespace warpcheck

BENCHMARK_MAIN();

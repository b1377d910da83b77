// One exhaustive 2^32 sweep of u * 2^-32 (the float histogram behind the
// "exhaustive" check). Target: under 0.5 s on two cores, under 1 GiB.
// Run: build/tests/benchmarks/bench_exhaustive [--benchmark_repetitions=5]
// Counters: distinct outputs (83886081 expected), threads, peak RSS in MiB.
//
// Measured (Release, g++ 12, AMD EPYC with AVX-512, 2 cores, machine quiet),
// 2026-11-21: 2 threads 379 ms, 1 thread 756 ms per 2^32 sweep; peak RSS 4 MiB.
// (Under a load average of ~5 from other builds both rows took ~1.15 s.)
#include <benchmark/benchmark.h>

#include <sys/resource.h>

#include <thread>

#include "sampling/unit_float.h"
#include "validate/exhaustive_sweep.h"
#include "validate/thread_pool.h"

namespace {

double peak_rss_mib() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

void BM_ExhaustiveSweepMul32(benchmark::State& state) {
    const auto threads = static_cast<unsigned>(state.range(0));
    warpcheck::ThreadPool pool(threads);
    const warpcheck::ParallelFor parallel_for = [&pool](std::size_t n, const std::function<void(std::size_t)>& body) {
        pool.parallel_for(n, body);
    };
    const auto fn = warpcheck::u32_block_fn([](uint32_t u) { return warpcheck::UnitFloatMul{}.sample(u); });
    uint64_t distinct = 0;
    for (auto _ : state) {
        const warpcheck::SweepSummary s = warpcheck::exhaustive_sweep(fn, uint64_t{1} << 32, 0.0f, 1.0f, parallel_for);
        distinct = s.distinct;
        benchmark::DoNotOptimize(distinct);
    }
    state.counters["distinct"] = static_cast<double>(distinct);
    state.counters["threads"] = threads;
    state.counters["peak_rss_MiB"] = peak_rss_mib();
    state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * (int64_t{1} << 32));
}
BENCHMARK(BM_ExhaustiveSweepMul32)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

}  // namespace

BENCHMARK_MAIN();

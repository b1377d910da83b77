// Benchmarks on a shared, noisy machine: each one runs its subject and a plain
// reference loop doing the same work alternately, round by round, and reports
// the ratio of their best times. Load slows both alike, so the ratio holds
// where absolute figures drift.
#pragma once

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

namespace warpcheck::bench {

inline double seconds_of(auto&& work) {
    const auto start = std::chrono::steady_clock::now();
    work();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

inline double median_of(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

/// Runs subject and reference alternately once per benchmark iteration (use
/// ->Iterations(n)->UseManualTime()); the benchmark's time is the subject's.
/// Counters, in ms: subject_min, subject_median, reference_min,
/// reference_median; speedup = reference_min / subject_min.
template <typename Subject, typename Reference>
void run_paired(benchmark::State& state, Subject&& subject, Reference&& reference) {
    std::vector<double> s, r;
    for (auto _ : state) {
        s.push_back(seconds_of(subject));
        r.push_back(seconds_of(reference));
        state.SetIterationTime(s.back());
    }
    if (s.empty()) return;
    state.counters["subject_min_ms"] = 1e3 * *std::min_element(s.begin(), s.end());
    state.counters["subject_median_ms"] = 1e3 * median_of(s);
    state.counters["reference_min_ms"] = 1e3 * *std::min_element(r.begin(), r.end());
    state.counters["reference_median_ms"] = 1e3 * median_of(r);
    state.counters["speedup"] = *std::min_element(r.begin(), r.end()) / *std::min_element(s.begin(), s.end());
}

}  // namespace warpcheck::bench

// A check: one kind of evidence (round trip, chi-square, ...) that runs on one
// warp case and returns a result. Checks never print.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>

#include "sampling/hash.h"
#include "sampling/pcg32.h"
#include "reports/result.h"
#include "validate/api/thread_pool.h"
#include "validate/api/warp_case.h"

namespace warpcheck {

/// Settings of a run that checks may read.
struct RunOptions {
    uint64_t seed = 1;
    uint64_t samples = 1'000'000;  ///< samples per statistical check
    unsigned threads = 0;          ///< 0: all hardware threads
    double alpha = 0.01;           ///< family-wise significance level (Šidák-corrected per test)
    bool exhaustive = false;       ///< run the heavy optional sweeps too
    bool include_flawed = false;   ///< also run the cases marked as known flaws (they are expected to fail)
    /// --strict: the allowances for float resolution that correct float code
    /// needs (the pdf's own float rounding in the normalisation, an inverse
    /// that returns exactly 1 for u within a float of 1, ...) are not granted:
    /// each such result fails instead of passing with its count and size.
    bool strict = false;
    /// CPU seconds one check may use before it is reported as an error and its
    /// worker process killed (a sampler that never terminates must not hang the
    /// run); in an in-process run, wall seconds after which it is asked to stop.
    double check_time_budget = 60.0;
    /// Whether the user set check_time_budget (--time-budget): then it binds
    /// every check; otherwise heavy sweeps may take their own larger default
    /// (Check::time_budget).
    bool time_budget_set = false;
    /// --max-float-bias R: the exhaustive check fails when a float's count is
    /// off its ideal by more than a factor R beyond one input of rounding slack
    /// (exhaustive_check.cpp defines the factor). 0: bias is only reported.
    double max_float_bias = 0.0;
    /// How many statistical tests the Šidák correction covers: those of the
    /// whole run when only part of it runs here (a shard, one gtest test);
    /// unset, those among the jobs run.
    std::optional<int> family_tests;
    /// The command that reruns a case, as it was invoked (argv[0]): a program
    /// built on warpcheck::main reruns itself, not `validate`.
    std::string program = "validate";
};

/// Thrown inside a check that the runner has cancelled.
struct CheckCancelled : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// What a check gets to run with.
class CheckContext {
public:
    CheckContext(const RunOptions& options, ThreadPool& pool, StreamId stream,
                 const std::atomic<bool>* cancelled = nullptr)
        : options_(options), pool_(pool), stream_(stream), cancelled_(cancelled) {}

    const RunOptions& options() const { return options_; }
    StreamId stream() const { return stream_; }

    /// The (case, check) stream itself.
    Pcg32 rng() const { return Pcg32(stream_.sequence, stream_.seed); }
    /// The random numbers of chunk `chunk` of this check's work: the same chunk
    /// gets the same numbers whichever thread runs it. Every chunk uses the
    /// check's own PCG32 sequence, started at an offset hashed from the chunk
    /// index. (Separate PCG32 sequences with a common seed, which this used
    /// before, are not independent enough: runs of correct warps then failed
    /// chi-square tests about 1.7 times as often as the significance level says.)
    Pcg32 chunk_rng(uint64_t chunk) const {
        return Pcg32(stream_.sequence, hash_combine(stream_.seed, chunk + 1));
    }

    /// body(i) for i in [0, n) across the pool; see thread_pool.h for the rule
    /// that keeps the result independent of the thread count.
    void parallel_for(std::size_t n, const std::function<void(std::size_t)>& body) const {
        pool_.parallel_for(n, body);
    }
    /// The same loop as a chi2::ParallelFor, to hand to chi2 and the sweeps.
    chi2::ParallelFor executor() const { return pool_.executor(); }

    /// Whether the runner has given up on this check (its time budget ran out).
    bool cancelled() const { return cancelled_ && cancelled_->load(std::memory_order_relaxed); }
    /// Long loops call this between chunks, so a check over its budget stops
    /// working soon after the runner has reported it.
    void throw_if_cancelled() const {
        if (cancelled()) throw CheckCancelled("cancelled: over the time budget");
    }

private:
    const RunOptions& options_;
    ThreadPool& pool_;
    StreamId stream_;
    const std::atomic<bool>* cancelled_;
};

/// w * 2^-64 rounded down to a float: a uniform float of [0, 1) in which every
/// float of [2^-40, 1) has its true probability (its spacing).
float uniform_float_from_bits(uint64_t w);

/// Fills `out` with fresh inputs of the given kind from `rng`: uniform floats at
/// 64-bit resolution (uniform_float_from_bits), or raw bits.
void draw_inputs(Pcg32& rng, InputKind kind, std::span<WarpInput> out);

/// The coordinates of a warp output as a domain point (float -> double).
inline chi2::DomainPoint to_domain_point(const WarpOutput& o) {
    return {static_cast<double>(o[0]), static_cast<double>(o[1]), static_cast<double>(o[2])};
}

/// A domain point (a quadrature node) as a warp output (double -> float).
inline WarpOutput to_warp_output(const chi2::DomainPoint& p) {
    return {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])};
}

class Check {
public:
    virtual ~Check() = default;
    /// Short stable name, used in the table and in --check: "roundtrip".
    virtual std::string name() const = 0;
    /// One line for --list.
    virtual std::string description() const = 0;
    virtual bool applies_to(const WarpCase& warp) const = 0;
    /// Where applies_to is false because the case lacks a part this check tests
    /// (a warp without an inverse has no round trip), why, in a few words: the
    /// run then shows an n/a row with it instead of leaving the check out
    /// silently. Empty (the default): the check is simply not about such cases
    /// (an exhaustive sweep of a 2D warp) and no row is shown.
    virtual std::string not_applicable_because(const WarpCase& warp) const {
        (void)warp;
        return {};
    }
    /// Whether the check runs by default; heavy sweeps run only with --exhaustive.
    virtual bool runs_by_default(const RunOptions& options) const {
        (void)options;
        return true;
    }
    /// Whether the result is the same for every seed (it enumerates instead of
    /// drawing random inputs): such checks cannot give a false positive by chance.
    virtual bool uses_seed() const { return true; }
    /// Whether the check is a statistical test, whose results carry a p-value
    /// that the runner judges at the Šidák-corrected level. The family is the
    /// number of such jobs in the run, fixed before any result is known, so
    /// that a shard of the run, or one job of it, is judged at the level of
    /// the whole run (a job that errors, or finds nothing to test, still counts).
    virtual bool statistical() const { return false; }
    /// Whether the check is about BSDFs and phase functions (validate/bsdf/):
    /// the runner gives BSDF cases only to such checks, and every other case
    /// only to the others.
    virtual bool about_bsdfs() const { return false; }
    /// Seconds this check may take before the runner reports it as an error:
    /// the run's budget, unless the check knows it needs more for a correct
    /// warp (a full 2^32 sweep) and the user did not set --time-budget.
    virtual double time_budget(const RunOptions& options) const { return options.check_time_budget; }
    /// Work the check would repeat in every job of a run and can do once for
    /// all of them (a table of simulated power at the run's levels, say): the
    /// runner calls it before the jobs start, in the process whose workers
    /// inherit what it computed. It runs no warp, and a job that finds the work
    /// not done does it itself, with the same result: results never depend on it.
    virtual void prepare(const RunOptions& options) const { (void)options; }
    /// Runs the check. The runner fills in the names, stream, timing and rerun
    /// command, and turns an exception into an Error verdict.
    virtual CheckResult run(const WarpCase& warp, const CheckContext& ctx) const = 0;
};

}  // namespace warpcheck

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
#include <utility>

#include "chi2/parallel.h"
#include "sampling/hash.h"
#include "sampling/pcg32.h"
#include "reports/result.h"
#include "validate/api/warp_case.h"
#include "validate/checks/judged.h"

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

/// The time budget of a check that makes `calls` sampler calls: the run's
/// budget if the user set it, otherwise at least calls * 100 ns. 100 ns is a
/// stated worst per-call cost: the slowest measured full sweep, the generic
/// batch path over 2^32 inputs of a non-monotone sampler with its exact
/// recount, took 121 s on two cores (28 ns per call); 100 ns leaves a factor
/// 3.5 for slower or busier machines (2^32 calls: 430 s).
inline double sweep_time_budget(const RunOptions& options, uint64_t calls) {
    constexpr double kWorstSecondsPerCall = 100e-9;
    if (options.time_budget_set) return options.check_time_budget;
    const double needed = static_cast<double>(calls) * kWorstSecondsPerCall;
    return options.check_time_budget > needed ? options.check_time_budget : needed;
}


/// Thrown inside a check that the runner has cancelled.
struct CheckCancelled : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// What a check gets to run with.
class CheckContext {
public:
    /// `parallel` runs the check's loops: the runner's thread pool
    /// (validate/run/thread_pool.h, ThreadPool::executor).
    CheckContext(const RunOptions& options, chi2::ParallelFor parallel, StreamId stream,
                 const std::atomic<bool>* cancelled = nullptr)
        : options_(options), parallel_(std::move(parallel)), stream_(stream), cancelled_(cancelled) {}

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

    /// body(i) for i in [0, n) across the pool; see validate/run/thread_pool.h
    /// for the rule that keeps the result independent of the thread count.
    void parallel_for(std::size_t n, const std::function<void(std::size_t)>& body) const { parallel_(n, body); }
    /// The same loop as a chi2::ParallelFor, to hand to chi2 and the sweeps.
    chi2::ParallelFor executor() const { return parallel_; }

    /// Whether the runner has given up on this check (its time budget ran out).
    bool cancelled() const { return cancelled_ && cancelled_->load(std::memory_order_relaxed); }
    /// Long loops call this between chunks, so a check over its budget stops
    /// working soon after the runner has reported it.
    void throw_if_cancelled() const {
        if (cancelled()) throw CheckCancelled("cancelled: over the time budget");
    }

private:
    const RunOptions& options_;
    chi2::ParallelFor parallel_;
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

/// A check's one decision on a case: it runs; or it is not about such cases
/// (an exhaustive sweep of a 2D warp: no row is shown); or the case lacks the
/// part the check tests (a warp without an inverse has no round trip: the run
/// shows an n/a row saying why, instead of leaving the check out silently).
class Applicability {
public:
    static Applicability runs() { return Applicability(true, {}); }
    static Applicability not_about_such_cases() { return Applicability(false, {}); }
    /// Not applicable because the case lacks a part: `why`, in a few words.
    static Applicability lacks(std::string why) { return Applicability(false, std::move(why)); }
    /// runs() where `about`, otherwise not_about_such_cases().
    static Applicability when(bool about) { return about ? runs() : not_about_such_cases(); }

    bool applies() const { return applies_; }
    /// Why the case gets an n/a row; empty where the check applies or is not about such cases.
    const std::string& not_applicable_because() const { return why_; }

private:
    Applicability(bool applies, std::string why) : applies_(applies), why_(std::move(why)) {}
    bool applies_;
    std::string why_;
};

class Check {
public:
    virtual ~Check() = default;
    /// Short stable name, used in the table and in --check: "roundtrip".
    virtual std::string name() const = 0;
    /// One line for --list.
    virtual std::string description() const = 0;
    /// What the check judges and how its p-value is formed, for the legend of
    /// every report (carried with the run: RunInfo::legends). The default is
    /// the description, without a p-value rule.
    virtual CheckLegend legend() const { return {name(), description(), ""}; }
    /// Whether the check runs on the case, and where it does not, whether the
    /// case lacks what the check tests (Applicability): stated once, here.
    virtual Applicability applicability(const WarpCase& warp) const = 0;
    bool applies_to(const WarpCase& warp) const { return applicability(warp).applies(); }
    std::string not_applicable_because(const WarpCase& warp) const {
        return applicability(warp).not_applicable_because();
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
    /// Whether the check is about BSDFs and phase functions (validate/checks/bsdf/):
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
    /// What the check judges, written into each of its rows (CheckResult::
    /// judged) once the run's level is settled (validate/checks/judged.h).
    /// The default: the p-value's line, and the generic tolerance lines.
    virtual JudgedRules judged_rules() const { return {}; }
};

/// The row of a check that compared nothing because the case's sampler
/// declined every input (a light not visible from its reference point: a
/// planar light seen edge-on within float rounding): n/a, saying so, never a
/// pass that tested nothing.
inline CheckResult nothing_sampled(uint64_t inputs) {
    CheckResult r;
    r.verdict = Verdict::NotApplicable;
    r.summary = "not applicable: every input declined (nothing visible to sample)";
    r.message = "the sampler declined all " + std::to_string(inputs) +
                " inputs (a light not visible from its reference point): there was nothing to compare";
    r.figures = {{"declined", static_cast<double>(inputs)}};
    return r;
}

}  // namespace warpcheck

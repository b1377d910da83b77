// What the known-bad catalogues' tests share (BSDFs, lights): a run of the
// whole catalogue judged as `validate --include-flawed` judges it, and the
// rule each entry is held to: its check fails, so do only the checks its bug
// rightly moves, and every other check passes or does not apply.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "validate/api/registry.h"
#include "validate/run/runner.h"

namespace warpcheck::testing {

/// The selected cases under the selected checks (all where empty), flawed
/// ones included, on 2 threads, with a budget no correct case reaches.
inline RunResult run_including_flawed(const Registry& registry, const std::vector<std::string>& cases,
                                      const std::vector<std::string>& checks, uint64_t seed, uint64_t samples) {
    RunOptions options;
    options.seed = seed;
    options.samples = samples;
    options.threads = 2;
    options.include_flawed = true;
    options.check_time_budget = 600.0;
    return run_jobs(select_jobs(registry, cases, checks, options), options);
}

/// The rows that neither passed nor were not applicable, one a line.
inline std::string failures_of(const RunResult& r) {
    std::string out;
    for (const CheckResult& c : r.results)
        if (c.verdict != Verdict::Pass && c.verdict != Verdict::NotApplicable)
            out += fmt::format("\n  {} {}: {} {}", c.check_name, c.case_name, c.summary, c.message);
    return out;
}

/// Holds each entry of `catalogue`, registered in its order as the only
/// cases of `registry`, to its rule in the run `r`.
/// A row's verdict agrees with the judgement its check wrote (CheckResult::
/// judged): a pass has no line beyond its limit, a failure at least one (the
/// rule that failed it). Errors and n/a rows judged nothing.
inline void expect_verdict_agrees_with_its_lines(const CheckResult& c) {
    if (c.verdict != Verdict::Pass && c.verdict != Verdict::Fail) return;
    std::string beyond;
    for (const JudgedQuantity& j : c.judged)
        if (j.state == JudgedQuantity::State::Beyond) beyond += " [" + j.quantity + " " + j.value + " " + j.limit + "]";
    if (c.verdict == Verdict::Pass)
        EXPECT_EQ(beyond, "") << c.check_name << " " << c.case_name << " passed with lines beyond their limits";
    else
        EXPECT_NE(beyond, "") << c.check_name << " " << c.case_name << " failed with no line beyond its limit: "
                              << c.message;
}

inline void expect_each_caught(const Registry& registry, const std::vector<FlawedBsdf>& catalogue,
                               const RunResult& r) {
    ASSERT_EQ(registry.cases().size(), catalogue.size());
    for (std::size_t i = 0; i < catalogue.size(); ++i) {
        const FlawedBsdf& flawed = catalogue[i];
        const std::string name = registry.cases()[i]->name();
        EXPECT_NE(registry.known_flaw(*registry.cases()[i]), "") << name;
        bool caught = false;
        for (const CheckResult& c : r.results) {
            if (c.case_name != name) continue;
            const bool expected_failure =
                c.check_name == flawed.caught_by ||
                std::find(flawed.also_fails.begin(), flawed.also_fails.end(), c.check_name) != flawed.also_fails.end();
            if (c.check_name == flawed.caught_by) caught = c.verdict == Verdict::Fail;
            if (!expected_failure)
                EXPECT_TRUE(c.verdict == Verdict::Pass || c.verdict == Verdict::NotApplicable)
                    << name << ": " << c.check_name << " should not fail: " << c.summary << " " << c.message;
            else
                EXPECT_EQ(c.verdict, Verdict::Fail) << name << ": " << c.check_name << " " << c.summary;
        }
        EXPECT_TRUE(caught) << name << " (" << flawed.flaw << ") not caught by " << flawed.caught_by;
    }
    for (const CheckResult& c : r.results) expect_verdict_agrees_with_its_lines(c);
}

}  // namespace warpcheck::testing

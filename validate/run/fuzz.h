// --fuzz: each family's parameters drawn from the ranges its axes declare
// (validate/api/registry.h), their ends first (roughness to its smallest,
// g toward +-1, eta toward 1, wo toward grazing from both sides), the cheap
// checks run on every point, and each failure shrunk to the simplest point of
// the family that still fails the same check, printed as a rerun line.
//
// The rule of a finding is the check's own, at the run's Šidák level over
// every statistical job of the fuzz run (the points are many tests, and a
// correct family must come out clean); shrinking keeps that level, so a
// shrunk point fails as significantly as the one found. A point the family's
// maker refuses inside a declared range is a finding too: the range is the
// family's claim about where it works.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "reports/result.h"
#include "validate/api/registry.h"
#include "validate/checks/check.h"
#include "validate/run/worker.h"

namespace warpcheck {

/// The checks --fuzz runs by default: each is cheap at any parameter (no
/// quadrature) and says what the issue of extreme parameters is about: finite
/// samples with positive pdfs, weights that agree with f and pdf, delta
/// lobes' shares and directions, energy at most 1, a returned pdf that is pdf().
std::vector<std::string> default_fuzz_checks();

struct FuzzOptions {
    /// Families whose name matches one of these (name_matches); empty: every family with a declared range.
    std::vector<std::string> families;
    /// Checks by name; empty: default_fuzz_checks().
    std::vector<std::string> checks;
    /// Points drawn at random per family, besides each range's ends (and their corners).
    unsigned random_points = 24;
    /// At most this many reruns per finding while shrinking.
    unsigned max_shrink_runs = 80;
    RunOptions run;  ///< seed, samples per check (the CLI's --fuzz default is 20,000), threads, alpha, budget
    Isolation isolation;
};

/// One failure: the first failing point of a family for a check, and the
/// simplest point of the family that fails it too.
struct FuzzFinding {
    std::string family, check;
    std::string found_case;   ///< the first point found failing
    std::string shrunk_case;  ///< the simplest failing point (found_case if nothing simpler fails)
    Verdict verdict = Verdict::Fail;  ///< of the shrunk point: Fail, or Error (a throw, a crash, a hang)
    std::string summary, message;     ///< of the shrunk point's row
    std::size_t failing_points = 0;   ///< points of the family failing this check in the fuzz run
    std::string rerun;                ///< the command that reruns the shrunk point's check
};

struct FuzzReport {
    std::size_t families = 0, points = 0, jobs = 0, shrink_runs = 0;
    int statistical_tests = 0;
    double per_test_level = 0.0;
    std::vector<FuzzFinding> findings;
    /// Points inside a declared range that the family's maker refused, with its reason: each is a finding.
    std::vector<std::string> refusals;
    /// Every row of the fuzz run (each point's checks, at the run's level),
    /// each rerun line a --fuzz-case line: what --json, --report and --junit write.
    RunResult run;
    double seconds = 0.0;
    bool clean() const { return findings.empty() && refusals.empty(); }
};

/// The fuzz run over `registry`'s families and checks.
FuzzReport run_fuzz(const Registry& registry, const FuzzOptions& options);

/// The points --fuzz draws for a family (each a full parameter list in axis
/// order), deduplicated, in a fixed order: a function of the family and the seed.
std::vector<std::vector<Parameter>> fuzz_points(const CaseFamily& family, unsigned random_points, uint64_t seed);

/// A family's case at `params` (in the family's axis order, named as a grid
/// names it); nullptr and the maker's reason in `refusal` where it refuses.
std::unique_ptr<WarpCase> make_family_case(const CaseFamily& family, const std::vector<Parameter>& params,
                                           std::string& refusal);

/// The case a name such as rough_conductor[alpha=0.0001,theta_o=89.99] names,
/// made by its registered family at those parameters (the rerun of a fuzz
/// finding); nullptr and the reason in `problem` where there is no such
/// family, a parameter is missing, unknown or not a number, or the maker refuses.
std::unique_ptr<WarpCase> make_case_from_name(const Registry& registry, const std::string& name, std::string& problem);

/// A row's rerun line (rerun_command's --filter 'case') as the --fuzz-case
/// line that makes its case from the family again: for a case no grid registered.
std::string fuzz_case_rerun(std::string rerun);

/// The report as text: the findings with their rerun lines, then a summary line.
std::string fuzz_report_text(const FuzzReport& report);

}  // namespace warpcheck

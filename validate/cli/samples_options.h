// The options of `validate` that judge samples from elsewhere (another build,
// a GPU kernel, another language): record the inputs the checks ask and replay
// another program's outputs for them, judge independent draws against a
// case's pdf, and compare two implementations, for the same inputs (ulps) or
// for independent draws (two-sample tests). validate/samples/README.md says how.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "reports/result.h"
#include "validate/api/registry.h"
#include "validate/checks/check.h"

namespace CLI {
class App;
}

namespace warpcheck {

struct SamplesOptions {
    std::string record_inputs, record_outputs;  ///< --record-inputs, --record-outputs
    std::vector<std::string> replay;            ///< --replay INPUTS OUTPUTS
    std::string judge_samples;                  ///< --judge-samples FILE
    std::vector<std::string> compare;           ///< --compare A B (the same inputs)
    std::vector<std::string> two_sample;        ///< --two-sample A B (independent draws)
    std::string compare_inputs;                 ///< --inputs FILE (the inputs of --compare's rows)
    uint64_t max_ulps = 0;                      ///< --max-ulps K
    float ulp_floor = 0.0f;                     ///< --ulp-floor S
    std::string raw_layout;                     ///< --raw-layout 3[,planar]
    bool isolation = true;                      ///< from --no-isolation (set by the caller)

    /// Whether any of these options was given (a mode, or an option that goes with one).
    bool any() const {
        return !record_inputs.empty() || !record_outputs.empty() || !replay.empty() || !judge_samples.empty() ||
               !compare.empty() || !two_sample.empty() || !compare_inputs.empty() || max_ulps > 0 ||
               ulp_floor > 0.0f || !raw_layout.empty();
    }
};

/// Adds the options to the command line.
void add_samples_options(CLI::App& app, SamplesOptions& o);

/// What was asked, run: the run to present, or nullopt after a usage error
/// written to `err` (prefixed with `program`). `filters` and `checks` are the
/// selection's --filter and --check.
std::optional<RunResult> run_samples_mode(const SamplesOptions& o, const Registry& registry,
                                          const std::vector<std::string>& filters,
                                          const std::vector<std::string>& checks, const RunOptions& options,
                                          const std::string& command, const std::string& program, std::ostream& err);

}  // namespace warpcheck

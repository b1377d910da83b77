#include "validate/cli/samples_options.h"

#include <filesystem>
#include <ostream>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "reports/outputs.h"
#include "validate/api/bsdf_case.h"
#include "validate/run/run_digest.h"
#include "validate/run/runner.h"
#include "validate/samples/replay_run.h"
#include "validate/samples/sample_arrays.h"
#include "validate/samples/sample_file.h"
#include "validate/samples/sample_set.h"
#include "validate/samples/two_sample_comparison.h"
#include "validate/samples/ulp_comparison.h"
#include "warpcheck/version.h"

namespace warpcheck {

void add_samples_options(CLI::App& app, SamplesOptions& o) {
    app.add_option("--record-inputs", o.record_inputs,
                   "With one case selected: run its checks and write every input they asked of sample to FILE "
                   "(.npy), for another build or device to warp (see --replay)")
        ->type_name("FILE");
    app.add_option("--record-outputs", o.record_outputs,
                   "With --record-inputs: also write the case's own outputs for those inputs to FILE (.npy)")
        ->type_name("FILE");
    app.add_option("--replay", o.replay,
                   "INPUTS OUTPUTS, with one case selected: run its checks with sample answered from another "
                   "program's OUTPUTS, row for row those of the recorded INPUTS")
        ->type_name("FILE")
        ->expected(2);
    app.add_option("--judge-samples", o.judge_samples,
                   "With one case selected: judge independent samples (FILE, one per row) against its pdf: "
                   "samples_consistency and samples_chi2")
        ->type_name("FILE");
    app.add_option("--compare", o.compare,
                   "A B: compare two implementations' outputs for the same inputs, row for row, in ulps (--max-ulps); "
                   "a selected case gives the dimension")
        ->type_name("FILE")
        ->expected(2);
    app.add_option("--inputs", o.compare_inputs, "With --compare: the inputs both were given, shown with the worst rows")
        ->type_name("FILE");
    app.add_option("--max-ulps", o.max_ulps,
                   "With --compare: the largest distance in ulps that counts as agreement (default 0: bit for bit)")
        ->type_name("K");
    app.add_option("--ulp-floor", o.ulp_floor,
                   "With --compare: count values smaller than S in ulps of S (e.g. 1 for directions: near 0 a "
                   "coordinate's rounding is absolute); default 0, the float grid itself")
        ->type_name("S")
        ->check(CLI::Range(0.0f, 1e30f).description(""));
    app.add_option("--two-sample", o.two_sample,
                   "A B: test whether two sets of independent samples come from one distribution (chi-square "
                   "homogeneity and Anderson-Darling); a selected case gives the domain")
        ->type_name("FILE")
        ->expected(2);
    app.add_option("--raw-layout", o.raw_layout,
                   "How a sample file that is not .npy holds its float32: N floats per sample (1-3), interleaved "
                   "(default) or planar, e.g. 3 or 3,planar")
        ->type_name("N[,planar]");
}

namespace {

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// The one case the selection names: --filter must select exactly one.
const WarpCase* selected_case(const Registry& registry, const std::vector<std::string>& filters, bool required,
                              const char* option) {
    std::vector<const WarpCase*> found;
    for (const auto& c : registry.cases()) {
        bool match = false;
        for (const std::string& pattern : filters)
            match = match || (registry.find_case(pattern) ? c->name() == pattern : name_matches(c->name(), pattern));
        if (match) found.push_back(c.get());
    }
    if (found.size() == 1) return found.front();
    if (found.empty() && !required) return nullptr;
    throw UsageError(found.empty() ? fmt::format("{} needs one case: select it with --filter NAME", option)
                                   : fmt::format("{} needs one case, and --filter selects {} (the first two: {}, {})",
                                                 option, found.size(), found[0]->name(), found[1]->name()));
}

struct Files {
    std::optional<RawLayout> layout;
    NumericArray read(const std::string& path) const { return read_sample_file(path, layout ? &*layout : nullptr); }
};

std::string quoted(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

std::string label_of(const std::string& path) { return std::filesystem::path(path).filename().string(); }

/// Inputs of the kind a case takes, or (without a case) the kind the array's type and shape say.
InputKind input_kind_of(const NumericArray& a, const WarpCase* warp) {
    if (warp) return warp->input_kind();
    if (a.type == ElementType::UInt32) return InputKind::Bits32;
    if (a.type == ElementType::UInt64) return InputKind::Bits64;
    return a.cols == 3 ? InputKind::Uniform3D : a.cols == 2 ? InputKind::Uniform2D : InputKind::Uniform1D;
}

std::vector<Job> case_jobs(const Registry& registry, const WarpCase& warp, const std::vector<std::string>& checks,
                           const RunOptions& options) {
    RunOptions with_flawed = options;
    with_flawed.include_flawed = true;  // the case is named: it runs, as --filter with its full name runs it
    return select_jobs(registry, {warp.name()}, checks, with_flawed);
}

RunResult record(const SamplesOptions& o, const Registry& registry, const WarpCase& warp,
                 const std::vector<std::string>& checks, const RunOptions& options) {
    Recording r = record_run(warp, case_jobs(registry, warp, checks, options), options);
    write_npy(o.record_inputs, array_of(r.samples.inputs, warp.input_kind()));
    if (!o.record_outputs.empty()) {
        NumericArray outputs = array_of(r.samples.outputs, warp.signature().output_dimension);
        if (r.samples.values) {  // the value sample returned, as the last column
            NumericArray with_values = outputs;
            with_values.cols += 1;
            with_values.one_dimensional = false;
            with_values.reals.clear();
            for (std::size_t i = 0; i < outputs.rows; ++i) {
                for (std::size_t c = 0; c < outputs.cols; ++c) with_values.reals.push_back(outputs.real(i, c));
                with_values.reals.push_back((*r.samples.values)[i]);
            }
            outputs = std::move(with_values);
        }
        write_npy(o.record_outputs, outputs);
    }
    return std::move(r.run);
}

RunResult replay(const SamplesOptions& o, const Files& files, const Registry& registry, const WarpCase& warp,
                 const std::vector<std::string>& checks, const RunOptions& options) {
    const NumericArray inputs = files.read(o.replay[0]), outputs = files.read(o.replay[1]);
    RecordedSamples table;
    table.inputs = inputs_of(inputs, warp.input_kind(), o.replay[0]);
    const int dims = std::max(1, warp.signature().output_dimension);
    const bool with_value = returns_value(warp) && outputs.cols == static_cast<std::size_t>(dims) + 1;
    if (with_value) table.values.emplace();
    table.outputs = outputs_of(outputs, dims, o.replay[1], with_value ? &*table.values : nullptr);
    if (table.outputs.size() != table.inputs.size())
        throw SampleFileError(fmt::format("--replay: {} has {} inputs but {} has {} outputs: one output per input, row "
                                          "for row",
                                          o.replay[0], table.inputs.size(), o.replay[1], table.outputs.size()));
    Isolation isolation;
    isolation.enabled = o.isolation;
    return replay_run(warp, std::move(table), case_jobs(registry, warp, checks, options), options, isolation);
}

CheckResult compare(const SamplesOptions& o, const Files& files, const WarpCase* warp) {
    const NumericArray a = files.read(o.compare[0]), b = files.read(o.compare[1]);
    UlpComparison how;
    how.max_ulps = o.max_ulps;
    how.floor = o.ulp_floor;
    how.dimension = warp ? std::max(1, warp->signature().output_dimension) : static_cast<int>(a.cols);
    how.label_a = label_of(o.compare[0]);
    how.label_b = label_of(o.compare[1]);
    std::vector<WarpInput> inputs;
    if (!o.compare_inputs.empty()) {
        const NumericArray u = files.read(o.compare_inputs);
        how.input_kind = input_kind_of(u, warp);
        inputs = inputs_of(u, how.input_kind, o.compare_inputs);
        how.inputs = inputs;
    }
    const auto xa = outputs_of(a, how.dimension, o.compare[0]), xb = outputs_of(b, how.dimension, o.compare[1]);
    CheckResult r = compare_same_inputs(xa, xb, how);
    r.case_name = warp ? warp->name() : how.label_a + " vs " + how.label_b;
    return r;
}

CheckResult two_sample(const SamplesOptions& o, const Files& files, const WarpCase* warp, const RunOptions& options) {
    const NumericArray a = files.read(o.two_sample[0]), b = files.read(o.two_sample[1]);
    TwoSampleComparison how;
    if (warp) how.domain = warp->domain();
    how.dimension = warp ? std::max(1, warp->signature().output_dimension) : static_cast<int>(a.cols);
    how.label_a = label_of(o.two_sample[0]);
    how.label_b = label_of(o.two_sample[1]);
    const auto xa = outputs_of(a, how.dimension, o.two_sample[0]), xb = outputs_of(b, how.dimension, o.two_sample[1]);
    CheckResult r = compare_independent(xa, xb, how, options);
    r.case_name = warp ? warp->name() : how.label_a + " vs " + how.label_b;
    return r;
}

/// The problem with combining the modes, or empty.
std::string combination_problem(const SamplesOptions& o) {
    const int modes = !o.record_inputs.empty() + !o.replay.empty() + !o.judge_samples.empty() +
                      (!o.compare.empty() || !o.two_sample.empty());
    if (modes > 1)
        return "--record-inputs, --replay, --judge-samples and --compare/--two-sample are separate runs: give one";
    if (modes == 0) return "--record-outputs, --inputs, --max-ulps, --ulp-floor and --raw-layout go with a run of samples "
                           "from elsewhere: --record-inputs, --replay, --judge-samples, --compare or --two-sample";
    if (!o.record_outputs.empty() && o.record_inputs.empty()) return "--record-outputs goes with --record-inputs";
    if ((!o.compare_inputs.empty() || o.max_ulps > 0 || o.ulp_floor > 0) && o.compare.empty())
        return "--inputs, --max-ulps and --ulp-floor go with --compare";
    return {};
}

RunResult run_mode(const SamplesOptions& o, const Registry& registry, const std::vector<std::string>& filters,
                   const std::vector<std::string>& checks, const RunOptions& options, const std::string& command) {
    Files files;
    if (!o.raw_layout.empty()) files.layout = parse_raw_layout(o.raw_layout);
    const bool one_case = !o.record_inputs.empty() || !o.replay.empty() || !o.judge_samples.empty();
    const char* option = !o.record_inputs.empty() ? "--record-inputs"
                         : !o.replay.empty()      ? "--replay"
                         : !o.judge_samples.empty() ? "--judge-samples"
                                                    : "--compare";
    const WarpCase* warp = filters.empty() && !one_case ? nullptr : selected_case(registry, filters, one_case, option);
    if (warp && as_bsdf(*warp) && (one_case || !o.compare.empty()))
        throw UsageError(fmt::format("{} takes warp cases; {} is a BSDF", option, warp->name()));
    RunResult run;
    if (!o.record_inputs.empty()) run = record(o, registry, *warp, checks, options);
    else if (!o.replay.empty()) {
        run = replay(o, files, registry, *warp, checks, options);
        for (CheckResult& r : run.results)
            r.rerun_command += fmt::format(" --replay {} {}", quoted(o.replay[0]), quoted(o.replay[1]));
    }
    else {
        std::vector<CheckResult> rows;
        if (!o.judge_samples.empty()) {
            const NumericArray x = files.read(o.judge_samples);
            const auto samples = outputs_of(x, std::max(1, warp->signature().output_dimension), o.judge_samples);
            rows = judge_sample_set(*warp, samples, options);
        }
        if (!o.compare.empty()) rows.push_back(compare(o, files, warp));
        if (!o.two_sample.empty()) rows.push_back(two_sample(o, files, warp, options));
        return run_of_rows(std::move(rows), options, command);
    }
    run.info.command_line = command;
    run.info.tool_version = WARPCHECK_VERSION;
    std::vector<JobName> names;
    for (const CheckResult& r : run.results) names.push_back({r.case_name, r.check_name});
    seal_run(run, names);
    return run;
}

}  // namespace

std::optional<RunResult> run_samples_mode(const SamplesOptions& o, const Registry& registry,
                                          const std::vector<std::string>& filters,
                                          const std::vector<std::string>& checks, const RunOptions& options,
                                          const std::string& command, const std::string& program, std::ostream& err) {
    if (const std::string problem = combination_problem(o); !problem.empty()) {
        err << program << ": " << problem << "\n";
        return std::nullopt;
    }
    try {
        return run_mode(o, registry, filters, checks, options, command);
    } catch (const UsageError& e) {
        err << program << ": " << e.what() << "\n";
    } catch (const SampleFileError& e) {
        err << program << ": " << e.what() << "\n";
    } catch (const std::invalid_argument& e) {  // a table whose rows contradict each other
        err << program << ": " << e.what() << "\n";
    } catch (const ReportError& e) {  // a recording that cannot be written
        err << program << ": " << e.what() << "\n";
    }
    return std::nullopt;
}

}  // namespace warpcheck

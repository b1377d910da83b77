#include "validate/cli/cli.h"

#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cmath>
#include <cstdio>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <new>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "chi2/multiple_testing.h"
#include "reports/atomic_file.h"
#include "reports/outputs.h"
#include "reports/text.h"
#include "reports/render.h"
#include "reports/progress.h"
#include "reports/terminal_table.h"
#include "validate/cli/cli_input.h"
#include "validate/cli/samples_options.h"
#include "validate/run/asan.h"
#include "validate/run/merge.h"
#include "validate/run/run_digest.h"
#include "validate/run/runner.h"
#include "validate/run/fuzz.h"
#include "warpcheck/version.h"

namespace warpcheck {
namespace {

struct CliOptions {
    RunOptions run;
    std::string program_name = "validate";  ///< how messages name the program: argv[0]'s file name
    bool all = false;
    bool list = false;
    bool failures_only = false;
    bool timings = false;
    bool wide = false;
    bool settings_from_environment = false;
    std::string color = "auto";
    std::string progress = "auto";
    std::string report_on_failure_path;
    std::vector<std::string> filters;
    std::vector<std::string> checks;
    std::vector<std::string> skipped_checks;  ///< --skip-check: left out of the checks run
    std::string report_path, json_path, junit_path;
    bool no_isolation = false;
    uint64_t memory_limit_mib = 0;
    bool memory_limit_set = false;
    bool list_jobs = false;
    std::optional<std::string> shard_spec;
    Shard shard;
    std::vector<std::string> merge_paths;
    bool missing_shards = false;
    SamplesOptions samples;  ///< samples from elsewhere (validate/cli/samples_options.h)
    bool fuzz = false;               ///< --fuzz (validate/run/fuzz.h)
    unsigned fuzz_points = 24;       ///< --fuzz-points: random points per family
    std::vector<std::string> fuzz_cases;  ///< --fuzz-case: cases made by their family at named parameters
};

struct Output {
    const char* option;
    const std::string* path;  ///< as given, for messages
    std::string (*render)(const RunResult&);
    const char* what;               ///< for "... written to PATH"
    bool only_on_failure = false;  ///< --report-on-failure: written only when a check failed or errored
    /// Where the file goes: the path made absolute when the command starts, so
    /// that a warp's chdir() in an in-process run does not move it.
    std::string target{};
};

std::vector<Output> requested_outputs(const CliOptions& o) {
    std::vector<Output> outputs;
    for (const Output& out : {Output{"--report", &o.report_path, render_html, "HTML report"},
                              Output{"--report-on-failure", &o.report_on_failure_path, render_html, "HTML report", true},
                              Output{"--json", &o.json_path, render_json, "JSON results"},
                              Output{"--junit", &o.junit_path, render_junit, "JUnit XML"}})
        if (!out.path->empty()) {
            std::error_code ec;
            const std::filesystem::path absolute = std::filesystem::absolute(*out.path, ec);
            outputs.push_back(out);
            outputs.back().target = *out.path == "-" || ec ? *out.path : absolute.string();
        }
    return outputs;
}

/// Whether `a` and `b` both exist and are one file (through links, hard links too).
bool same_file(const std::string& a, const std::string& b) {
    struct stat sa {}, sb {};
    return ::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev &&
           sa.st_ino == sb.st_ino;
}

// Every output is probed before the run, so that a typo does not cost a whole
// run: '-' (standard output) at most once, each path writable, no two outputs
// landing in the same file, none of them a file to merge. Returns the problem, or empty.
std::string output_problem(const std::vector<Output>& outputs, const std::vector<std::string>& inputs) {
    std::set<std::string> targets;
    int to_stdout = 0;
    for (const Output& out : outputs) {
        if (*out.path == "-") {
            if (++to_stdout > 1) return "only one output can be '-' (standard output)";
            continue;
        }
        if (const std::string why = output_path_problem(*out.path); !why.empty())
            return fmt::format("cannot write '{}' ({}): {}", *out.path, out.option, why);
        if (!targets.insert(resolved_output_path(*out.path)).second)
            return fmt::format("'{}' ({}) is the same file as another output", *out.path, out.option);
        for (const std::string& input : inputs)
            if (same_file(*out.path, input))
                return fmt::format("'{}' ({}) is the file to merge '{}': the merge would overwrite it", *out.path,
                                   out.option, input);
    }
    return {};
}

// Writes every output it can, even after one failed, and says where each
// file went on `notes` (the table's stream); false if any failed.
bool write_outputs(const std::vector<Output>& outputs, const RunResult& run, const std::string& program,
                   std::ostream& notes) {
    bool ok = true;
    for (const Output& out : outputs) {
        if (out.only_on_failure && run.all_passed()) continue;
        try {
            if (*out.path == "-") {
                std::cout << out.render(run) << std::flush;
                continue;
            }
            const std::string text = out.render(run);
            write_file_atomically(out.target, text);
            notes << out.what << " written to " << *out.path << "\n";
            // A shard's results too large for --merge to read: said now, not at the merge.
            if (out.render == render_json && run.info.shard_count > 0)
                if (const std::string warning = shard_size_warning(text.size(), run.info.shard_count); !warning.empty())
                    std::cerr << program << ": warning: --json " << *out.path << ": " << warning << "\n";
        } catch (const std::exception& e) {
            std::cerr << program << ": " << out.option << ": " << e.what() << "\n";
            ok = false;
        }
    }
    return ok;
}

// Counts and real numbers are read by validate/cli/cli_input.h (1e6, 10M and
// 1_000_000 for counts; the range said in words). A transform rewrites a
// count as plain digits for CLI11 to store. No description: --help shows the
// ranges in the options' own text instead of validator names.
CLI::Validator count_in(uint64_t min, uint64_t max, std::string unit = "") {
    return CLI::Validator(
        [=](std::string& text) {
            const ParsedCount c = parse_count_in(text, min, max);
            if (!c.problem.empty()) return c.problem + unit;
            text = std::to_string(c.value);
            return std::string();
        },
        "");
}

const CLI::Validator kSeed(
    [](std::string& text) {
        const ParsedCount c = parse_count(text);
        if (!c.problem.empty())
            return fmt::format("'{}' is not a seed: give a whole number from 0 to {}", text, format_count(UINT64_MAX));
        text = std::to_string(c.value);
        return std::string();
    },
    "");

CLI::Validator real_in(double min, double max, std::string unit = "") {
    return CLI::Validator(
        [=](std::string& text) {
            const ParsedReal r = parse_real_in(text, min, max);
            return r.problem.empty() ? r.problem : r.problem + unit;
        },
        "");
}

void list_cases(const Registry& registry, const std::vector<Job>& jobs, std::ostream& out) {
    out << "Checks:\n";
    for (const auto& c : registry.checks())
        out << fmt::format("  {:<22} {}\n", terminal_text(c->name()), terminal_text(c->description()));
    out << "\nWarp cases (with the checks that apply):\n";
    const WarpCase* current = nullptr;
    for (const Job& job : jobs) {
        if (job.warp != current) {
            current = job.warp;
            const std::string flaw = registry.known_flaw(*current);
            out << fmt::format("  {}\n      {}\n", terminal_text(current->name()),
                               terminal_text(current->info().description));
            if (!flaw.empty())
                out << fmt::format("      known flaw (runs with --include-flawed): {}\n", terminal_text(flaw));
            out << "      checks:";
        }
        out << " " << terminal_text(job.check->name())
            << (job.not_applicable.empty() ? "" : " (n/a: " + terminal_text(job.not_applicable) + ")");
        if (&job == &jobs.back() || (&job + 1)->warp != current) out << "\n";
    }
}


void add_selection_options(CLI::App& app, CliOptions& o) {
    app.add_flag("--all", o.all, "Run every warp case");
    app.add_option("--filter", o.filters,
                   "Run the cases whose name contains PATTERN (or matches it as a glob with * and ?; "
                   "a full case name selects exactly that case). Repeatable.")
        ->type_name("PATTERN")
        // One pattern per --filter, taken whole: CLI11 would otherwise split a
        // value in brackets at its commas ('[a=1,b=3]' as '[a=1' and 'b=3]').
        ->allow_extra_args(false);
    app.add_option("--check", o.checks, "Run only this check (repeatable); see --list for names")->type_name("NAME");
    app.add_option("--skip-check", o.skipped_checks,
                   "Run every check that would run but this one (repeatable; with --check, those named there "
                   "but this one): e.g. the 2^32 sweeps of exhaustive left out of a quick run")
        ->type_name("NAME");
    app.add_flag("--list", o.list, "List the checks and the warp cases (those selected by --filter), then exit");
    app.add_flag("--list-jobs", o.list_jobs,
                 "List the (case, check) jobs the selection would run (of the --shard, if given), one per line: "
                 "the check, a tab, the case; then exit");
    app.add_option("--shard",
                   "Run only part I of N of the selected (case, check) jobs (1 <= I <= N), judged at the Sidak level "
                   "of the whole selection: the N shards' --json files merge (--merge) into the whole run")
        ->type_name("I/N")
        ->each([&o](const std::string& spec) { o.shard_spec = spec; });
    app.add_option("--merge", o.merge_paths,
                   "Combine the --json files of the shards of one run into its table and reports, then exit")
        ->type_name("FILE")
        ->expected(1, -1);
    app.add_flag("--missing-shards", o.missing_shards,
                 "With --merge: check the files given and list the shards of their run that are not among them "
                 "(I/N, one per line; none when all are there), instead of merging: the ones to run again");
    app.add_flag("--fuzz", o.fuzz,
                 "Draw each family's parameters from the ranges it declares, their ends first, run the cheap checks "
                 "(finite samples with positive pdfs, weights, delta lobes, energy; --check to choose) at 20,000 "
                 "samples unless --samples says otherwise, and shrink each failure to the simplest parameters that "
                 "still fail, printed as a rerun line; --filter selects families");
    app.add_option("--fuzz-points", o.fuzz_points,
                   "With --fuzz: points drawn at random per family besides the ranges' ends, 0 to 10000")
        ->type_name("N")
        ->capture_default_str();
    app.add_option("--fuzz-case", o.fuzz_cases,
                   "Run the checks on a case its family makes at the parameters named, e.g. "
                   "'rough_conductor[alpha=0.0001,theta_o=89.99]' (the rerun of a --fuzz finding). Repeatable.")
        ->type_name("NAME")
        ->allow_extra_args(false);
    app.add_flag("--exhaustive", o.run.exhaustive, "Also run the heavy sweeps (e.g. round trips over every float)");
    app.add_flag("--include-flawed", o.run.include_flawed,
                 "Also run the cases that demonstrate known flaws (e.g. u * 2^-32 reaching 1.0); they fail");
    app.add_flag("--strict", o.run.strict,
                 "Grant no float-resolution allowance: a pdf whose float rounding moves its integral, or an inverse "
                 "that returns 1 for u within a float of 1, fails instead of passing with its size and count");
}

// The limits, stated once here and in validate/cli/cli_input.h (samples,
// alpha, time budget and memory limit, shared with the WARPCHECK_* variables);
// validate/cli/README.md says them too.
constexpr unsigned kMaxThreads = 1024;

void add_run_options(CLI::App& app, CliOptions& o) {
    app.add_option("--seed", o.run.seed, "Global seed, 0 to 2^64-1; every (case, check) stream derives from it")
        ->type_name("N")
        ->transform(kSeed)
        ->capture_default_str();
    app.add_option("--samples", o.run.samples,
                   fmt::format("Samples per statistical check, {} to {} (1e6, 10M and 1_000_000 are read)",
                               format_count(kMinSamples), format_count(kMaxSamples)))
        ->type_name("N")
        ->transform(count_in(kMinSamples, kMaxSamples))
        ->capture_default_str();
    app.add_option("--threads", o.run.threads,
                   fmt::format("Worker threads, 0 (all hardware threads) to {}; results do not depend on it", kMaxThreads))
        ->type_name("N")
        ->transform(count_in(0, kMaxThreads))
        ->capture_default_str();
    app.add_option("--alpha", o.run.alpha,
                   fmt::format("Family-wise significance level over all statistical tests of the run, {} to {}",
                               format_limit(kMinAlpha), format_limit(kMaxAlpha)))
        ->type_name("A")
        ->check(real_in(kMinAlpha, kMaxAlpha))
        ->capture_default_str();
    app.add_option("--time-budget", o.run.check_time_budget,
                   fmt::format("CPU seconds one check may use, {} to {} (rounded up to whole seconds), before its "
                               "worker is killed and the check reported as an error; a worker asleep for 10x the "
                               "budget in wall time is killed too. With --no-isolation the check is only asked to "
                               "stop after this many wall seconds, and a warp that never returns hangs the run",
                               format_limit(kMinBudget), format_limit(kMaxBudget)))
        ->type_name("S")
        ->check(real_in(kMinBudget, kMaxBudget, " (seconds)"))
        ->capture_default_str()
        ->each([&o](const std::string&) { o.run.time_budget_set = true; });
    app.add_flag("--no-isolation", o.no_isolation,
                 "Run the checks in this process instead of one worker process per check (for debuggers): a "
                 "crash or endless loop in a warp then takes the whole run down, and a warp's exit() ends it with "
                 "status 1 and a message naming the check, without reports");
    app.add_option("--memory-limit", o.memory_limit_mib,
                   fmt::format("Address space in MiB that the run's worker processes may use together, 0 (no limit) "
                               "to {}: the workers that run at once share it equally, and a check over its share is "
                               "an error. Default: the machine's physical memory, at most 8192 MiB per worker. Not "
                               "applied under AddressSanitizer",
                               format_count(kMaxMemoryMib)))
        ->type_name("MIB")
        ->transform(count_in(0, kMaxMemoryMib, " (MiB)"))
        ->each([&o](const std::string&) { o.memory_limit_set = true; });
    app.add_option("--max-float-bias", o.run.max_float_bias,
                   "Fail an exhaustive sweep when a float's count is off its ideal by more than this factor, 1 to 1e6")
        ->type_name("R")
        ->check(real_in(1.0, 1e6));
    app.add_flag("--settings-from-environment", o.settings_from_environment,
                 "WARPCHECK_SEED, WARPCHECK_SAMPLES, WARPCHECK_ALPHA, WARPCHECK_TIME_BUDGET and "
                 "WARPCHECK_MEMORY_LIMIT, where set, replace --seed, --samples, --alpha, --time-budget and "
                 "--memory-limit (an invalid value is an error naming the variable); what warpcheck_discover_tests "
                 "runs");
}

void add_output_options(CLI::App& app, CliOptions& o) {
    // A symbolic link is written through to its target; '-' is standard output
    // (for one of them; the table then goes to standard error).
    app.add_option("--report", o.report_path, "Write a self-contained HTML report ('-': standard output)")
        ->type_name("FILE");
    app.add_option("--report-on-failure", o.report_on_failure_path,
                   "Write the HTML report only if a check failed or errored: the evidence of a CI or ctest run")
        ->type_name("FILE");
    app.add_option("--json", o.json_path, "Write the results as JSON ('-': standard output)")->type_name("FILE");
    app.add_option("--junit", o.junit_path, "Write the results as JUnit XML ('-': standard output)")
        ->type_name("FILE");
    app.add_flag("--failures-only", o.failures_only, "Print only the rows that did not pass");
    app.add_flag("--wide", o.wide,
                 "Print case names and key figures whole, however wide (the table otherwise fits the terminal, "
                 "or 120 columns)");
    app.add_flag("--timings", o.timings,
                 "After the table, where the run's time went: seconds per check, the slowest rows and their parts");
    app.add_option("--color", o.color, "Colour the table: auto (on a terminal), always, never")
        ->type_name("WHEN")
        ->check(CLI::IsMember({"auto", "always", "never"}).description(""))
        ->capture_default_str();
    app.add_option("--progress", o.progress,
                   "Show progress on standard error: auto (a bar on a terminal, else a line every 10 s or 10%), "
                   "bar, log, none. Failures are shown as they happen")
        ->type_name("HOW")
        ->check(CLI::IsMember({"auto", "bar", "log", "none"}).description(""))
        ->capture_default_str();
}

/// The check names, with a suggestion for a misspelt one.
std::string unknown_check(const std::string& name, const Registry& registry) {
    std::vector<std::string> names;
    for (const auto& c : registry.checks()) names.push_back(c->name());
    std::string list;
    for (const auto& n : names) list += " " + n;
    return fmt::format("unknown check '{}'{}; the checks are:{}", name, did_you_mean(closest_names(name, names)), list);
}

/// A --filter that matches nothing, with the closest families (or, for a
/// pattern with parameters, the closest case names).
std::string no_case_matches(const std::string& pattern, const Registry& registry, const std::string& program) {
    std::vector<std::string> names;
    const bool whole_names = pattern.find('[') != std::string::npos;
    for (const auto& c : registry.cases()) {
        const std::string& name = c->name();
        names.push_back(whole_names ? name : name.substr(0, name.find('[')));
    }
    const bool glob = pattern.find_first_of("*?") != std::string::npos;
    const std::string hint = glob ? "" : did_you_mean(closest_names(pattern, names, !whole_names));
    return fmt::format("no warp case matches '{}'{}; '{} --list' shows them all", pattern, hint, program);
}

/// --skip-check: o.checks becomes the checks that would run (all that run by
/// default, or those named by --check) less the skipped; what is wrong, or empty.
std::string apply_skipped_checks(CliOptions& o, const Registry& registry) {
    if (o.skipped_checks.empty()) return {};
    // Both lists first: a misspelt --check must not vanish from the list below.
    for (const auto* names : {&o.checks, &o.skipped_checks})
        for (const auto& name : *names)
            if (!registry.find_check(name)) return unknown_check(name, registry);
    // Named, so that select_jobs takes exactly those (a check that runs only
    // when asked stays out, as it would without --skip-check).
    const auto named = [](const std::vector<std::string>& names, const std::string& name) {
        return std::find(names.begin(), names.end(), name) != names.end();
    };
    std::vector<std::string> kept;
    for (const auto& c : registry.checks()) {
        const bool would_run = o.checks.empty() ? c->runs_by_default(o.run) : named(o.checks, c->name());
        if (would_run && !named(o.skipped_checks, c->name())) kept.push_back(c->name());
    }
    if (kept.empty()) return "--skip-check leaves no check to run";
    o.checks = std::move(kept);
    return {};
}

/// What is wrong with the selection, or empty; reads --shard into o.shard.
std::string selection_problem(CliOptions& o, const Registry& registry) {
    if (o.missing_shards && o.merge_paths.empty())
        return "--missing-shards lists what --merge lacks: give --merge FILE...";
    if (!o.merge_paths.empty())
        return o.all || !o.filters.empty() || o.list || o.list_jobs || o.shard_spec
                   ? "--merge takes the shards' results files, not a selection (--all, --filter, --list, --shard)"
                   : "";
    if (!o.all && o.filters.empty() && !o.list && !o.list_jobs)
        return "nothing selected: use --all, --filter PATTERN or --list";
    if (o.all && !o.filters.empty()) return "--all and --filter exclude each other";
    if (!o.report_path.empty() && !o.report_on_failure_path.empty())
        return "--report and --report-on-failure exclude each other";
    if (o.shard_spec) {
        const auto shard = parse_shard(*o.shard_spec);
        if (!shard)
            return fmt::format("--shard: '{}' is not a shard: give I/N, part I of N with 1 <= I <= N (e.g. 2/4)",
                               terminal_text(*o.shard_spec));
        o.shard = *shard;
    }
    for (const auto& name : o.checks)
        if (!registry.find_check(name)) return unknown_check(name, registry);
    for (const auto& pattern : o.filters) {
        bool any = false;
        for (const auto& c : registry.cases()) any = any || name_matches(c->name(), pattern);
        if (!any) return no_case_matches(pattern, registry, o.program_name);
    }
    return {};
}

/// Whether all that was written to standard output got there; if not, says
/// so on standard error. A pipe whose reader left early (`| head`) is the
/// reader's choice, not an error: the exit status then still says what the
/// checks said.
bool stdout_written(const std::string& program, const char* what) {
    errno = 0;
    std::cout.flush();
    const bool failed = !std::cout || std::fflush(stdout) != 0 || std::ferror(stdout);
    const int error = errno;
    struct stat out_stat {};
    const bool to_pipe = fstat(STDOUT_FILENO, &out_stat) == 0 && S_ISFIFO(out_stat.st_mode);
    if (!failed || to_pipe) return true;
    std::cerr << program << ": could not write " << what << " to standard output"
              << (error ? std::string(": ") + std::strerror(error) : std::string()) << "\n";
    return false;
}

/// For an in-process run: what warps print to standard output goes to standard
/// error while the checks run, so that standard output carries only the tool's
/// own (a `--json -` stays parseable). Isolated runs capture it per job.
class StdoutToStderr {
public:
    StdoutToStderr() {
        std::cout.flush();
        std::fflush(stdout);
        saved_ = ::dup(STDOUT_FILENO);
        if (saved_ >= 0) ::dup2(STDERR_FILENO, STDOUT_FILENO);
    }
    ~StdoutToStderr() {
        std::cout.flush();
        std::fflush(stdout);
        if (saved_ < 0) return;
        ::dup2(saved_, STDOUT_FILENO);
        ::close(saved_);
        std::cout.clear();  // a warp's failed write was not the tool's
        std::clearerr(stdout);
    }
    StdoutToStderr(const StdoutToStderr&) = delete;
    StdoutToStderr& operator=(const StdoutToStderr&) = delete;

private:
    int saved_ = -1;
};

/// The table's look: colour and width follow the terminal it goes to, if any.
TableStyle table_style(const CliOptions& o, int fd) {
    TableStyle style;
    const bool terminal = isatty(fd) == 1;
    style.color = o.color == "always" || (o.color == "auto" && terminal);
    style.failures_only = o.failures_only;
    style.timings = o.timings;
    winsize size{};
    if (o.wide) style.width = 0;
    else if (terminal && ::ioctl(fd, TIOCGWINSZ, &size) == 0 && size.ws_col >= 60) style.width = size.ws_col;
    return style;
}

/// Prints the table and writes the outputs; the exit status.
int present(const RunResult& run, const CliOptions& o, const std::vector<Output>& outputs) {
    // With a report on standard output, the table goes to standard error.
    const bool report_to_stdout =
        std::any_of(outputs.begin(), outputs.end(), [](const Output& out) { return *out.path == "-"; });
    std::ostream& table = report_to_stdout ? std::cerr : std::cout;
    print_table(run, table, table_style(o, report_to_stdout ? STDERR_FILENO : STDOUT_FILENO));
    if (!write_outputs(outputs, run, o.program_name, table) || !stdout_written(o.program_name, "the table"))
        return kExitUsage;
    return run.all_passed() ? kExitPass : kExitFail;
}

std::string command_line(int argc, char** argv) {
    std::ostringstream command;
    for (int i = 0; i < argc; ++i) command << (i ? " " : "") << argv[i];
    return command.str();
}

/// --merge: the shards' JSON files read, checked and combined.
int run_merge(const CliOptions& o, const std::vector<Output>& outputs, const std::string& command) {
    std::vector<ShardFile> shards;
    RunResult merged;
    try {
        for (const std::string& path : o.merge_paths) shards.push_back(read_shard_file(path));
        if (o.missing_shards) {
            for (const std::string& shard : missing_shards(shards)) std::cout << shard << "\n";
            return stdout_written(o.program_name, "the missing shards") ? kExitPass : kExitUsage;
        }
        merged = merge_shards(shards, o.run.program);
    } catch (const MergeError& e) {
        std::cerr << o.program_name << ": --merge: " << e.what() << "\n";
        return kExitUsage;
    } catch (const std::bad_alloc&) {
        std::cerr << "validate: --merge: out of memory reading the shards\n";
        return kExitUsage;
    }
    merged.info.command_line = command;
    return present(merged, o, outputs);
}

/// Runs the selection (or its shard) and presents it.
int run_selection(const CliOptions& o, const Registry& registry, const std::vector<Output>& outputs,
                  const std::string& command, const std::function<void(RunResult&)>& adjust = {}) {
    const std::vector<Job> all_jobs = select_jobs(registry, o.filters, o.checks, o.run);
    const std::vector<Job> jobs = shard_jobs(all_jobs, o.shard);
    if (o.list_jobs) {
        for (const Job& job : jobs)
            std::cout << terminal_text(job.check->name()) << '\t' << terminal_text(job.warp->name()) << '\n';
        return stdout_written(o.program_name, "the job list") ? kExitPass : kExitUsage;
    }
    if (all_jobs.empty()) {
        std::cerr << o.program_name << ": the selected checks apply to none of the selected cases\n";
        return kExitUsage;
    }
    RunOptions options = o.run;
    options.family_tests = statistical_tests(all_jobs);  // a shard is judged as part of the whole run
    Isolation isolation;
    isolation.enabled = !o.no_isolation;
    if (o.memory_limit_set) isolation.memory_budget = o.memory_limit_mib << 20;
    ProgressDisplay::Options progress;
    progress.mode = progress_mode(o.progress, isatty(STDERR_FILENO) == 1).value_or(ProgressMode::Off);
    progress.level = chi2::sidak_level(options.alpha, *options.family_tests);
    progress.program = o.program_name;
    RunResult run = [&] {
        std::optional<StdoutToStderr> warps_print_to_stderr;
        if (o.no_isolation) warps_print_to_stderr.emplace();
        return run_jobs(jobs, options, stderr_progress(std::move(progress)), isolation);
    }();
    run.info.command_line = command;
    run.info.tool_version = WARPCHECK_VERSION;
    if (o.shard_spec) {
        run.info.shard_index = o.shard.index;
        run.info.shard_count = o.shard.count;
        run.info.run_jobs = all_jobs.size();
    }
    std::vector<JobName> whole_run;
    for (const Job& job : all_jobs) whole_run.push_back({job.warp->name(), job.check->name()});
    if (adjust) adjust(run);
    seal_run(run, whole_run);
    return present(run, o, outputs);
}

/// --fuzz-case: the cases their families make at the parameters named, run as a selection.
int run_fuzz_cases(CliOptions o, const Registry& registry, const std::vector<Output>& outputs,
                   const std::string& command) {
    if (o.all || !o.filters.empty()) {
        std::cerr << o.program_name << ": --fuzz-case names its cases: it takes no --all or --filter\n";
        return kExitUsage;
    }
    Registry made;
    for (const std::string& name : o.fuzz_cases) {
        std::string problem;
        std::unique_ptr<WarpCase> warp = make_case_from_name(registry, name, problem);
        if (!warp) {
            std::cerr << o.program_name << ": --fuzz-case: " << terminal_text(problem) << "\n";
            return kExitUsage;
        }
        if (!made.find_case(warp->name())) made.add_case(std::move(warp));
        o.filters.push_back(name);
    }
    for (const auto& check : registry.checks()) made.add_named_check(check->name(), check);
    if (const std::string problem = selection_problem(o, made); !problem.empty()) {
        std::cerr << o.program_name << ": " << problem << "\n";
        return kExitUsage;
    }
    if (const std::string bad = output_problem(outputs, {}); !bad.empty()) {
        std::cerr << o.program_name << ": " << bad << "\n";
        return kExitUsage;
    }
    // Each row's rerun line makes its case from its name again, as the run did.
    return run_selection(o, made, outputs, command, [](RunResult& run) {
        for (CheckResult& r : run.results) r.rerun_command = fuzz_case_rerun(r.rerun_command);
    });
}

/// --fuzz: the families' ranges run through the cheap checks (validate/run/fuzz.h).
int run_fuzz_mode(const CliOptions& o, const Registry& registry, bool samples_given,
                  const std::vector<Output>& outputs, const std::string& command) {
    if (o.all || o.list || o.list_jobs || o.shard_spec || !o.merge_paths.empty() || o.samples.any()) {
        std::cerr << o.program_name << ": --fuzz runs on its own: --filter picks families, --check checks\n";
        return kExitUsage;
    }
    if (o.fuzz_points > 10000) {
        std::cerr << o.program_name << ": --fuzz-points: " << o.fuzz_points << " is more than 10000\n";
        return kExitUsage;
    }
    FuzzOptions f;
    f.families = o.filters;
    f.checks = o.checks;
    f.random_points = o.fuzz_points;
    f.run = o.run;
    if (!samples_given) f.run.samples = 20'000;
    f.isolation.enabled = !o.no_isolation;
    if (o.memory_limit_set) f.isolation.memory_budget = o.memory_limit_mib << 20;
    for (const auto& name : o.checks)
        if (!registry.find_check(name)) {
            std::cerr << o.program_name << ": " << unknown_check(name, registry) << "\n";
            return kExitUsage;
        }
    bool any = false;
    for (const CaseFamily& family : registry.families()) {
        bool wanted = o.filters.empty();
        for (const std::string& pattern : o.filters)
            wanted = wanted || (registry.find_family(pattern) ? family.base.family == pattern
                                                              : name_matches(family.base.family, pattern));
        any = any || (wanted && family.fuzzable());
    }
    if (!any) {
        std::cerr << o.program_name << ": --fuzz: no family "
                  << (o.filters.empty() ? "declares" : "selected by --filter declares")
                  << " a parameter range (GridAxis::ranges) to draw from\n";
        return kExitUsage;
    }
    if (const std::string bad = output_problem(outputs, {}); !bad.empty()) {
        std::cerr << o.program_name << ": " << bad << "\n";
        return kExitUsage;
    }
    FuzzReport report = run_fuzz(registry, f);
    std::cout << fuzz_report_text(report);
    // Every point's rows, for --json, --report and --junit: one result model.
    report.run.info.command_line = command;
    report.run.info.tool_version = WARPCHECK_VERSION;
    std::vector<JobName> whole_run;
    for (const CheckResult& r : report.run.results) whole_run.push_back({r.case_name, r.check_name});
    seal_run(report.run, whole_run);
    if (!write_outputs(outputs, report.run, o.program_name, std::cout) ||
        !stdout_written(o.program_name, "the fuzz report"))
        return kExitUsage;
    return report.clean() ? kExitPass : kExitFail;
}

/// The widest line --help prints: its descriptions are wrapped to fit.
constexpr std::size_t kHelpWidth = 100;

/// `text` broken at spaces into lines of at most `width` characters (a word
/// longer than that on a line of its own).
std::string wrap_words(const std::string& text, std::size_t width) {
    std::string out, line;
    std::istringstream words(text);
    for (std::string word; words >> word;) {
        if (!line.empty() && line.size() + 1 + word.size() > width) {
            out += line + "\n";
            line.clear();
        }
        line += (line.empty() ? "" : " ") + word;
    }
    return out + line;
}

/// CLI11's help with each option's description wrapped, continued under its
/// first line (CLI11 2.1 prints a description on one line, up to 357 columns).
class WrappingFormatter : public CLI::Formatter {
public:
    std::string make_option_desc(const CLI::Option* option) const override {
        return wrap_words(CLI::Formatter::make_option_desc(option), kHelpWidth - get_column_width());
    }
};

/// The unknown options CLI11 left over, each with the closest known option.
std::string unknown_options(const CLI::App& app) {
    std::vector<std::string> known;
    for (const CLI::Option* option : app.get_options())
        for (const std::string& name : option->get_lnames()) known.push_back("--" + name);
    std::string text;
    const auto add = [&](const std::string& problem) { text += (text.empty() ? "" : "; ") + problem; };
    bool after_unknown_option = false;
    for (const std::string& arg : app.remaining()) {
        if (arg.size() >= 2 && arg[0] == '-') {
            const std::string typed = arg.substr(0, arg.find('='));
            add(fmt::format("unknown option '{}'{}", typed, did_you_mean(closest_names(typed, known))));
            after_unknown_option = true;
            continue;
        }
        // A word without dashes: an option's name typed as a word (`validate
        // all`), or, after an unknown option, that option's value.
        const std::string word = arg.substr(0, arg.find('='));
        if (std::find(known.begin(), known.end(), "--" + word) != known.end()) {
            add(fmt::format("'{}' is not an argument: options start with '--' (did you mean '--{}'?)",
                            terminal_text(arg), terminal_text(word)));
        } else if (!after_unknown_option) {
            add(fmt::format("unexpected argument '{}': {} takes options only (a case goes after --filter, e.g. "
                            "--filter '{}')",
                            terminal_text(arg), app.get_name(), terminal_text(arg)));
        }
        after_unknown_option = false;
    }
    return text;
}

/// Parses the command line into `o`; the exit status if the program is done
/// (help, version, bad usage), else nullopt.
std::optional<int> parse(CLI::App& app, CliOptions& o, int argc, char** argv) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ExtrasError& e) {
        const std::string unknown = unknown_options(app);
        std::cerr << o.program_name << ": " << (unknown.empty() ? std::string(e.what()) : unknown) << "\nRun '"
                  << o.program_name << " --help' for the options.\n";
        return kExitUsage;
    } catch (const CLI::ParseError& e) {
        std::cerr << o.program_name << ": " << e.what() << "\nRun '" << o.program_name << " --help' for the options.\n";
        return kExitUsage;
    }
    if (o.settings_from_environment) {
        std::optional<uint64_t> memory_limit_mib;
        if (const std::string problem = apply_environment_settings(o.run, &memory_limit_mib); !problem.empty()) {
            std::cerr << o.program_name << ": " << problem << "\n";
            return kExitUsage;
        }
        if (memory_limit_mib) {
            o.memory_limit_mib = *memory_limit_mib;
            o.memory_limit_set = true;
        }
    }
    return std::nullopt;
}

}  // namespace

void prefer_huge_pages([[maybe_unused]] char** argv) {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 35)) && \
    !defined(WARPCHECK_ASAN)
    if (!argv || !argv[0]) return;
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    const std::string before = tunables ? tunables : "";
    if (before.find("glibc.malloc.hugetlb") != std::string::npos) return;  // set: by the user, or by this exec
    std::ifstream mode("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string modes;
    std::getline(mode, modes);
    if (modes.find("[madvise]") == std::string::npos) return;  // "always" has them already, "never" not at all
    const std::string after = before.empty() ? "glibc.malloc.hugetlb=1" : before + ":glibc.malloc.hugetlb=1";
    if (::setenv("GLIBC_TUNABLES", after.c_str(), 1) != 0) return;
    std::fflush(nullptr);
    ::execv("/proc/self/exe", argv);
    // The exec failed: run on as this process, with the environment it had.
    if (tunables)
        ::setenv("GLIBC_TUNABLES", before.c_str(), 1);
    else
        ::unsetenv("GLIBC_TUNABLES");
#endif
}

int run_cli(int argc, char** argv, const Registry& registry) {
    // A reader that closes early (`validate --all | head`) must not kill the run
    // before the reports are written; a failed write to stdout is reported below.
    std::signal(SIGPIPE, SIG_IGN);
    // A report over the file size limit (ulimit -f) is a write error with a
    // message, not a death that leaves the temporary file behind.
    std::signal(SIGXFSZ, SIG_IGN);
    remove_temporary_files_on_signals();
    CliOptions o;
    if (argc > 0 && argv[0] && *argv[0]) {
        o.run.program = argv[0];
        o.program_name = std::filesystem::path(argv[0]).filename().string();
    }
    CLI::App app{"warpcheck " + o.program_name +
                     ": statistical and exhaustive checks of sampling routines (warps).\n"
                     "Exit status: 0 all passed, 1 a check failed or errored, 2 bad usage.",
                 o.program_name};
    app.formatter(std::make_shared<WrappingFormatter>());
    add_selection_options(app, o);
    add_run_options(app, o);
    add_output_options(app, o);
    add_samples_options(app, o.samples);
    app.set_version_flag("--version", "warpcheck " + o.program_name + " " WARPCHECK_VERSION);
    if (const auto done = parse(app, o, argc, argv)) return *done;
    const std::vector<Output> outputs = requested_outputs(o);
    if (const std::string bad = apply_skipped_checks(o, registry); !bad.empty()) {
        std::cerr << o.program_name << ": " << bad << "\n";
        return kExitUsage;
    }
    if (o.samples.any()) {  // samples from elsewhere: a run of their own (validate/cli/samples_options.h)
        o.samples.isolation = !o.no_isolation;
        if (const std::string bad = output_problem(outputs, {}); !bad.empty()) {
            std::cerr << o.program_name << ": " << bad << "\n";
            return kExitUsage;
        }
        const auto run = run_samples_mode(o.samples, registry, o.filters, o.checks, o.run, command_line(argc, argv),
                                          o.program_name, std::cerr);
        return run ? present(*run, o, outputs) : kExitUsage;
    }
    if (o.fuzz) return run_fuzz_mode(o, registry, app.count("--samples") > 0, outputs, command_line(argc, argv));
    if (!o.fuzz_cases.empty()) return run_fuzz_cases(o, registry, outputs, command_line(argc, argv));
    std::string problem = selection_problem(o, registry);
    if (problem.empty()) problem = output_problem(outputs, o.merge_paths);
    if (!problem.empty()) {
        std::cerr << o.program_name << ": " << problem << "\n";
        return kExitUsage;
    }
    if (!o.merge_paths.empty()) return run_merge(o, outputs, command_line(argc, argv));
    if (o.list) {
        RunOptions everything = o.run;  // list the known-flawed cases too, marked
        everything.include_flawed = true;
        list_cases(registry, select_jobs(registry, o.filters, o.checks, everything), std::cout);
        return stdout_written(o.program_name, "the list") ? kExitPass : kExitUsage;
    }
    return run_selection(o, registry, outputs, command_line(argc, argv));
}

}  // namespace warpcheck

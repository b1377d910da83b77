#include "validate/cli.h"

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
#include <iostream>
#include <optional>
#include <set>
#include <sstream>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "reports/atomic_file.h"
#include "reports/json_input.h"
#include "reports/outputs.h"
#include "reports/render.h"
#include "reports/progress.h"
#include "reports/terminal_table.h"
#include "validate/merge.h"
#include "validate/runner.h"
#include "warpcheck/version.h"

namespace warpcheck {
namespace {

struct CliOptions {
    RunOptions run;
    bool all = false;
    bool list = false;
    bool failures_only = false;
    bool timings = false;
    std::string color = "auto";
    std::vector<std::string> filters;
    std::vector<std::string> checks;
    std::string report_path, json_path, junit_path;
    bool no_isolation = false;
    uint64_t memory_limit_mib = 0;
    bool memory_limit_set = false;
    bool list_jobs = false;
    std::optional<std::string> shard_spec;
    Shard shard;
    std::vector<std::string> merge_paths;
};

struct Output {
    const char* option;
    const std::string* path;  ///< as given, for messages
    std::string (*render)(const RunResult&);
    /// Where the file goes: the path made absolute when the command starts, so
    /// that a warp's chdir() in an in-process run does not move it.
    std::string target{};
};

std::vector<Output> requested_outputs(const CliOptions& o) {
    std::vector<Output> outputs;
    for (const Output& out : {Output{"--report", &o.report_path, render_html}, Output{"--json", &o.json_path, render_json},
                              Output{"--junit", &o.junit_path, render_junit}})
        if (!out.path->empty()) {
            std::error_code ec;
            const std::filesystem::path absolute = std::filesystem::absolute(*out.path, ec);
            outputs.push_back(out);
            outputs.back().target = *out.path == "-" || ec ? *out.path : absolute.string();
        }
    return outputs;
}

// Every output is probed before the run, so that a typo does not cost a whole
// run: '-' (standard output) at most once, each path writable, no two outputs
// landing in the same file. Returns the problem, or empty.
std::string output_problem(const std::vector<Output>& outputs) {
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
    }
    return {};
}

// Writes every output it can, even after one failed; false if any failed.
bool write_outputs(const std::vector<Output>& outputs, const RunResult& run) {
    bool ok = true;
    for (const Output& out : outputs) {
        try {
            if (*out.path == "-") std::cout << out.render(run) << std::flush;
            else write_file_atomically(out.target, out.render(run));
        } catch (const std::exception& e) {
            std::cerr << "validate: " << out.option << ": " << e.what() << "\n";
            ok = false;
        }
    }
    return ok;
}

// CLI::Range lets NaN through (every comparison with NaN is false): a value
// meant to be a finite number is checked for that first.
const CLI::Validator kFinite(
    [](std::string& text) {
        double v = 0;
        if (!CLI::detail::lexical_cast(text, v) || !std::isfinite(v)) return "'" + text + "' is not a finite number";
        return std::string();
    },
    "FINITE");

// CLI11 reads an empty string as 0 and saturates out-of-range integers; the
// seed must be written out in full, 0 to 2^64-1.
const CLI::Validator kSeed(
    [](std::string& text) {
        const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
        errno = 0;
        if (digits) (void)std::strtoull(text.c_str(), nullptr, 10);
        if (!digits || errno == ERANGE)
            return "'" + text + "' is not a seed: an integer from 0 to 18446744073709551615";
        return std::string();
    },
    "SEED");

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
        ->type_name("FILE...")
        ->expected(1, -1);
    app.add_flag("--exhaustive", o.run.exhaustive, "Also run the heavy sweeps (e.g. round trips over every float)");
    app.add_flag("--include-flawed", o.run.include_flawed,
                 "Also run the cases that demonstrate known flaws (e.g. u * 2^-32 reaching 1.0); they fail");
    app.add_flag("--strict", o.run.strict,
                 "Grant no float-resolution allowance: a pdf whose float rounding moves its integral, or an inverse "
                 "that returns 1 for u within a float of 1, fails instead of passing with its size and count");
}

void add_run_options(CLI::App& app, CliOptions& o) {
    app.add_option("--seed", o.run.seed, "Global seed; every (case, check) stream derives from it")
        ->check(kSeed)
        ->capture_default_str();
    app.add_option("--samples", o.run.samples, "Samples per statistical check")
        ->check(CLI::Range(uint64_t{1000}, uint64_t{10'000'000'000}))
        ->capture_default_str();
    app.add_option("--threads", o.run.threads, "Worker threads (0: all hardware threads); results do not depend on it")
        ->check(CLI::Range(0u, 1024u))
        ->capture_default_str();
    app.add_option("--alpha", o.run.alpha, "Family-wise significance level over all statistical tests of the run")
        ->check(kFinite & CLI::Range(1e-12, 0.5))
        ->capture_default_str();
    app.add_option("--time-budget", o.run.check_time_budget,
                   "CPU seconds one check may use (rounded up to whole seconds) before its worker is killed and the "
                   "check reported as an error; a worker asleep for 10x the budget in wall time is killed too. With "
                   "--no-isolation the check is only asked to stop after this many wall seconds, and a warp that "
                   "never returns hangs the run")
        ->check(kFinite & CLI::Range(0.1, 86400.0))
        ->capture_default_str()
        ->each([&o](const std::string&) { o.run.time_budget_set = true; });
    app.add_flag("--no-isolation", o.no_isolation,
                 "Run the checks in this process instead of one worker process per check (for debuggers): a "
                 "crash or endless loop in a warp then takes the whole run down, and a warp's exit() ends it with "
                 "status 1 and a message naming the check, without reports");
    app.add_option("--memory-limit", o.memory_limit_mib,
                   "Address space in MiB that the run's worker processes may use together (0: no limit): the "
                   "workers that run at once share it equally, and a check over its share is an error. Default: "
                   "the machine's physical memory, at most 8192 MiB per worker. Not applied under AddressSanitizer")
        ->check(CLI::Range(uint64_t{0}, uint64_t{1} << 30))
        ->each([&o](const std::string&) { o.memory_limit_set = true; });
    app.add_option("--max-float-bias", o.run.max_float_bias,
                   "Fail an exhaustive sweep when a float's count is off its ideal by more than this factor")
        ->check(kFinite & CLI::Range(1.0, 1e6));
}

void add_output_options(CLI::App& app, CliOptions& o) {
    // A symbolic link is written through to its target; '-' is standard output
    // (for one of the three; the table then goes to standard error).
    app.add_option("--report", o.report_path, "Write a self-contained HTML report ('-': standard output)")
        ->type_name("FILE");
    app.add_option("--json", o.json_path, "Write the results as JSON ('-': standard output)")->type_name("FILE");
    app.add_option("--junit", o.junit_path, "Write the results as JUnit XML ('-': standard output)")
        ->type_name("FILE");
    app.add_flag("--failures-only", o.failures_only, "Print only the rows that did not pass");
    app.add_flag("--timings", o.timings,
                 "After the table, where the run's time went: seconds per check, the slowest rows and their parts");
    app.add_option("--color", o.color, "Colour the table: auto, always, never")
        ->check(CLI::IsMember({"auto", "always", "never"}))
        ->capture_default_str();
}

/// What is wrong with the selection, or empty; reads --shard into o.shard.
std::string selection_problem(CliOptions& o, const Registry& registry) {
    if (!o.merge_paths.empty())
        return o.all || !o.filters.empty() || o.list || o.list_jobs || o.shard_spec
                   ? "--merge takes the shards' results files, not a selection (--all, --filter, --list, --shard)"
                   : "";
    if (!o.all && o.filters.empty() && !o.list && !o.list_jobs)
        return "nothing selected: use --all, --filter PATTERN or --list";
    if (o.all && !o.filters.empty()) return "--all and --filter exclude each other";
    if (o.shard_spec) {
        const auto shard = parse_shard(*o.shard_spec);
        if (!shard)
            return fmt::format("--shard: '{}' is not a shard: give I/N, part I of N with 1 <= I <= N (e.g. 2/4)",
                               terminal_text(*o.shard_spec));
        o.shard = *shard;
    }
    for (const auto& name : o.checks) {
        if (registry.find_check(name)) continue;
        std::string names;
        for (const auto& c : registry.checks()) names += " " + c->name();
        return fmt::format("unknown check '{}'; the checks are:{}", terminal_text(name), names);
    }
    for (const auto& pattern : o.filters) {
        bool any = false;
        for (const auto& c : registry.cases()) any = any || name_matches(c->name(), pattern);
        if (!any)
            return fmt::format("no warp case matches '{}'; 'validate --list' shows them all", terminal_text(pattern));
    }
    return {};
}

/// Whether all that was written to standard output got there; if not, says
/// so on standard error. A pipe whose reader left early (`| head`) is the
/// reader's choice, not an error: the exit status then still says what the
/// checks said.
bool stdout_written(const char* what) {
    errno = 0;
    std::cout.flush();
    const bool failed = !std::cout || std::fflush(stdout) != 0 || std::ferror(stdout);
    const int error = errno;
    struct stat out_stat {};
    const bool to_pipe = fstat(STDOUT_FILENO, &out_stat) == 0 && S_ISFIFO(out_stat.st_mode);
    if (!failed || to_pipe) return true;
    std::cerr << "validate: could not write " << what << " to standard output"
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

/// Prints the table and writes the outputs; the exit status.
int present(const RunResult& run, const CliOptions& o, const std::vector<Output>& outputs) {
    TableStyle style;
    style.color = o.color == "always" || (o.color == "auto" && isatty(STDOUT_FILENO));
    style.failures_only = o.failures_only;
    style.timings = o.timings;
    // With a report on standard output, the table goes to standard error.
    const bool report_to_stdout =
        std::any_of(outputs.begin(), outputs.end(), [](const Output& out) { return *out.path == "-"; });
    print_table(run, report_to_stdout ? std::cerr : std::cout, style);
    if (!write_outputs(outputs, run) || !stdout_written("the table")) return kExitUsage;
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
        for (const std::string& path : o.merge_paths) {
            std::ifstream in(path, std::ios::binary);
            std::ostringstream text;
            if (!(in && text << in.rdbuf())) throw MergeError(fmt::format("{}: cannot be read", path));
            try {
                shards.push_back({path, parse_json_results(text.str())});
            } catch (const JsonInputError& e) {
                throw MergeError(fmt::format("{}: {}", path, e.what()));
            }
        }
        merged = merge_shards(shards);
    } catch (const MergeError& e) {
        std::cerr << "validate: --merge: " << e.what() << "\n";
        return kExitUsage;
    }
    merged.info.command_line = command;
    return present(merged, o, outputs);
}

/// Runs the selection (or its shard) and presents it.
int run_selection(const CliOptions& o, const Registry& registry, const std::vector<Output>& outputs,
                  const std::string& command) {
    const std::vector<Job> all_jobs = select_jobs(registry, o.filters, o.checks, o.run);
    const std::vector<Job> jobs = shard_jobs(all_jobs, o.shard);
    if (o.list_jobs) {
        for (const Job& job : jobs)
            std::cout << terminal_text(job.check->name()) << '\t' << terminal_text(job.warp->name()) << '\n';
        return stdout_written("the job list") ? kExitPass : kExitUsage;
    }
    if (all_jobs.empty()) {
        std::cerr << "validate: the selected checks apply to none of the selected cases\n";
        return kExitUsage;
    }
    RunOptions options = o.run;
    options.family_tests = statistical_tests(all_jobs);  // a shard is judged as part of the whole run
    Isolation isolation;
    isolation.enabled = !o.no_isolation;
    if (o.memory_limit_set) isolation.memory_budget = o.memory_limit_mib << 20;
    RunResult run = [&] {
        std::optional<StdoutToStderr> warps_print_to_stderr;
        if (o.no_isolation) warps_print_to_stderr.emplace();
        return run_jobs(jobs, options, stderr_progress(), isolation);
    }();
    run.info.command_line = command;
    run.info.tool_version = WARPCHECK_VERSION;
    if (o.shard_spec) {
        run.info.shard_index = o.shard.index;
        run.info.shard_count = o.shard.count;
        run.info.run_jobs = all_jobs.size();
    }
    return present(run, o, outputs);
}

}  // namespace

int run_cli(int argc, char** argv, const Registry& registry) {
    // A reader that closes early (`validate --all | head`) must not kill the run
    // before the reports are written; a failed write to stdout is reported below.
    std::signal(SIGPIPE, SIG_IGN);
    // A report over the file size limit (ulimit -f) is a write error with a
    // message, not a death that leaves the temporary file behind.
    std::signal(SIGXFSZ, SIG_IGN);
    remove_temporary_files_on_signals();
    CliOptions o;
    if (argc > 0 && argv[0] && *argv[0]) o.run.program = argv[0];
    CLI::App app{"warpcheck validate: statistical and exhaustive checks of sampling routines (warps).\n"
                 "Exit status: 0 all passed, 1 a check failed or errored, 2 bad usage.",
                 "validate"};
    add_selection_options(app, o);
    add_run_options(app, o);
    add_output_options(app, o);
    app.set_version_flag("--version", "warpcheck validate " WARPCHECK_VERSION);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "validate: " << e.what() << "\nRun 'validate --help' for the options.\n";
        return kExitUsage;
    }
    const std::vector<Output> outputs = requested_outputs(o);
    std::string problem = selection_problem(o, registry);
    if (problem.empty()) problem = output_problem(outputs);
    if (!problem.empty()) {
        std::cerr << "validate: " << problem << "\n";
        return kExitUsage;
    }
    if (!o.merge_paths.empty()) return run_merge(o, outputs, command_line(argc, argv));
    if (o.list) {
        RunOptions everything = o.run;  // list the known-flawed cases too, marked
        everything.include_flawed = true;
        list_cases(registry, select_jobs(registry, o.filters, o.checks, everything), std::cout);
        return stdout_written("the list") ? kExitPass : kExitUsage;
    }
    return run_selection(o, registry, outputs, command_line(argc, argv));
}

}  // namespace warpcheck

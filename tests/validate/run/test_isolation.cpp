// Isolated jobs: a warp that crashes, aborts, exits or allocates without bound
// is one ERROR row naming the cause; what it prints is its row's evidence; what
// it starts does not outlive its check; results travel from the worker
// complete and bit for bit.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <new>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "reports/terminal_table.h"
#include "reports/text.h"
#include "sampling/hemisphere.h"
#include "validate/checks/checks.h"
#include "validate/run/result_codec.h"
#include "validate/run/runner.h"
#include "validate/run/worker_output.h"
#include "validate/run/worker_supervisor.h"

#if defined(__SANITIZE_ADDRESS__)
#define WARPCHECK_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define WARPCHECK_TEST_ASAN 1
#endif
#endif

namespace warpcheck {
namespace {

TEST(ResultCodec, EveryFieldRoundTripsBitForBit) {
    CheckResult r;
    r.case_name = "c[a=1]";
    r.check_name = "chi2";
    r.verdict = Verdict::Fail;
    r.summary = "s";
    r.message = std::string("bytes \xff\x00 kept", 13);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    r.figures = {{"nan", nan}, {"inf", -std::numeric_limits<double>::infinity()}, {"zero", -0.0}, {"x", 0.1}};
    r.p_value = nan;
    r.level = 1e-300;
    Plot plot;
    plot.kind = Plot::Kind::Heatmaps;
    plot.title = "t";
    plot.log_y = true;
    plot.series = {{"s", {1, 2}, {nan, 4}}};
    Heatmap h;
    h.label = "h";
    h.rows = 1;
    h.cols = 2;
    h.values = {nan, 5e-324};
    h.y_max = 3;
    h.color_scale = Heatmap::ColorScale::Diverging;
    h.min_color_limit = 4;
    plot.heatmaps = {h};
    r.plots = {plot};
    r.tables = {{"worst", {"u", "x"}, {{"1", "2"}, {"3", "4"}}}};
    r.stream_seed = ~uint64_t{0};
    r.stream_sequence = 7;
    r.samples = 123;
    r.seconds = 0.25;
    r.phases = {{"integration", 0.125}, {"sampling+binning", 0x1.123456789abcdp-7}};
    r.rerun_command = "validate --filter 'c[a=1]'";

    const auto back = decode_result(encode_result(r));
    ASSERT_TRUE(back.has_value());
    // Re-encoding gives the same bytes: every field, every bit of every double.
    EXPECT_EQ(encode_result(*back), encode_result(r));
    EXPECT_EQ(back->message, r.message);
    EXPECT_EQ(std::memcmp(&back->figures[2].value, &r.figures[2].value, sizeof(double)), 0);
    EXPECT_TRUE(std::isnan(*back->p_value));
    EXPECT_EQ(back->plots.at(0).heatmaps.at(0).values.at(1), 5e-324);
    EXPECT_EQ(back->tables.at(0).rows.at(1).at(1), "4");
    ASSERT_EQ(back->phases.size(), 2u);
    EXPECT_EQ(back->phases[1].phase, "sampling+binning");
    EXPECT_EQ(back->phases[1].seconds, 0x1.123456789abcdp-7);
    // Half an encoding (a worker that died while writing) is no result.
    const std::string bytes = encode_result(r);
    EXPECT_FALSE(decode_result(bytes.substr(0, bytes.size() / 2)).has_value());
}

// A warp whose sample() does `misbehave` on the first call and is fine after.
std::unique_ptr<WarpCase> hostile(const char* name, void (*misbehave)()) {
    return make_warp_case({name, {}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()},
                          warp_of([misbehave](Point2f u) {
                                      misbehave();
                                      return UniformHemisphere{}.sample(u);
                                  })
                              .with_pdf([](Vector3f x) { return UniformHemisphere{}.pdf(x); })
                              .with_invert([](Vector3f x) { return UniformHemisphere{}.invert(x); }));
}

RunResult run_isolated(const std::vector<std::unique_ptr<WarpCase>>& cases, double budget = 20, unsigned threads = 2,
                       uint64_t memory_budget = uint64_t{2} << 30) {
    const auto check = make_roundtrip_check();
    std::vector<Job> jobs;
    for (const auto& c : cases) jobs.push_back({c.get(), check.get()});
    RunOptions options;
    options.samples = 20'000;
    options.threads = threads;
    options.check_time_budget = budget;
    Isolation isolation;
    isolation.enabled = true;
    isolation.memory_budget = memory_budget;
    return run_jobs(jobs, options, {}, isolation);
}

/// Ends the test program (a failure) if a test hangs for `seconds`: the way
/// these tests fail when a run waits for a warp's children.
struct Watchdog {
    explicit Watchdog(unsigned seconds) { alarm(seconds); }
    ~Watchdog() { alarm(0); }
};

/// The rows of the result's table titled `title` (empty if there is none).
std::vector<std::string> table_lines(const CheckResult& r, const std::string& title) {
    std::vector<std::string> lines;
    for (const Table& t : r.tables)
        if (t.title == title)
            for (const auto& row : t.rows) lines.push_back(row.at(0));
    return lines;
}

/// The pids a warp printed as "pid N" lines on its standard output.
std::vector<pid_t> printed_pids(const CheckResult& r) {
    std::vector<pid_t> pids;
    for (const std::string& line : table_lines(r, "Output of the warp (stdout)"))
        if (line.rfind("pid ", 0) == 0) pids.push_back(std::stoi(line.substr(4)));
    return pids;
}

bool process_exists(pid_t pid) { return ::kill(pid, 0) == 0 || errno != ESRCH; }

/// A child that sleeps forever, holding the worker's pipes; prints its pid.
void start_sleeping_child() {
    static bool started = false;
    if (std::exchange(started, true)) return;
    const pid_t child = fork();
    if (child == 0)
        for (;;) pause();
    std::printf("pid %d\n", static_cast<int>(child));
    std::fflush(stdout);
}

/// A daemon (fork, setsid, fork) that sleeps forever; prints its pid.
void start_sleeping_daemon() {
    static bool started = false;
    if (std::exchange(started, true)) return;
    int ends[2];
    if (pipe(ends) != 0) return;
    const pid_t child = fork();
    if (child == 0) {
        setsid();
        if (fork() == 0) {
            const pid_t self = getpid();
            (void)!write(ends[1], &self, sizeof self);
            for (;;) pause();
        }
        _exit(0);
    }
    pid_t daemon = 0;
    if (read(ends[0], &daemon, sizeof daemon) == sizeof daemon) std::printf("pid %d\n", static_cast<int>(daemon));
    std::fflush(stdout);
    waitpid(child, nullptr, 0);
}

// A warp that starts a process which never exits and holds the worker's
// pipes: the run reads the result without waiting for end of file on them,
// and kills the process when the check ends. (The run used to wait for the
// pipes' end of file: forever.)
TEST(Isolation, ProcessesAWarpStartsNeitherStallTheRunNorOutliveTheirCheck) {
    const Watchdog watchdog(120);
    std::vector<std::unique_ptr<WarpCase>> cases;
    cases.push_back(hostile("child", start_sleeping_child));
    cases.push_back(hostile("daemon", start_sleeping_daemon));
    const auto start = std::chrono::steady_clock::now();
    const RunResult run = run_isolated(cases, 10);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_EQ(run.results.size(), 2u);
    for (const CheckResult& r : run.results) {
        EXPECT_EQ(r.verdict, Verdict::Pass) << r.case_name << ": " << r.message;
        const std::vector<pid_t> pids = printed_pids(r);
        ASSERT_EQ(pids.size(), 1u) << r.case_name;
        EXPECT_FALSE(process_exists(pids[0])) << r.case_name << ": process " << pids[0] << " outlived the run";
    }
    // Two short checks; the processes sleep forever. 60 s is a loaded machine.
    EXPECT_LT(seconds, 60.0);
}

void print_three_lines() {
    static bool printed = false;
    if (std::exchange(printed, true)) return;
    std::printf("printf line\n");
    std::cout << "cout line" << std::endl;
    std::fprintf(stderr, "stderr line\n");
}

void print_then_abort() {
    std::fprintf(stderr, "first\nassertion failed: x < 1\n");
    std::abort();
}

// What a warp prints is captured per job and shown in its row; an error row
// quotes the last line on standard error.
TEST(Isolation, WhatAWarpPrintsIsItsRowsEvidence) {
    std::vector<std::unique_ptr<WarpCase>> cases;
    cases.push_back(hostile("prints", print_three_lines));
    cases.push_back(hostile("asserts", print_then_abort));
    cases.push_back(make_warp_case({"quiet", {}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()},
                                   UniformHemisphere{}));
    const RunResult run = run_isolated(cases);
    ASSERT_EQ(run.results.size(), 3u);
    EXPECT_EQ(run.results[0].verdict, Verdict::Pass) << run.results[0].message;
    EXPECT_EQ(table_lines(run.results[0], "Output of the warp (stdout)"),
              (std::vector<std::string>{"printf line", "cout line"}));
    EXPECT_EQ(table_lines(run.results[0], "Output of the warp (stderr)"), std::vector<std::string>{"stderr line"});
    EXPECT_EQ(run.results[0].message, "");
#ifndef WARPCHECK_TEST_ASAN
    EXPECT_EQ(run.results[1].message,
              "aborted (SIGABRT); its last line on standard error: \"assertion failed: x < 1\"");
#endif
    for (const Table& t : run.results[2].tables) EXPECT_EQ(t.title.find("Output of the warp"), std::string::npos);
}

TEST(CapturedOutput, KeepsTheHeadAndTheTailAndCountsTheRest) {
    CapturedOutput whole(4, 6), pieces(4, 6);
    const std::string text = "abcdefghijklmnop\nlast line\n";
    whole.append(text);
    for (char c : text) pieces.append(std::string(1, c));
    for (const CapturedOutput* out : {&whole, &pieces}) {
        EXPECT_EQ(out->total_bytes(), text.size());
        EXPECT_EQ(out->dropped_bytes(), text.size() - 10);
        EXPECT_EQ(out->text(), "abcd\n[... 17 bytes not kept ...]\n line\n");
        EXPECT_EQ(out->last_line(), "... line") << "the kept part of a line cut by the bound";
        EXPECT_EQ(out->text().size(), 10 + std::string("\n[... 17 bytes not kept ...]\n").size());
    }
    CapturedOutput whole_line(4, 6), whole_line_in_pieces(4, 6);
    whole_line.append("abcdefghij\nline\n\n");
    for (const char* piece : {"abcdefghij\n", "li", "ne\n", "\n"}) whole_line_in_pieces.append(piece);
    EXPECT_EQ(whole_line.last_line(), "line") << "a line that starts where the tail does is whole";
    EXPECT_EQ(whole_line_in_pieces.last_line(), "line");
    CapturedOutput small;
    small.append("a\nb");
    EXPECT_EQ(small.text(), "a\nb");
    EXPECT_EQ(small.dropped_bytes(), 0u);
    EXPECT_EQ(small.last_line(), "b");
    CheckResult r;
    attach_output(r, small, "stdout");
    ASSERT_EQ(r.tables.size(), 1u);
    EXPECT_EQ(r.tables[0].title, "Output of the warp (stdout)");
    EXPECT_EQ(r.tables[0].rows, (std::vector<std::vector<std::string>>{{"a"}, {"b"}}));
    attach_output(r, CapturedOutput{}, "stderr");
    EXPECT_EQ(r.tables.size(), 1u) << "an empty stream adds no table";
}

// The rule: the workers that run at once share the run's budget equally, so
// together they never hold more than it; by default the budget is the
// machine's memory, at most 8 GiB per worker.
TEST(Isolation, MemoryBudgetRule) {
    Isolation isolation;
    isolation.memory_budget = uint64_t{1} << 30;
    EXPECT_EQ(run_memory_budget(isolation, 4), uint64_t{1} << 30);
    EXPECT_EQ(worker_memory_limit(uint64_t{1} << 30, 4), uint64_t{256} << 20);
    EXPECT_EQ(worker_memory_limit(uint64_t{1} << 30, 1), uint64_t{1} << 30);
    EXPECT_EQ(worker_memory_limit(0, 4), 0u) << "0 is no limit";
    isolation.memory_budget.reset();
    const uint64_t machine = physical_memory();
    ASSERT_GT(machine, 0u);
    for (unsigned workers : {1u, 2u, 64u, 1024u}) {
        const uint64_t budget = run_memory_budget(isolation, workers);
        EXPECT_LE(budget, machine) << workers;
        EXPECT_LE(worker_memory_limit(budget, workers), kDefaultWorkerMemory) << workers;
        EXPECT_EQ(budget, std::min(machine, kDefaultWorkerMemory * workers)) << workers;
    }
}

#ifndef WARPCHECK_TEST_ASAN  // no memory limit under AddressSanitizer
void hold_700_mib() {
    static auto held = std::make_unique_for_overwrite<char[]>(std::size_t{700} << 20);
    (void)held;
}

// 700 MiB fits one worker's 1 GiB budget, not each of two workers' halves.
// (Each worker used to get the whole limit: both passed.)
TEST(Isolation, MemoryBudgetIsSharedByTheWorkersThatRunAtOnce) {
    std::vector<std::unique_ptr<WarpCase>> cases;
    cases.push_back(hostile("holds_a", hold_700_mib));
    cases.push_back(hostile("holds_b", hold_700_mib));
    const RunResult two = run_isolated(cases, 20, 2, uint64_t{1} << 30);
    for (const CheckResult& r : two.results) {
        EXPECT_EQ(r.verdict, Verdict::Error) << r.case_name;
        EXPECT_NE(r.message.find("ran out of memory (std::bad_alloc): the warp allocates without bound, or the check "
                                 "needs more than the 512 MiB of address space each worker may use "
                                 "(--memory-limit 1024 MiB, shared by the 2 workers that run at once)"),
                  std::string::npos)
            << r.message;
    }
    const RunResult one = run_isolated(cases, 20, 1, uint64_t{1} << 30);
    for (const CheckResult& r : one.results) EXPECT_EQ(r.verdict, Verdict::Pass) << r.case_name << ": " << r.message;
}
#endif

void kill_supervisor() {
    static bool done = false;
    if (!std::exchange(done, true)) ::kill(getppid(), SIGKILL);
}

void stop_supervisor() {
    static bool done = false;
    if (!std::exchange(done, true)) ::kill(getppid(), SIGSTOP);
}

// A warp that kills (or stops) the process that started its worker costs its
// own row, and the rest of the run goes on.
TEST(Isolation, AWarpThatKillsOrStopsItsSupervisorCostsOnlyItsRow) {
    const Watchdog watchdog(120);
    std::vector<std::unique_ptr<WarpCase>> cases;
    cases.push_back(hostile("stops_its_parent", stop_supervisor));
    cases.push_back(hostile("kills_its_parent", kill_supervisor));
    cases.push_back(make_warp_case({"fine", {}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()},
                                   UniformHemisphere{}));
    const RunResult run = run_isolated(cases, 10, 1);
    ASSERT_EQ(run.results.size(), 3u);
    EXPECT_EQ(run.results[0].verdict, Verdict::Pass) << run.results[0].message;
    EXPECT_EQ(run.results[1].verdict, Verdict::Error);
    EXPECT_EQ(run.results[1].message, "the worker supervisor process was killed by signal 9 (SIGKILL) while the check "
                                      "ran (did the warp kill its parent?); its worker died with it");
    EXPECT_EQ(run.results[2].verdict, Verdict::Pass) << run.results[2].message;
}

// In-process (--no-isolation), a warp's exit(0) used to end the program with
// status 0 and no report; now the run names the check and exits with status 1,
// whichever thread the warp calls it from.
void expect_exit_reported(void (*misbehave)(), const std::string& message) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    const auto warp = hostile("exits_in_process", misbehave);
    const auto check = make_roundtrip_check();
    RunOptions options;
    options.samples = 20'000;
    options.threads = 2;  // the check's loop runs on a pool thread too
    EXPECT_EXIT(run_jobs({{warp.get(), check.get()}}, options), ::testing::ExitedWithCode(1), message);
}

TEST(InProcessRun, AWarpsExitIsReportedWithStatus1) {
    const std::string named = "validate: the warp of case exits_in_process called exit\\(\\) during check roundtrip\n"
                              "The in-process run \\(--no-isolation\\) is abandoned and no report is written";
    expect_exit_reported([] { std::exit(0); }, named);
    expect_exit_reported([] { std::quick_exit(0); }, named);
    expect_exit_reported([] { std::thread([] { std::exit(0); }).join(); },
                         "validate: exit\\(\\) was called from a thread that runs no check; the checks running "
                         "were:\n  roundtrip exits_in_process\n");
}

// Many threads calling exit(0) at once: glibc runs each exit handler once, so
// without a copy of the handler for each of them a second thread's exit ended
// the process with status 0 while the first wrote the report (a CI failure).
void exit_from_eight_threads_at_once() {
    std::atomic<int> waiting{8};
    std::vector<std::thread> threads;
    for (int i = 0; i < 8; ++i)
        threads.emplace_back([&waiting] {
            waiting.fetch_sub(1);
            while (waiting.load() > 0) {
            }
            std::exit(0);
        });
    for (std::thread& t : threads) t.join();
}

TEST(InProcessRun, ExitFromManyThreadsAtOnceIsStillReportedWithStatus1) {
    for (int repeat = 0; repeat < 5; ++repeat)
        expect_exit_reported(exit_from_eight_threads_at_once,
                             "validate: exit\\(\\) was called from a thread that runs no check");
}

// A worker that sleeps is killed at 10x its CPU budget in wall time; one
// that works but gets little of a busy machine's CPU is left to its CPU limit
// (a spinning warp that got 4% of a core was once reported as asleep), up to
// 30x.
TEST(Isolation, WallBackstopSparesAWorkerThatWorks) {
    EXPECT_FALSE(past_wall_backstop(9.9, 0.0, 1));
    EXPECT_TRUE(past_wall_backstop(10.0, 0.0, 1)) << "asleep, blocked or stopped";
    EXPECT_TRUE(past_wall_backstop(10.0, 0.009, 1)) << "under 1% of a core";
    EXPECT_FALSE(past_wall_backstop(10.0, 0.04, 1)) << "working on a busy machine";
    EXPECT_FALSE(past_wall_backstop(29.9, 0.04, 1));
    EXPECT_TRUE(past_wall_backstop(30.0, 1.0, 1)) << "the hard stop";
    EXPECT_FALSE(past_wall_backstop(1799.0, 0.5, 60));
    EXPECT_TRUE(past_wall_backstop(600.0, 0.0, 60));
    EXPECT_TRUE(past_wall_backstop(600.0, std::nan(""), 60)) << "an unknown CPU time is no work";
}

// A case name with control bytes: shown escaped, rerun with bash's $'...'.
TEST(Isolation, ControlBytesInANameReachNoTerminal) {
    std::vector<std::unique_ptr<WarpCase>> cases;
    cases.push_back(make_warp_case({"bell\a[x=1]\x1b[2J", {}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()},
                                   UniformHemisphere{}));
    const RunResult run = run_isolated(cases);
    ASSERT_EQ(run.results.size(), 1u);
    EXPECT_NE(run.results[0].rerun_command.find(" --filter $'bell\\x07[x=1]\\x1b[2J' "), std::string::npos)
        << run.results[0].rerun_command;
    EXPECT_EQ(terminal_text(run.results[0].case_name), "bell\\x07[x=1]\\x1b[2J");
}


// A rejection loop that never accepts must not hang the run: its worker is
// killed when its CPU time budget runs out, and the other checks finish.
TEST(Isolation, SamplerThatNeverTerminatesIsAnErrorAfterItsBudget) {
    std::vector<std::unique_ptr<WarpCase>> cases;
    cases.push_back(hostile("never_accepts", [] {
        volatile float candidate = 0.5f;
        while (candidate < 2.0f) candidate = candidate * 0.5f;  // rejection that never accepts
    }));
    cases.push_back(make_warp_case({"fine", {}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()},
                                   UniformHemisphere{}));
    const RunResult run = run_isolated(cases, 1.0);
    ASSERT_EQ(run.results.size(), 2u);
    EXPECT_EQ(run.results[0].verdict, Verdict::Error);
    EXPECT_EQ(run.results[0].summary, "error: over time budget");
    // What is known: the CPU time used against the budget, and how to raise it.
    EXPECT_NE(run.results[0].message.find("over its CPU time budget of 1 s (the default; --time-budget SECONDS raises "
                                          "it): used "),
              std::string::npos)
        << run.results[0].message;
    EXPECT_NE(run.results[0].message.find(" s of CPU time and was killed. A check that is slow but finite passes "
                                          "with a larger budget or fewer --samples"),
              std::string::npos)
        << run.results[0].message;
    EXPECT_EQ(run.results[1].verdict, Verdict::Pass) << run.results[1].message;
    EXPECT_EQ(run.info.abandoned_checks, 1);
}

TEST(Isolation, ExitAndRunawayAllocationAreErrorRows) {
    std::vector<std::unique_ptr<WarpCase>> cases;
    cases.push_back(make_warp_case({"fine", {}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()},
                                   UniformHemisphere{}));
    cases.push_back(hostile("exits0", [] { std::exit(0); }));
    cases.push_back(hostile("exits3", [] { std::exit(3); }));
#ifndef WARPCHECK_TEST_ASAN
    cases.push_back(hostile("allocates", [] {
        static std::vector<std::vector<char>> hoard;
        for (;;) hoard.emplace_back(std::size_t{64} << 20);
    }));
#endif
    const RunResult run = run_isolated(cases);
    ASSERT_EQ(run.results.size(), cases.size());
    EXPECT_EQ(run.results[0].verdict, Verdict::Pass) << run.results[0].message;
    for (std::size_t i = 1; i < cases.size(); ++i) EXPECT_EQ(run.results[i].verdict, Verdict::Error);
#ifndef WARPCHECK_TEST_ASAN
    EXPECT_EQ(run.results[1].message, "called exit(0) before returning a result");
    EXPECT_EQ(run.results[2].message, "exited with status 3 before returning a result");
#else  // LeakSanitizer checks at exit() and may change the status
    EXPECT_NE(run.results[1].message.find("before returning a result"), std::string::npos);
    EXPECT_NE(run.results[2].message.find("before returning a result"), std::string::npos);
#endif
    EXPECT_EQ(run.results[1].case_name, "exits0");
#ifndef WARPCHECK_TEST_ASAN
    EXPECT_NE(run.results[3].message.find("ran out of memory"), std::string::npos) << run.results[3].message;
#endif
}

#ifndef WARPCHECK_TEST_ASAN  // AddressSanitizer catches SIGSEGV itself and exits instead
TEST(Isolation, CrashesAreErrorRowsNamingTheSignal) {
    std::vector<std::unique_ptr<WarpCase>> cases;
    cases.push_back(hostile("segfaults", [] { std::raise(SIGSEGV); }));
    cases.push_back(hostile("aborts", [] { std::abort(); }));
    cases.push_back(make_warp_case({"fine", {}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()},
                                   UniformHemisphere{}));
    const RunResult run = run_isolated(cases);
    ASSERT_EQ(run.results.size(), 3u);
    EXPECT_EQ(run.results[0].message, "killed by signal 11 (SIGSEGV)");
    EXPECT_EQ(run.results[1].message, "aborted (SIGABRT)");
    EXPECT_EQ(run.results[2].verdict, Verdict::Pass) << run.results[2].message;
}
#endif

}  // namespace
}  // namespace warpcheck

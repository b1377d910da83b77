#include "reports/progress.h"

#include <sys/ioctl.h>
#include <unistd.h>

#include <cmath>
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "reports/text.h"

namespace warpcheck {
namespace {

constexpr auto kMinRedrawInterval = std::chrono::milliseconds(50);
constexpr std::string_view kClearLine = "\r\x1b[K";
constexpr std::size_t kBarCells = 20;

std::size_t terminal_width(int fd) {
    winsize size{};
    if (::ioctl(fd, TIOCGWINSZ, &size) == 0 && size.ws_col > 0) return size.ws_col;
    return 80;
}

/// "[=======>            ]" for the fraction done.
std::string bar(std::size_t done, std::size_t total) {
    const std::size_t filled = total > 0 ? done * kBarCells / total : 0;
    std::string cells(kBarCells, ' ');
    for (std::size_t i = 0; i < filled; ++i) cells[i] = '=';
    if (filled < kBarCells && filled > 0) cells[filled] = '>';
    return "[" + cells + "]";
}

/// A finished row in the table's words: "FAIL   chi2  power[n=2]  chi2 812.3 dof 40 p 3e-90".
std::string row_text(Verdict verdict, const ProgressStep& step) {
    return printable(fmt::format("{:<5}  {}  {}  {}", to_string(verdict), step.check, step.case_name,
                                 step.result ? step.result->summary : std::string()));
}

}  // namespace

std::optional<ProgressMode> progress_mode(std::string_view name, bool terminal) {
    if (name == "auto") return terminal ? ProgressMode::Bar : ProgressMode::Log;
    if (name == "bar") return ProgressMode::Bar;
    if (name == "log") return ProgressMode::Log;
    if (name == "none") return ProgressMode::Off;
    return std::nullopt;
}

Verdict progress_verdict(const CheckResult& result, double level) {
    // The runner's rule (runner.cpp, apply_multiple_test_correction): a passing
    // row with a p-value fails when the p-value is not at least the level; NaN fails.
    if (result.verdict == Verdict::Pass && result.p_value && level > 0.0 && !(*result.p_value >= level))
        return Verdict::Fail;
    return result.verdict;
}

ProgressDisplay::ProgressDisplay(std::ostream& out, Options options)
    : out_(&out), options_(std::move(options)), start_(options_.now()), last_line_(start_) {}

ProgressDisplay::~ProgressDisplay() { finish(); }

std::string ProgressDisplay::facts(const ProgressStep& step, std::string_view separator) const {
    const double elapsed = std::chrono::duration<double>(options_.now() - start_).count();
    // The jobs left at the mean pace so far: rough, as jobs differ in cost.
    const double left = step.done > 0 && step.total >= step.done
                            ? elapsed / static_cast<double>(step.done) * static_cast<double>(step.total - step.done)
                            : std::nan("");
    return fmt::format("{} elapsed{}ETA {}{}{} failed", format_clock(elapsed), separator, format_clock(left),
                       separator, failed_);
}

void ProgressDisplay::operator()(const ProgressStep& step) {
    std::lock_guard lock(mutex_);
    if (options_.mode == ProgressMode::Off || finished_) return;
    done_ = step.done;
    total_ = step.total;
    const Verdict verdict = step.result ? progress_verdict(*step.result, options_.level) : Verdict::Pass;
    if (verdict == Verdict::Fail || verdict == Verdict::Error) {
        ++failed_;
        const std::string row = row_text(verdict, step);
        if (options_.mode == ProgressMode::Bar) {
            clear_bar();
            *out_ << fit_columns(row, options_.width > 1 ? options_.width - 1 : 1) << "\n";
        } else {
            *out_ << options_.program << ": " << row << "\n";
            logged_ = true;
        }
        *out_ << std::flush;
    }
    const bool last = step.total > 0 && step.done >= step.total;  // the closing line says the rest
    if (options_.mode == ProgressMode::Bar) draw_bar(step);
    else if (!last) log_line(step, false);
    if (last) finish_locked();
}

void ProgressDisplay::draw_bar(const ProgressStep& step) {
    const auto now = options_.now();
    if (bar_shown_ && now - last_line_ < kMinRedrawInterval) return;
    last_line_ = now;
    const int digits = static_cast<int>(fmt::formatted_size("{}", step.total));
    const unsigned percent =
        step.total > 0 ? static_cast<unsigned>(100.0 * static_cast<double>(step.done) / static_cast<double>(step.total))
                       : 0;
    const std::string line = fmt::format("{} {:>{}}/{} {:>3}%  {}  {} {}", bar(step.done, step.total), step.done,
                                         digits, step.total, percent, facts(step, "  "), step.check, step.case_name);
    // One column short of the width, so that the cursor never wraps to a new line.
    *out_ << kClearLine << fit_columns(printable(line), options_.width > 1 ? options_.width - 1 : 1) << std::flush;
    bar_shown_ = true;
}

void ProgressDisplay::log_line(const ProgressStep& step, bool closing) {
    const auto now = options_.now();
    const unsigned tenth = step.total > 0 ? static_cast<unsigned>(10 * step.done / step.total) : 0;
    const bool quiet = now - start_ < options_.log_quiet || now - last_line_ < options_.log_quiet;
    const bool due = now - last_line_ >= options_.log_every || tenth > last_tenth_;
    if (!closing && (quiet || !due)) return;
    last_line_ = now;
    last_tenth_ = tenth;
    const unsigned percent = step.total > 0 ? static_cast<unsigned>(100 * step.done / step.total) : 0;
    if (closing)
        *out_ << fmt::format("{}: {}/{} done in {}, {} failed\n", options_.program, step.done, step.total,
                             format_clock(std::chrono::duration<double>(now - start_).count()), failed_);
    else
        *out_ << fmt::format("{}: {}/{} done ({}%), {}\n", options_.program, step.done, step.total, percent,
                             facts(step, ", "));
    *out_ << std::flush;
    logged_ = true;
}

void ProgressDisplay::clear_bar() {
    if (bar_shown_) *out_ << kClearLine << std::flush;
    bar_shown_ = false;
}

void ProgressDisplay::finish() {
    std::lock_guard lock(mutex_);
    finish_locked();
}

void ProgressDisplay::finish_locked() {
    if (finished_) return;
    finished_ = true;
    if (options_.mode == ProgressMode::Bar) clear_bar();
    if (options_.mode == ProgressMode::Log && logged_) log_line({done_, total_, {}, {}, nullptr}, true);
}

ProgressCallback stderr_progress(ProgressDisplay::Options options) {
    if (options.mode == ProgressMode::Off) return {};
    if (options.mode == ProgressMode::Bar) options.width = terminal_width(STDERR_FILENO);
    auto display = std::make_shared<ProgressDisplay>(std::cerr, std::move(options));
    return [display](const ProgressStep& step) { (*display)(step); };
}

}  // namespace warpcheck

// Progress of a run on stderr, in two forms with the same facts (jobs done of
// all, elapsed time, an estimate of the time left, failures so far):
//
// - on a terminal, a bar redrawn in place, cleared when the run is done:
//     [=======>            ]  123/304  40%  0:12 elapsed  ETA 0:18  0 failed  chi2 cosine_hemisphere
// - in a CI log (stderr not a terminal), a plain line every 10 seconds or
//   every tenth of the run, whichever comes first (none in the first 2 s, so
//   a short run prints nothing but its failures), and a closing line:
//     validate: 123/304 done (40%), 0:12 elapsed, ETA 0:18, 0 failed
//
// In both, a row that fails or errors is printed as soon as its job ends, in
// the table's form ("FAIL  chi2  case  key figure"), so that a long run shows
// its problems early; the table after the run shows every row in order.
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <iosfwd>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include "reports/progress_callback.h"

namespace warpcheck {

enum class ProgressMode {
    Off,  ///< nothing
    Bar,  ///< a bar redrawn in place (a terminal)
    Log,  ///< plain lines (a CI log, a file, a pipe)
};

/// "auto" (Bar on a terminal, else Log), "bar", "log" or "none"; nullopt for
/// anything else.
std::optional<ProgressMode> progress_mode(std::string_view name, bool terminal);

class ProgressDisplay {
public:
    using Clock = std::chrono::steady_clock;

    struct Options {
        ProgressMode mode = ProgressMode::Log;
        std::size_t width = 80;  ///< Bar: the terminal's columns (lines are cut one short, never wrapping)
        /// The run's per-test significance level: a statistical row whose
        /// p-value is below it (or NaN) counts as failed, as the runner judges it
        /// after the run. 0: p-values are not judged here.
        double level = 0.0;
        std::string program = "validate";  ///< Log: the prefix of each line
        std::chrono::milliseconds log_every{10'000};  ///< Log: the longest silence once lines have begun
        std::chrono::milliseconds log_quiet{2'000};   ///< Log: no line sooner after the start or the previous one
        std::function<Clock::time_point()> now = [] { return Clock::now(); };  ///< the clock (tests set their own)
    };

    ProgressDisplay(std::ostream& out, Options options);
    ~ProgressDisplay();
    ProgressDisplay(const ProgressDisplay&) = delete;
    ProgressDisplay& operator=(const ProgressDisplay&) = delete;

    /// Reports one finished job; the last one (done == total) calls finish().
    void operator()(const ProgressStep& step);

    /// Clears the bar, or writes the closing line of a Log that wrote any.
    /// Later calls do nothing.
    void finish();

private:
    void draw_bar(const ProgressStep& step);
    void log_line(const ProgressStep& step, bool closing);
    std::string facts(const ProgressStep& step, std::string_view separator) const;
    void clear_bar();
    void finish_locked();

    std::ostream* out_;
    Options options_;
    Clock::time_point start_, last_line_{};
    std::size_t failed_ = 0, done_ = 0, total_ = 0;
    unsigned last_tenth_ = 0;
    bool bar_shown_ = false, logged_ = false, finished_ = false;
    std::mutex mutex_;
};

/// A callback that shows progress on stderr in `options.mode` (width: the
/// terminal's, for a bar); it finishes the display after the last job, or when
/// the last copy of the callback is destroyed.
ProgressCallback stderr_progress(ProgressDisplay::Options options);

/// The kind of row a finished job gives, with `level` applied as above.
Verdict progress_verdict(const CheckResult& result, double level);

}  // namespace warpcheck

// Progress of a long run on stderr, for people watching a terminal:
//   [ 12/140]   8%  chi2  trowbridge_reitz[alpha=0.3]
// redrawn in place, and the line cleared when the run is done. When stderr is
// not a terminal (CI logs, pipes) nothing at all is written.
#pragma once

#include <chrono>
#include <cstddef>
#include <iosfwd>
#include <memory>
#include <mutex>
#include <string>

#include "reports/progress_callback.h"

namespace warpcheck {

class ProgressLine {
public:
    /// Draws on stderr if, and only if, stderr is a terminal.
    ProgressLine();
    /// Draws on `out` if `enabled`, lines cut to `width` columns (for tests).
    ProgressLine(std::ostream& out, bool enabled, std::size_t width);
    ~ProgressLine();
    ProgressLine(const ProgressLine&) = delete;
    ProgressLine& operator=(const ProgressLine&) = delete;

    bool enabled() const { return enabled_; }

    /// Redraws the line (at most every 50 ms, except for the last step). Safe to
    /// call from several threads. Clears the line once done == total.
    void operator()(std::size_t done, std::size_t total, const std::string& what);

    /// Clears the line if one is shown; the next update draws a new one.
    void clear();

private:
    std::ostream* out_;
    bool enabled_;
    std::size_t width_;
    bool shown_ = false;
    std::chrono::steady_clock::time_point last_draw_{};
    std::mutex mutex_;
};

/// A callback that draws on stderr when it is a terminal and is a no-op
/// otherwise; it clears its line when the last step is reported or when the
/// last copy of the callback is destroyed.
ProgressCallback stderr_progress();

}  // namespace warpcheck

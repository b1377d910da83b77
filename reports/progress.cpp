#include "reports/progress.h"

#include <sys/ioctl.h>
#include <unistd.h>

#include <iostream>

#include <fmt/format.h>

namespace warpcheck {
namespace {

constexpr auto kMinRedrawInterval = std::chrono::milliseconds(50);
constexpr std::string_view kClearLine = "\r\x1b[K";

std::size_t terminal_width(int fd) {
    winsize size{};
    if (::ioctl(fd, TIOCGWINSZ, &size) == 0 && size.ws_col > 0) return size.ws_col;
    return 80;
}

/// Cuts `text` to at most `columns` characters, counting UTF-8 sequences as one
/// column each (never splitting a sequence), and marks the cut with "…".
std::string fit(const std::string& text, std::size_t columns) {
    const auto is_lead = [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; };
    std::size_t characters = 0;
    for (char c : text) characters += is_lead(c);
    if (characters <= columns) return text;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (is_lead(text[i]) && kept++ == columns - 1) return text.substr(0, i) + "\xE2\x80\xA6";
    }
    return text;
}

}  // namespace

ProgressLine::ProgressLine()
    : out_(&std::cerr), enabled_(::isatty(STDERR_FILENO) == 1), width_(enabled_ ? terminal_width(STDERR_FILENO) : 80) {}

ProgressLine::ProgressLine(std::ostream& out, bool enabled, std::size_t width)
    : out_(&out), enabled_(enabled), width_(width) {}

ProgressLine::~ProgressLine() { clear(); }

void ProgressLine::operator()(std::size_t done, std::size_t total, const std::string& what) {
    if (!enabled_) return;
    std::lock_guard lock(mutex_);
    if (total > 0 && done >= total) {
        if (shown_) *out_ << kClearLine << std::flush;
        shown_ = false;
        return;
    }
    const auto now = std::chrono::steady_clock::now();
    if (shown_ && now - last_draw_ < kMinRedrawInterval) return;
    last_draw_ = now;

    const int digits = static_cast<int>(fmt::formatted_size("{}", total));
    const unsigned percent = total > 0 ? static_cast<unsigned>(100.0 * static_cast<double>(done) / static_cast<double>(total)) : 0;
    std::string line = fmt::format("[{:>{}}/{}] {:>3}%  {}", done, digits, total, percent, what);
    // One column short of the width, so that the cursor never wraps to a new line.
    line = fit(line, width_ > 1 ? width_ - 1 : 1);
    *out_ << kClearLine << line << std::flush;
    shown_ = true;
}

void ProgressLine::clear() {
    if (!enabled_) return;
    std::lock_guard lock(mutex_);
    if (shown_) *out_ << kClearLine << std::flush;
    shown_ = false;
}

ProgressCallback stderr_progress() {
    auto line = std::make_shared<ProgressLine>();
    if (!line->enabled()) return [](std::size_t, std::size_t, const std::string&) {};
    return [line](std::size_t done, std::size_t total, const std::string& what) { (*line)(done, total, what); };
}

}  // namespace warpcheck

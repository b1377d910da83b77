// What a warp writes to standard output and standard error in its worker: kept
// per job, bounded, and shown in the job's row (a table of its lines), never
// mixed into the tool's own output (a `--json -` stays parseable).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "reports/result.h"

namespace warpcheck {

/// The bytes of one stream, bounded: the first `head_limit` bytes and the last
/// `tail_limit`, with the count of those in between that were not kept. A warp
/// that prints without end costs the run a fixed amount of memory, and the row
/// still shows how its output began and how it ended (an assertion's message
/// before an abort is usually the last line).
class CapturedOutput {
public:
    static constexpr std::size_t kDefaultHead = 8 * 1024, kDefaultTail = 8 * 1024;

    explicit CapturedOutput(std::size_t head_limit = kDefaultHead, std::size_t tail_limit = kDefaultTail)
        : head_limit_(head_limit), tail_limit_(tail_limit) {}

    void append(std::string_view bytes);

    bool empty() const { return total_ == 0; }
    /// Every byte written, kept or not.
    uint64_t total_bytes() const { return total_; }
    /// The bytes written and not kept (between the head and the tail).
    uint64_t dropped_bytes() const { return total_ - head_.size() - tail_.size(); }
    /// The kept bytes, head then tail, with one line in between that says how
    /// many bytes were left out there (if any were).
    std::string text() const;
    /// The last non-empty line written, without its newline (empty if none;
    /// "..." and its kept end if the bound cut its start off).
    std::string last_line() const;

private:
    std::size_t head_limit_, tail_limit_;
    std::string head_;
    std::string tail_;  // the last tail_limit_ bytes after the head, in order
    char before_tail_ = '\n';  // the byte written just before the tail's first
    uint64_t total_ = 0;
};

/// A table of `output`'s lines titled "Output of the warp (<stream>)" (stdout,
/// stderr), for a row's evidence; nothing when the stream was empty.
void attach_output(CheckResult& result, const CapturedOutput& output, std::string_view stream);

}  // namespace warpcheck

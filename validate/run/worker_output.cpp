#include "validate/run/worker_output.h"

#include <algorithm>

#include <fmt/format.h>

namespace warpcheck {

void CapturedOutput::append(std::string_view bytes) {
    total_ += bytes.size();
    const std::size_t to_head = std::min(bytes.size(), head_limit_ - head_.size());
    head_.append(bytes.substr(0, to_head));
    bytes.remove_prefix(to_head);
    if (bytes.empty() || tail_limit_ == 0) return;
    if (tail_.empty()) before_tail_ = head_.empty() ? '\n' : head_.back();
    // Only the last tail_limit_ bytes of the tail and this write can survive.
    if (bytes.size() >= tail_limit_) {
        const std::size_t start = bytes.size() - tail_limit_;
        if (start > 0) before_tail_ = bytes[start - 1];
        else if (!tail_.empty()) before_tail_ = tail_.back();
        tail_.assign(bytes.substr(start));
        return;
    }
    const std::size_t drop = tail_.size() - std::min(tail_.size(), tail_limit_ - bytes.size());
    if (drop > 0) before_tail_ = tail_[drop - 1];
    tail_.erase(0, drop);
    tail_.append(bytes);
}

std::string CapturedOutput::text() const {
    if (dropped_bytes() == 0) return head_ + tail_;
    std::string joint = head_;
    if (!joint.empty() && joint.back() != '\n') joint += '\n';
    joint += fmt::format("[... {} bytes not kept ...]\n", dropped_bytes());
    return joint + tail_;
}

std::string CapturedOutput::last_line() const {
    // With bytes left out, only the tail is one piece of text.
    const std::string kept = dropped_bytes() > 0 ? tail_ : head_ + tail_;
    const std::size_t end = kept.find_last_not_of("\r\n");
    if (end == std::string::npos) return {};
    const std::size_t newline = kept.find_last_of('\n', end);
    const std::size_t start = newline == std::string::npos ? 0 : newline + 1;
    const bool cut = newline == std::string::npos && dropped_bytes() > 0 && before_tail_ != '\n';
    return (cut ? "..." : "") + kept.substr(start, end + 1 - start);
}

void attach_output(CheckResult& result, const CapturedOutput& output, std::string_view stream) {
    if (output.empty()) return;
    Table table;
    table.title = fmt::format("Output of the warp ({})", stream);
    table.columns = {"line"};
    const std::string text = output.text();
    for (std::size_t start = 0; start < text.size();) {
        std::size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        table.rows.push_back({text.substr(start, end - start)});
        start = end + 1;
    }
    result.tables.push_back(std::move(table));
}

}  // namespace warpcheck

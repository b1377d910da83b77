#include "validate/cli/cli_input.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <numeric>
#include <optional>
#include <utility>

#include <fmt/format.h>

#include "validate/checks/check.h"

namespace warpcheck {
namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }

/// The parts of a number as written: all its digits (the separators dropped),
/// and the power of ten they are scaled by. False if `text` is not one.
struct Decimal {
    std::string digits;
    long long exponent = 0;
};

bool read_digits(std::string_view text, std::size_t& i, std::string& digits, bool separators) {
    const std::size_t start = i;
    while (i < text.size()) {
        if (is_digit(text[i])) {
            digits += text[i++];
        } else if (separators && (text[i] == '_' || text[i] == '\'') && i > start && i + 1 < text.size() &&
                   is_digit(text[i + 1])) {
            ++i;  // a separator between two digits
        } else {
            break;
        }
    }
    return i > start;
}

int suffix_exponent(char c) {
    switch (c) {
        case 'k': case 'K': return 3;
        case 'M': return 6;
        case 'G': return 9;
        case 'T': return 12;
        default: return -1;
    }
}

bool read_decimal(std::string_view text, Decimal& d) {
    std::size_t i = 0;
    const bool whole = read_digits(text, i, d.digits, true);
    bool fraction = false;
    if (i < text.size() && text[i] == '.') {
        ++i;
        const std::size_t before = d.digits.size();
        fraction = read_digits(text, i, d.digits, false);
        d.exponent -= static_cast<long long>(d.digits.size() - before);
    }
    if (!whole && !fraction) return false;
    if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
        ++i;
        const bool negative = i < text.size() && text[i] == '-';
        if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
        std::string power;
        if (!read_digits(text, i, power, false) || power.size() > 4) return false;
        d.exponent += negative ? -std::stoll(power) : std::stoll(power);
    }
    if (i + 1 == text.size() && suffix_exponent(text[i]) >= 0) d.exponent += suffix_exponent(text[i++]);
    return i == text.size();
}

constexpr const char* kCountForms = "1000000, 1_000_000, 1e6 or 1M";

}  // namespace

ParsedCount parse_count(std::string_view text) {
    ParsedCount out;
    Decimal d;
    if (!read_decimal(text, d)) {
        out.problem = fmt::format("'{}' is not a count (write it as {})", text, kCountForms);
        return out;
    }
    // Digits below the decimal point must be zeros: a count is whole.
    std::string digits = d.digits;
    digits.erase(0, std::min(digits.find_first_not_of('0'), digits.size()));
    for (; d.exponent < 0 && !digits.empty(); ++d.exponent) {
        if (digits.back() != '0') {
            out.problem = fmt::format("'{}' is not a whole number", text);
            return out;
        }
        digits.pop_back();
    }
    if (digits.empty()) return out;  // zero, however written
    digits.append(static_cast<std::size_t>(std::min<long long>(d.exponent, 21)), '0');
    for (char c : digits) {
        const uint64_t digit = static_cast<uint64_t>(c - '0');
        if (out.value > (UINT64_MAX - digit) / 10) {
            out.problem = fmt::format("'{}' is too large (at most {})", text, format_count(UINT64_MAX));
            out.value = 0;
            return out;
        }
        out.value = out.value * 10 + digit;
    }
    return out;
}

ParsedCount parse_count_in(std::string_view text, uint64_t min, uint64_t max) {
    ParsedCount out = parse_count(text);
    if (out.problem.empty() && (out.value < min || out.value > max))
        out.problem = fmt::format("{} is out of range: give {} to {}", format_count(out.value), format_count(min),
                                  format_count(max));
    return out;
}

ParsedReal parse_real_in(std::string_view text, double min, double max) {
    ParsedReal out;
    const char* end = text.data() + text.size();
    const auto [at, error] = std::from_chars(text.data(), end, out.value);
    if (text.empty() || error != std::errc() || at != end || !std::isfinite(out.value)) {
        out.problem = fmt::format("'{}' is not a finite number", text);
    } else if (!(out.value >= min && out.value <= max)) {
        out.problem = fmt::format("{} is out of range: give {} to {}", text, format_limit(min), format_limit(max));
    }
    return out;
}

std::string format_count(uint64_t value) {
    const std::string digits = std::to_string(value);
    std::string out;
    for (std::size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

std::string format_limit(double value) { return fmt::format("{}", value); }

std::size_t edit_distance(std::string_view a, std::string_view b) {
    // Rows i-2, i-1 and i of the optimal-string-alignment table.
    std::vector<std::size_t> two(b.size() + 1), one(b.size() + 1), row(b.size() + 1);
    std::iota(one.begin(), one.end(), std::size_t{0});
    for (std::size_t i = 1; i <= a.size(); ++i) {
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            row[j] = std::min({one[j] + 1, row[j - 1] + 1, one[j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) row[j] = std::min(row[j], two[j - 2] + 1);
        }
        std::swap(two, one);
        std::swap(one, row);
    }
    return one[b.size()];
}

std::size_t substring_edit_distance(std::string_view pattern, std::string_view text) {
    // As edit_distance with pattern down the rows, but a match may start and
    // end anywhere in text: row 0 is free, and the answer is the last row's minimum.
    std::vector<std::size_t> two(text.size() + 1, 0), one(text.size() + 1, 0), row(text.size() + 1);
    for (std::size_t i = 1; i <= pattern.size(); ++i) {
        row[0] = i;
        for (std::size_t j = 1; j <= text.size(); ++j) {
            const std::size_t cost = pattern[i - 1] == text[j - 1] ? 0 : 1;
            row[j] = std::min({one[j] + 1, row[j - 1] + 1, one[j - 1] + cost});
            if (i > 1 && j > 1 && pattern[i - 1] == text[j - 2] && pattern[i - 2] == text[j - 1])
                row[j] = std::min(row[j], two[j - 2] + 1);
        }
        std::swap(two, one);
        std::swap(one, row);
    }
    return pattern.empty() ? 0 : *std::min_element(one.begin(), one.end());
}

std::vector<std::string> closest_names(std::string_view typed, const std::vector<std::string>& candidates,
                                       bool substring, std::size_t limit) {
    const std::size_t allowed = std::max<std::size_t>(1, typed.size() / 3);
    std::size_t best = allowed;
    std::vector<std::pair<std::size_t, std::string>> near;  // (whole-name distance, name) at the best distance
    for (const std::string& c : candidates) {
        const std::size_t d = substring ? substring_edit_distance(typed, c) : edit_distance(typed, c);
        if (d > best) continue;  // beyond the allowed distance, or farther than one already found
        if (d < best) near.clear();
        best = d;
        if (std::none_of(near.begin(), near.end(), [&](const auto& n) { return n.second == c; }))
            near.emplace_back(edit_distance(typed, c), c);
    }
    // Of the candidates as close as any, those nearest as whole names first.
    std::stable_sort(near.begin(), near.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::string> names;
    for (std::size_t i = 0; i < near.size() && i < limit; ++i) names.push_back(near[i].second);
    return names;
}

std::string apply_environment_settings(RunOptions& run, std::optional<uint64_t>* memory_limit_mib) {
    const auto variable = [](const char* name) -> std::optional<std::string> {
        const char* value = std::getenv(name);
        if (!value || !*value) return std::nullopt;
        return std::string(value);
    };
    const auto problem = [](const char* name, const std::string& value, const std::string& why) {
        // The parsers' messages start with the value itself; say it once, with the variable.
        const std::string quoted = "'" + value + "' ";
        if (why.starts_with(quoted)) return fmt::format("{}='{}' {}", name, value, why.substr(quoted.size()));
        return fmt::format("{}='{}': {}", name, value, why);
    };
    if (const auto text = variable("WARPCHECK_SEED")) {
        const ParsedCount c = parse_count(*text);
        // As --seed says it: a seed is not "a count".
        if (!c.problem.empty())
            return fmt::format("WARPCHECK_SEED='{}' is not a seed: give a whole number from 0 to {}", *text,
                               format_count(UINT64_MAX));
        run.seed = c.value;
    }
    if (const auto text = variable("WARPCHECK_SAMPLES")) {
        const ParsedCount c = parse_count_in(*text, kMinSamples, kMaxSamples);
        if (!c.problem.empty()) return problem("WARPCHECK_SAMPLES", *text, c.problem);
        run.samples = c.value;
    }
    if (const auto text = variable("WARPCHECK_ALPHA")) {
        const ParsedReal r = parse_real_in(*text, kMinAlpha, kMaxAlpha);
        if (!r.problem.empty()) return problem("WARPCHECK_ALPHA", *text, r.problem);
        run.alpha = r.value;
    }
    if (const auto text = variable("WARPCHECK_TIME_BUDGET")) {
        const ParsedReal r = parse_real_in(*text, kMinBudget, kMaxBudget);
        if (!r.problem.empty()) return problem("WARPCHECK_TIME_BUDGET", *text, r.problem + " (seconds)");
        run.check_time_budget = r.value;
        run.time_budget_set = true;
    }
    if (const auto text = variable("WARPCHECK_MEMORY_LIMIT"); text && memory_limit_mib) {
        const ParsedCount c = parse_count_in(*text, 0, kMaxMemoryMib);
        if (!c.problem.empty()) return problem("WARPCHECK_MEMORY_LIMIT", *text, c.problem + " (MiB)");
        *memory_limit_mib = c.value;
    }
    return "";
}

std::string did_you_mean(const std::vector<std::string>& suggestions) {
    if (suggestions.empty()) return "";
    std::string list = "'" + suggestions.front() + "'";
    for (std::size_t i = 1; i < suggestions.size(); ++i)
        list += (i + 1 == suggestions.size() ? " or '" : ", '") + suggestions[i] + "'";
    return " (did you mean " + list + "?)";
}

}  // namespace warpcheck

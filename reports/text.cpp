#include "reports/text.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <fmt/format.h>

namespace warpcheck {
namespace {

constexpr std::string_view kReplacement = "\xEF\xBF\xBD";  // U+FFFD in UTF-8

/// Length of the valid UTF-8 sequence that starts `text`, or 0 if it is not one.
/// Rejects overlong forms, surrogates and code points above U+10FFFF.
std::size_t utf8_sequence_length(std::string_view text, char32_t& code_point) {
    const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
    const unsigned char lead = byte(0);
    std::size_t length = 0;
    char32_t min = 0;
    if (lead < 0x80) {
        code_point = lead;
        return 1;
    } else if ((lead & 0xE0) == 0xC0) {
        length = 2, code_point = lead & 0x1F, min = 0x80;
    } else if ((lead & 0xF0) == 0xE0) {
        length = 3, code_point = lead & 0x0F, min = 0x800;
    } else if ((lead & 0xF8) == 0xF0) {
        length = 4, code_point = lead & 0x07, min = 0x10000;
    } else {
        return 0;
    }
    if (text.size() < length) return 0;
    for (std::size_t i = 1; i < length; ++i) {
        if ((byte(i) & 0xC0) != 0x80) return 0;
        code_point = (code_point << 6) | (byte(i) & 0x3F);
    }
    if (code_point < min || code_point > 0x10FFFF || (code_point >= 0xD800 && code_point <= 0xDFFF)) return 0;
    return length;
}

bool allowed_in_xml(char32_t c) {
    if (c < 0x20) return c == '\t' || c == '\n' || c == '\r';
    return c != 0xFFFE && c != 0xFFFF;
}

}  // namespace

void append_escaped(std::string& out, std::string_view text) {
    out.reserve(out.size() + text.size());
    while (!text.empty()) {
        char32_t c = 0;
        const std::size_t length = utf8_sequence_length(text, c);
        if (length == 0) {  // one invalid byte: replace it and resynchronise on the next
            out += kReplacement;
            text.remove_prefix(1);
            continue;
        }
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&#39;"; break;
            default:
                if (allowed_in_xml(c))
                    out.append(text.substr(0, length));
                else
                    out += kReplacement;
        }
        text.remove_prefix(length);
    }
}

std::string escaped(std::string_view text) {
    std::string out;
    append_escaped(out, text);
    return out;
}

std::string format_number(double value) {
    if (std::isnan(value)) return "NaN";
    if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
    if (value == std::floor(value) && std::abs(value) < 1e15) return fmt::format("{:.0f}", value);
    return fmt::format("{:.6g}", value);
}

std::string format_grouped(double value) {
    std::string plain = format_number(value);
    const std::size_t first_digit = plain[0] == '-' ? 1 : 0;
    if (plain.find_first_not_of("0123456789", first_digit) != std::string::npos || plain.size() - first_digit < 5) return plain;
    std::string grouped = plain.substr(0, first_digit);
    const std::size_t digits = plain.size() - first_digit;
    for (std::size_t i = 0; i < digits; ++i) {
        if (i > 0 && (digits - i) % 3 == 0) grouped += "\u202f";
        grouped += plain[first_digit + i];
    }
    return grouped;
}

std::string format_probability(double p) {
    if (std::isnan(p)) return "NaN";
    if (p == 0.0) return "< 1e-300";
    if (p >= 0.001) return fmt::format("{:.3g}", p);
    return fmt::format("{:.2e}", p);
}

std::string format_seconds(double seconds) {
    if (std::isnan(seconds)) return "NaN";
    if (seconds < 0.01) return fmt::format("{:.2f} ms", seconds * 1000.0);
    if (seconds < 1.0) return fmt::format("{:.0f} ms", seconds * 1000.0);
    if (seconds < 60.0) return fmt::format("{:.1f} s", seconds);
    const auto whole = static_cast<std::int64_t>(std::llround(seconds));
    if (whole < 3600) return fmt::format("{} min {} s", whole / 60, whole % 60);
    return fmt::format("{} h {} min", whole / 3600, whole / 60 % 60);
}

}  // namespace warpcheck

namespace warpcheck {

std::string format_clock(double seconds) {
    if (!(seconds >= 0.0 && seconds < 1e9)) return "--:--";
    const auto whole = static_cast<std::int64_t>(seconds);
    if (whole < 3600) return fmt::format("{}:{:02}", whole / 60, whole % 60);
    return fmt::format("{}:{:02}:{:02}", whole / 3600, whole / 60 % 60, whole % 60);
}

namespace {

bool starts_character(char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }

}  // namespace

std::size_t display_width(std::string_view text) {
    return static_cast<std::size_t>(std::count_if(text.begin(), text.end(), starts_character));
}

std::string fit_columns(std::string_view text, std::size_t columns) {
    if (display_width(text) <= columns) return std::string(text);
    if (columns == 0) return {};
    std::size_t kept = 0;
    for (std::size_t i = 0; i < text.size(); ++i)
        if (starts_character(text[i]) && kept++ == columns - 1) return std::string(text.substr(0, i)) + "\xE2\x80\xA6";
    return std::string(text);
}

namespace {

// The length of the valid UTF-8 sequence at the start of `text` that is not a
// control character, or 0.
std::size_t printable_sequence(std::string_view text) {
    const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
    const unsigned char lead = byte(0);
    if (lead >= 0x20 && lead < 0x7F) return 1;
    const std::size_t length = lead >= 0xC2 && lead <= 0xDF ? 2 : lead >= 0xE0 && lead <= 0xEF ? 3
                               : lead >= 0xF0 && lead <= 0xF4                 ? 4
                                                                              : 0;
    if (length == 0 || text.size() < length) return 0;
    for (std::size_t i = 1; i < length; ++i)
        if ((byte(i) & 0xC0) != 0x80) return 0;
    if (lead == 0xC2 && byte(1) < 0xA0) return 0;   // U+0080..U+009F: C1 controls (CSI is U+009B)
    if (lead == 0xE0 && byte(1) < 0xA0) return 0;   // overlong
    if (lead == 0xED && byte(1) >= 0xA0) return 0;  // UTF-16 surrogates
    if (lead == 0xF0 && byte(1) < 0x90) return 0;   // overlong
    if (lead == 0xF4 && byte(1) >= 0x90) return 0;  // beyond U+10FFFF
    return length;
}

}  // namespace

std::string terminal_text(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    while (!text.empty()) {
        std::size_t n = printable_sequence(text);
        if (n > 0) {
            out.append(text.substr(0, n));
        } else {
            n = 1;
            out += fmt::format("\\x{:02x}", static_cast<unsigned char>(text.front()));
        }
        text.remove_prefix(n);
    }
    return out;
}

}  // namespace warpcheck

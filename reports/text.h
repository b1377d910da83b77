// Text helpers shared by the writers: escaping for markup, compact formatting
// of numbers for people, and fitting text into terminal columns.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace warpcheck {

/// Appends `text` escaped for XML and HTML, in element content and in quoted
/// attribute values alike: & < > " ' become character references. Bytes that
/// are not valid UTF-8 and characters that XML 1.0 forbids (control characters
/// other than tab, newline and carriage return) become U+FFFD, so that any case
/// name or exception message yields a well-formed document.
void append_escaped(std::string& out, std::string_view text);

/// `text` escaped as by append_escaped.
std::string escaped(std::string_view text);

/// A number for a table cell: integers as integers (up to 1e15), otherwise six
/// significant digits; "NaN", "inf", "-inf" for the non-finite.
std::string format_number(double value);

/// As format_number, but integers of five or more digits are grouped in threes
/// by narrow no-break spaces, for reading: "4 294 967 296".
std::string format_grouped(double value);

/// A probability or a significance level: "0.43", "1.2e-05", "< 1e-300" for 0.
std::string format_probability(double p);

/// A duration: "850 ms", "3.2 s", "4 min 12 s".
std::string format_seconds(double seconds);

/// A duration as a clock, whole seconds: "0:07", "3:05", "1:02:03"; "--:--" if not finite or negative.
std::string format_clock(double seconds);

/// The columns `text` takes on a terminal, each UTF-8 character counted as one.
std::size_t display_width(std::string_view text);

/// `text` cut to at most `columns` columns (as display_width counts them), never
/// inside a UTF-8 sequence; a cut is marked by "…" in the last column.
std::string fit_columns(std::string_view text, std::size_t columns);

/// `text` safe to print on a terminal: every byte that a terminal could take as
/// a control (C0 controls and DEL, UTF-8-encoded C1 controls, bytes that are not
/// valid UTF-8) becomes a visible \xNN escape, so that a case name or a message
/// can neither move the cursor nor fake a row ('\n' and '\t' included). Other
/// text, UTF-8 included, is unchanged.
std::string terminal_text(std::string_view text);

/// The same: what the table, the progress lines and the summaries print.
inline std::string printable(std::string_view text) { return terminal_text(text); }

}  // namespace warpcheck

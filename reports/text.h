// Text helpers shared by the HTML, SVG and JUnit writers: escaping for markup
// and compact formatting of numbers for people.
#pragma once

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

}  // namespace warpcheck

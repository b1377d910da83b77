// The paths of the tree that a text names (docs, comments, scripts), for the
// lint that every one of them exists (tests/lint/named_paths.cpp): after the
// moves of last round, a dozen comments and READMEs named files that were gone.
#pragma once

#include <array>
#include <cctype>
#include <string>
#include <string_view>
#include <vector>

namespace lint {

struct NamedPath {
    std::string path;  ///< as written, without trailing punctuation
    int line = 0;
};

/// The top-level rooms whose paths are looked for.
inline constexpr std::array<std::string_view, 7> kRooms = {"sampling/", "validate/", "chi2/", "tests/",
                                                           "reports/",  "cmake/",    ".ci/"};

namespace detail {

inline bool path_char(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '/' || c == '-';
}

}  // namespace detail

/// Every path of a room named in `text`: a room's name ("validate/") at the
/// start of a word, followed by path characters. Not taken: a path inside
/// <...> (an installed include path such as <validate/api/external.h>, which
/// names the installed tree), a pattern (followed by *, { or <: bsdf_*.h), and
/// the part of a longer path or URL (preceded by a path character or ':').
inline std::vector<NamedPath> named_paths(std::string_view text) {
    std::vector<NamedPath> out;
    int line = 1;
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i] == '\n') {
            ++line;
            continue;
        }
        if (i > 0 && (detail::path_char(text[i - 1]) || text[i - 1] == '<' || text[i - 1] == ':')) continue;
        bool room = false;
        for (std::string_view r : kRooms) room = room || text.substr(i, r.size()) == r;
        if (!room) continue;
        std::size_t end = i;
        while (end < text.size() && detail::path_char(text[end])) ++end;
        const bool pattern = end < text.size() && (text[end] == '*' || text[end] == '{' || text[end] == '<');
        std::string path(text.substr(i, end - i));
        while (!path.empty() && (path.back() == '.' || path.back() == '-')) path.pop_back();
        if (!pattern) out.push_back({path, line});
        i = end - 1;
    }
    return out;
}

}  // namespace lint

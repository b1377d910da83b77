// Reading the HTML report as its script does: the packs (zlib streams of
// {row index: details markup}, in base64) decoded and their details put back
// into the rows, so that tests can check what a reader sees on opening a row.
#pragma once

#include <map>
#include <regex>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>
#include <zlib.h>

namespace warpcheck::testing {

inline std::string base64_decoded(const std::string& text) {
    static const std::string digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    unsigned bits = 0;
    int count = 0;
    for (char c : text) {
        if (c == '=' || c == '\n' || c == ' ') continue;
        const auto at = digits.find(c);
        if (at == std::string::npos) throw std::runtime_error("not base64");
        bits = (bits << 6) | static_cast<unsigned>(at);
        if ((count += 6) >= 8) out += static_cast<char>((bits >> (count -= 8)) & 0xFF);
    }
    return out;
}

/// Inflates a zlib stream (RFC 1950) with zlib itself.
inline std::string inflated(const std::string& stream) {
    z_stream z{};
    if (inflateInit(&z) != Z_OK) throw std::runtime_error("inflateInit");
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(stream.data()));
    z.avail_in = static_cast<uInt>(stream.size());
    std::string out;
    char buffer[65536];
    int status = Z_OK;
    while (status == Z_OK) {
        z.next_out = reinterpret_cast<Bytef*>(buffer);
        z.avail_out = sizeof buffer;
        status = inflate(&z, Z_NO_FLUSH);
        out.append(buffer, sizeof buffer - z.avail_out);
    }
    inflateEnd(&z);
    if (status != Z_STREAM_END) throw std::runtime_error("not a complete zlib stream");
    return out;
}

/// Every pack of a report: its id -> {row index -> details markup}.
inline std::map<std::string, nlohmann::json> report_packs(const std::string& html) {
    // Found by plain search: std::regex recurses once per character of a
    // pack's text and overflows the stack on a long one (AddressSanitizer).
    std::map<std::string, nlohmann::json> packs;
    const std::string open = "<script type=\"application/x-warpcheck-pack\" id=\"pack-", close = "</script>";
    for (std::size_t at = html.find(open); at != std::string::npos; at = html.find(open, at + 1)) {
        const std::size_t id = at + open.size(), id_end = html.find("\">", id);
        if (id_end == std::string::npos) throw std::runtime_error("a pack without its id's end");
        const std::size_t text = id_end + 2, end = html.find(close, text);
        if (end == std::string::npos) throw std::runtime_error("a pack without </script>");
        packs[html.substr(id, id_end - id)] = nlohmann::json::parse(inflated(base64_decoded(html.substr(text, end - text))));
    }
    return packs;
}

/// The report with each packed row's details in its body, as a reader who
/// opened every row sees it.
inline std::string unpacked_html(std::string html) {
    const auto packs = report_packs(html);
    const std::regex row_re("<details class=\"r [a-z]+\" id=\"r-(\\d+)\"[^>]* data-p=\"(\\d+)\"");
    std::string out;
    std::size_t from = 0;
    for (auto it = std::sregex_iterator(html.begin(), html.end(), row_re); it != std::sregex_iterator(); ++it) {
        const std::string empty = "<div class=\"body\"></div>";
        const std::size_t body = html.find(empty, static_cast<std::size_t>(it->position()));
        if (body == std::string::npos) throw std::runtime_error("a packed row without a body");
        out += html.substr(from, body - from) + "<div class=\"body\">" +
               packs.at((*it)[2]).at(std::string((*it)[1])).get<std::string>() + "</div>";
        from = body + empty.size();
    }
    return out + html.substr(from);
}

}  // namespace warpcheck::testing

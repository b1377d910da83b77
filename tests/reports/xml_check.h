// A small XML well-formedness checker for the tests: the JUnit report must be
// XML, and the HTML report is written as polyglot markup (well-formed XML that
// is also HTML), so both go through it. It checks what matters for a report:
// balanced tags, quoted attributes without '<', no duplicate attributes, only
// the five predefined or numeric character references, one root element.
#pragma once

#include <cctype>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace warpcheck::testing {

/// Empty if `text` is well-formed, else the first problem and its offset.
inline std::string xml_problem(std::string_view text) {
    std::size_t i = 0;
    std::vector<std::string> open;
    int roots = 0;
    const auto fail = [&](std::string_view what) { return std::string(what) + " at offset " + std::to_string(i); };
    const auto name_char = [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == ':' || c == '.' ||
               (static_cast<unsigned char>(c) & 0x80);
    };
    const auto check_reference = [&](std::size_t at, std::string_view in) -> bool {
        const std::size_t end = in.find(';', at);
        if (end == std::string_view::npos) return false;
        const std::string_view ref = in.substr(at + 1, end - at - 1);
        if (ref == "amp" || ref == "lt" || ref == "gt" || ref == "quot" || ref == "apos") return true;
        if (ref.size() >= 2 && ref[0] == '#') {
            const bool hex = ref[1] == 'x';
            const std::string_view digits = ref.substr(hex ? 2 : 1);
            if (digits.empty()) return false;
            for (char c : digits)
                if (!(hex ? std::isxdigit(static_cast<unsigned char>(c)) : std::isdigit(static_cast<unsigned char>(c))))
                    return false;
            return true;
        }
        return false;
    };
    const auto check_text = [&](std::string_view chunk) -> bool {
        for (std::size_t k = 0; k < chunk.size(); ++k)
            if (chunk[k] == '&' && !check_reference(k, chunk)) return false;
        return true;
    };
    while (i < text.size()) {
        if (text[i] != '<') {
            std::size_t next = text.find('<', i);
            if (next == std::string_view::npos) next = text.size();
            const std::string_view chunk = text.substr(i, next - i);
            if (!check_text(chunk)) return fail("bad character reference in text");
            if (open.empty() && chunk.find_first_not_of(" \t\r\n") != std::string_view::npos)
                return fail("text outside the root element");
            i = next;
            continue;
        }
        if (text.substr(i, 4) == "<!--") {
            const std::size_t end = text.find("-->", i + 4);
            if (end == std::string_view::npos) return fail("unterminated comment");
            i = end + 3;
        } else if (text.substr(i, 9) == "<![CDATA[") {
            const std::size_t end = text.find("]]>", i);
            if (end == std::string_view::npos || open.empty()) return fail("bad CDATA");
            i = end + 3;
        } else if (text.substr(i, 2) == "<?") {
            const std::size_t end = text.find("?>", i);
            if (end == std::string_view::npos) return fail("unterminated processing instruction");
            i = end + 2;
        } else if (text.substr(i, 9) == "<!DOCTYPE") {
            if (roots > 0 || !open.empty()) return fail("DOCTYPE after the root");
            const std::size_t end = text.find('>', i);
            if (end == std::string_view::npos) return fail("unterminated DOCTYPE");
            i = end + 1;
        } else if (text.substr(i, 2) == "</") {
            std::size_t k = i + 2;
            while (k < text.size() && name_char(text[k])) ++k;
            const std::string name(text.substr(i + 2, k - i - 2));
            while (k < text.size() && std::isspace(static_cast<unsigned char>(text[k]))) ++k;
            if (k >= text.size() || text[k] != '>') return fail("bad end tag");
            if (open.empty() || open.back() != name) return fail("end tag </" + name + "> does not match");
            open.pop_back();
            i = k + 1;
        } else {
            std::size_t k = i + 1;
            while (k < text.size() && name_char(text[k])) ++k;
            const std::string name(text.substr(i + 1, k - i - 1));
            if (name.empty()) return fail("'<' that starts no tag");
            std::set<std::string> attributes;
            bool self_closing = false;
            for (;;) {
                while (k < text.size() && std::isspace(static_cast<unsigned char>(text[k]))) ++k;
                if (k >= text.size()) return fail("unterminated tag <" + name + ">");
                if (text[k] == '>') break;
                if (text.substr(k, 2) == "/>") {
                    self_closing = true;
                    ++k;
                    break;
                }
                const std::size_t start = k;
                while (k < text.size() && name_char(text[k])) ++k;
                const std::string attribute(text.substr(start, k - start));
                if (attribute.empty()) return fail("bad attribute in <" + name + ">");
                if (!attributes.insert(attribute).second) return fail("duplicate attribute " + attribute);
                if (k >= text.size() || text[k] != '=') return fail("attribute " + attribute + " without a value");
                ++k;
                if (k >= text.size() || (text[k] != '"' && text[k] != '\'')) return fail("unquoted attribute " + attribute);
                const char quote = text[k];
                const std::size_t end = text.find(quote, k + 1);
                if (end == std::string_view::npos) return fail("unterminated attribute value");
                const std::string_view value = text.substr(k + 1, end - k - 1);
                if (value.find('<') != std::string_view::npos) return fail("'<' in attribute " + attribute);
                if (!check_text(value)) return fail("bad character reference in attribute " + attribute);
                k = end + 1;
            }
            if (open.empty()) {
                if (++roots > 1) return fail("a second root element");
            }
            if (!self_closing) open.push_back(name);
            i = k + 1;
        }
    }
    if (!open.empty()) return "element <" + open.back() + "> is not closed";
    if (roots != 1) return "no root element";
    return {};
}

}  // namespace warpcheck::testing

// The function bodies of a C++ source text and their lengths, read from its
// tokens (tests/lint/function_length.cpp says how and why).
#pragma once

#include <cctype>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace lint {

struct FunctionBody {
    std::string name;  ///< the identifier before the head's first "(" ("operator" for operators)
    int name_line = 0;
    int lines = 0;  ///< closing brace's line minus opening brace's line, as clang-tidy counts
};

struct Token {
    std::string text;  ///< an identifier or number, or one punctuation character ("->" and "::" joined)
    int line = 0;
};

namespace detail {

inline bool ident_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

/// The end of the literal that starts at text[i] (a quote), past its closing quote.
inline std::size_t skip_quoted(std::string_view text, std::size_t i, int& line) {
    const char quote = text[i++];
    while (i < text.size() && text[i] != quote) {
        if (text[i] == '\\') ++i;
        else if (text[i] == '\n') ++line;
        ++i;
    }
    return i + 1;
}

/// The end of the raw string whose R is at text[i]: R"delim( ... )delim".
inline std::size_t skip_raw(std::string_view text, std::size_t i, int& line) {
    const std::size_t open = text.find('(', i + 2);
    if (open == std::string_view::npos) return text.size();
    std::string close(1, ')');  // built by appends: g++ 12 warns falsely (-Wrestrict) on ")" + s + "\""
    close.append(text.substr(i + 2, open - i - 2));
    close.push_back('"');
    const std::size_t end = text.find(close, open);
    const std::size_t stop = end == std::string_view::npos ? text.size() : end + close.size();
    for (std::size_t k = i; k < stop; ++k) line += text[k] == '\n';
    return stop;
}

/// The end of the comment or preprocessor line at text[i], or i where there is none.
inline std::size_t skip_comment_or_directive(std::string_view text, std::size_t i, bool line_start, int& line) {
    if (text.compare(i, 2, "//") == 0) return text.find('\n', i) == std::string_view::npos ? text.size() : text.find('\n', i);
    if (text.compare(i, 2, "/*") == 0) {
        const std::size_t end = text.find("*/", i + 2);
        const std::size_t stop = end == std::string_view::npos ? text.size() : end + 2;
        for (std::size_t k = i; k < stop; ++k) line += text[k] == '\n';
        return stop;
    }
    if (line_start && text[i] == '#') {  // a directive, continued by backslashes
        std::size_t k = i;
        while (k < text.size() && !(text[k] == '\n' && text[k - 1] != '\\')) line += text[k++] == '\n';
        return k;
    }
    return i;
}

}  // namespace detail

/// The tokens of a source text, without comments, literals and directives.
inline std::vector<Token> tokenize(std::string_view text) {
    std::vector<Token> tokens;
    int line = 1;
    bool line_start = true;  // only whitespace since the last newline
    std::size_t i = 0;
    while (i < text.size()) {
        const char c = text[i];
        if (c == '\n') { ++line, ++i, line_start = true; continue; }
        if (std::isspace(static_cast<unsigned char>(c))) { ++i; continue; }
        if (const std::size_t end = detail::skip_comment_or_directive(text, i, line_start, line); end != i) {
            i = end;
            continue;
        }
        line_start = false;
        if (c == '"') { i = detail::skip_quoted(text, i, line); continue; }
        if (c == '\'') { i = detail::skip_quoted(text, i, line); continue; }
        if (detail::ident_char(c)) {
            std::size_t k = i;
            // Digit separators (1'000) belong to a number; a prefix (u8, L) before a quote to a literal.
            const bool number = std::isdigit(static_cast<unsigned char>(c));
            while (k < text.size() && (detail::ident_char(text[k]) || (number && (text[k] == '\'' || text[k] == '.'))))
                ++k;
            const std::string_view word = text.substr(i, k - i);
            if (k < text.size() && text[k] == '"' && !word.empty() && word.back() == 'R') {
                i = detail::skip_raw(text, k - 1, line);
                continue;
            }
            if (k < text.size() && (text[k] == '"' || text[k] == '\'') && (word == "u8" || word == "u" || word == "U" || word == "L")) {
                i = k;
                continue;
            }
            tokens.push_back({std::string(word), line});
            i = k;
            continue;
        }
        if ((c == '-' && i + 1 < text.size() && text[i + 1] == '>') || (c == ':' && i + 1 < text.size() && text[i + 1] == ':')) {
            tokens.push_back({std::string(text.substr(i, 2)), line});
            i += 2;
            continue;
        }
        tokens.push_back({std::string(1, c), line});
        ++i;
    }
    return tokens;
}

namespace detail {

enum class Scope { Declarations, Function, Other };

/// What the statement tokens before a brace at declaration scope make of it.
inline Scope classify_brace(const std::vector<Token>& statement, const Token* previous) {
    int parens = 0;
    bool seen_paren = false, seen_close_paren = false, init_list = false, arrow = false, requires_clause = false;
    for (std::size_t k = 0; k < statement.size(); ++k) {
        const std::string& t = statement[k].text;
        if (t == "template" && k + 1 < statement.size() && statement[k + 1].text == "<") {
            int angles = 0;  // skip the template head, whose class/typename and = are not the statement's
            for (++k; k < statement.size(); ++k) {
                if (statement[k].text == "<") ++angles;
                if (statement[k].text == ">" && --angles == 0) break;
            }
            continue;
        }
        if (t == "(") { ++parens, seen_paren = true; continue; }
        if (t == ")") { --parens, seen_close_paren = parens == 0 || seen_close_paren; continue; }
        if (parens != 0) continue;
        if (!seen_paren && (t == "namespace" || t == "class" || t == "struct" || t == "union" || t == "enum"))
            return Scope::Declarations;
        if (t == "extern" && statement.size() == 1) return Scope::Declarations;  // extern "C" {
        // "name = " or "] = " begins an initialiser (a lambda or braced list); the
        // "=" of ==, <=, +=, operator= and the like follows punctuation or "operator".
        if (t == "=" && k > 0 && (statement[k - 1].text == "]" ||
                                  (ident_char(statement[k - 1].text[0]) && statement[k - 1].text != "operator")) &&
            !(k + 1 < statement.size() && statement[k + 1].text == "="))
            return Scope::Other;
        if (seen_close_paren && t == ":") init_list = true;
        if (seen_close_paren && t == "->") arrow = true;
        if (seen_close_paren && t == "requires") requires_clause = true;
    }
    if (!seen_close_paren || previous == nullptr) return Scope::Other;
    const std::string& p = previous->text;
    for (const char* s : {")", "const", "override", "final", "noexcept", "mutable", "volatile", "&"})
        if (p == s) return Scope::Function;
    if (init_list) return p == "}" ? Scope::Function : Scope::Other;  // ": a_{x} {" ends a constructor's head
    if (arrow || requires_clause) return Scope::Function;
    return Scope::Other;
}

/// The name of a function whose head is `statement`: the identifier before its first "(".
inline const Token* function_name(const std::vector<Token>& statement) {
    const Token* name = nullptr;
    for (std::size_t k = 0; k < statement.size(); ++k) {
        const std::string& t = statement[k].text;
        if (t == "__attribute__" || t == "alignas" || t == "__declspec") {  // skip the attribute's parentheses
            int depth = 0;
            for (++k; k < statement.size(); ++k) {
                if (statement[k].text == "(") ++depth;
                if (statement[k].text == ")" && --depth == 0) break;
            }
            continue;
        }
        if (t == "(") return name;
        if (ident_char(t[0])) name = &statement[k];
    }
    return name;
}

}  // namespace detail

/// Every function body of the text (at namespace or class scope, at any depth
/// of namespaces and classes), in order of their closing braces.
inline std::vector<FunctionBody> function_bodies(std::string_view text) {
    const std::vector<Token> tokens = tokenize(text);
    struct Open {
        detail::Scope scope;
        int line;
        FunctionBody body;
    };
    std::vector<Open> stack;
    std::vector<Token> statement;  // tokens since the last ; { } at declaration scope
    std::vector<FunctionBody> bodies;
    const auto in_declarations = [&] { return stack.empty() || stack.back().scope == detail::Scope::Declarations; };
    for (std::size_t k = 0; k < tokens.size(); ++k) {
        const Token& t = tokens[k];
        if (t.text == "{") {
            detail::Scope scope = detail::Scope::Other;
            FunctionBody body;
            if (in_declarations()) {
                scope = detail::classify_brace(statement, k > 0 ? &tokens[k - 1] : nullptr);
                if (scope == detail::Scope::Function) {
                    const Token* name = detail::function_name(statement);
                    body.name = name ? name->text : "?";
                    body.name_line = name ? name->line : t.line;
                }
                if (scope != detail::Scope::Other) statement.clear();
            }
            stack.push_back({scope, t.line, body});
            continue;
        }
        if (t.text == "}") {
            if (stack.empty()) continue;  // unbalanced: leave it to the compiler
            Open open = stack.back();
            stack.pop_back();
            if (open.scope == detail::Scope::Function) {
                open.body.lines = t.line - open.line;
                bodies.push_back(open.body);
            }
            if (open.scope != detail::Scope::Other) statement.clear();
            else if (in_declarations()) statement.push_back(t);  // ": a_{x}" goes on to the body's brace
            continue;
        }
        if (!in_declarations()) continue;
        if (t.text == ";") { statement.clear(); continue; }
        if (t.text == ":" && statement.size() == 1 &&
            (statement[0].text == "public" || statement[0].text == "private" || statement[0].text == "protected")) {
            statement.clear();
            continue;
        }
        statement.push_back(t);
    }
    return bodies;
}

}  // namespace lint

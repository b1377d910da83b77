// The function-length lint (tests/lint/function_length.h) on the shapes of
// code the project writes: each body found with clang-tidy's line count, and
// nothing else taken for a body.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "lint/function_length.h"

namespace {

std::string lines(int n) {
    std::string s;
    for (int i = 0; i < n; ++i) s += "    x += " + std::to_string(i) + ";\n";
    return s;
}

std::vector<std::string> names(const std::vector<lint::FunctionBody>& bodies) {
    std::vector<std::string> out;
    for (const lint::FunctionBody& b : bodies) out.push_back(b.name + ":" + std::to_string(b.lines));
    return out;
}

TEST(FunctionLength, CountsLinesAsClangTidyDoes) {
    // Opening brace on line 1, closing on line 1 + 3 + 1: four lines apart.
    const auto bodies = lint::function_bodies("int f(int x) {\n" + lines(3) + "}\n");
    ASSERT_EQ(bodies.size(), 1u);
    EXPECT_EQ(bodies[0].name, "f");
    EXPECT_EQ(bodies[0].name_line, 1);
    EXPECT_EQ(bodies[0].lines, 4);
}

TEST(FunctionLength, FindsBodiesInNamespacesClassesAndAfterSpecifiers) {
    const std::string text =
        "namespace a { namespace b {\n"
        "template <typename T, class U = int>\n"
        "struct S : Base<(1 > 0)> {\n"
        "  public:\n"
        "    S() : a_(1), b_{2} {\n" + lines(2) + "    }\n"
        "    int get() const noexcept {\n" + lines(1) + "    }\n"
        "    bool operator==(const S&) const { return true; }\n"
        "    S& operator+=(int v) { return *this; }\n"
        "    auto tail() -> std::vector<int> {\n" + lines(1) + "    }\n"
        "    int a_ = 0, b_{0};\n"
        "    std::function<void()> f_ = [](int) {\n" + lines(5) + "    };\n"
        "};\n"
        "template <typename W> requires Concept<W> void g(W w) requires Other<W> {\n" + lines(2) + "}\n"
        "__attribute__((target(\"avx512f\"))) void h() {\n" + lines(1) + "}\n"
        "}}  // namespace a::b\n";
    EXPECT_EQ(names(lint::function_bodies(text)),
              (std::vector<std::string>{"S:3", "get:2", "operator:0", "operator:0", "tail:2", "g:3", "h:2"}));
}

TEST(FunctionLength, InitialisersEnumsAndLambdasAreNotBodies) {
    const std::string text =
        "enum class Kind { A, B };\n"
        "const int table[] = {1, 2, 3};\n"
        "const Point kOrigin{0, 0};\n"
        "auto lambda = [](int x) {\n" + lines(90) + "};\n"
        "template <typename W> concept Warp = requires(W w) { w.sample(0); };\n"
        "extern \"C\" {\n"
        "int c_function(void) {\n" + lines(1) + "}\n"
        "}\n";
    EXPECT_EQ(names(lint::function_bodies(text)), (std::vector<std::string>{"c_function:2"}));
}

TEST(FunctionLength, CommentsLiteralsAndDirectivesHoldNoBraces) {
    const std::string text =
        "// a comment { with a brace\n"
        "/* and { a block\n comment } */\n"
        "#define MACRO(x) { x; \\\n  }\n"
        "const char* s = \"{\\\"\";\n"
        "const char* r = R\"json({\"a\": \"}\"})json\";\n"
        "const char c = '{';\n"
        "const long n = 1'000'000;\n"
        "int f() {\n" + lines(2) + "    return '}';\n}\n";
    EXPECT_EQ(names(lint::function_bodies(text)), (std::vector<std::string>{"f:4"}));
}

TEST(FunctionLength, LambdasAndLocalClassesInsideABodyCountAsItsLines) {
    const std::string text = "void outer() {\n"
                             "    auto l = [&](int) {\n" + lines(3) + "    };\n"
                             "    struct Local { int m() { return 1; } };\n"
                             "}\n";
    EXPECT_EQ(names(lint::function_bodies(text)), (std::vector<std::string>{"outer:7"}));
}

}  // namespace

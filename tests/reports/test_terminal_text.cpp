// Control bytes of a case name or a message never reach the terminal raw: the
// table shows them as \xNN escapes and leaves every other character alone.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "reports/terminal_table.h"
#include "reports/text.h"

namespace warpcheck {
namespace {

TEST(TerminalText, EscapesWhatATerminalWouldObey) {
    EXPECT_EQ(terminal_text("uniform_cone[cos_theta_max=0.3]"), "uniform_cone[cos_theta_max=0.3]");
    const std::string utf8 = "\xCE\xB8 and \xE2\x80\xA6 and \xF0\x9F\x99\x82";
    EXPECT_EQ(terminal_text(utf8), utf8) << "UTF-8 text is shown as it is";
    EXPECT_EQ(terminal_text("a\x1b[2Jb\x07"), "a\\x1b[2Jb\\x07");
    EXPECT_EQ(terminal_text("tab\tnew\nline\rdel\x7f"), "tab\\x09new\\x0aline\\x0ddel\\x7f");
    EXPECT_EQ(terminal_text(std::string("nul\0x", 5)), "nul\\x00x");
    EXPECT_EQ(terminal_text("csi\xC2\x9B" "31m"), "csi\\xc2\\x9b31m") << "U+009B, a C1 control, in UTF-8";
    EXPECT_EQ(terminal_text("raw\x9b"), "raw\\x9b") << "a lone byte that is not UTF-8 (CSI to an 8-bit terminal)";
    EXPECT_EQ(terminal_text("over\xC0\x9B"), "over\\xc0\\x9b") << "an overlong encoding";
    EXPECT_EQ(terminal_text("cut\xE2\x80"), "cut\\xe2\\x80") << "a sequence cut short";
    EXPECT_EQ(terminal_text("surrogate\xED\xA0\x80"), "surrogate\\xed\\xa0\\x80");
    EXPECT_EQ(terminal_text("\\x1b stays as typed"), "\\x1b stays as typed");
}

TEST(TerminalText, TheTableShowsNoControlByte) {
    RunResult run;
    CheckResult r;
    r.case_name = "evil\x1b]0;owned\x07\nFAIL  fake row";
    r.check_name = "roundtrip";
    r.verdict = Verdict::Fail;
    r.summary = "max |du| \x1b[31m1\x1b[0m";
    r.message = "the warp threw: \x1b[2J";
    r.rerun_command = "validate --filter $'evil\\x1b'";
    run.results = {r};
    std::ostringstream out;
    print_table(run, out);
    const std::string text = out.str();
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        EXPECT_TRUE(c == '\n' || (byte >= 0x20 && byte != 0x7F)) << "byte " << int(byte) << " in:\n" << text;
    }
    EXPECT_NE(text.find("evil\\x1b]0;owned\\x07\\x0aFAIL  fake row"), std::string::npos) << text;
    EXPECT_NE(text.find("the warp threw: \\x1b[2J"), std::string::npos) << text;
}

}  // namespace
}  // namespace warpcheck

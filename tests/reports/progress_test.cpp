#include <sstream>
#include <thread>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "reports/progress.h"

namespace warpcheck {
namespace {

using ::testing::EndsWith;
using ::testing::HasSubstr;

TEST(Progress, SilentWhenNotATerminal) {
    std::ostringstream out;
    {
        ProgressLine line(out, false, 80);
        line(1, 10, "chi2 uniform_disk[]");
        line(10, 10, "done");
    }
    EXPECT_EQ(out.str(), "");
}

TEST(Progress, ShowsWhichAndHowFarThenClears) {
    std::ostringstream out;
    ProgressLine line(out, true, 80);
    line(12, 140, "chi2 trowbridge_reitz[alpha=0.3]");
    EXPECT_EQ(out.str(), "\r\x1b[K[ 12/140]   8%  chi2 trowbridge_reitz[alpha=0.3]");
    line(140, 140, "");
    EXPECT_THAT(out.str(), EndsWith("\r\x1b[K"));
}

TEST(Progress, NeverWrapsTheLine) {
    std::ostringstream out;
    ProgressLine line(out, true, 30);
    line(1, 9, std::string(100, 'x') + "\xCF\x80");
    const std::string shown = out.str().substr(4);  // after "\r\x1b[K"
    EXPECT_THAT(shown, EndsWith("\xE2\x80\xA6"));
    std::size_t columns = 0;
    for (char c : shown) columns += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
    EXPECT_EQ(columns, 29u);
}

TEST(Progress, ClearsWhenDestroyedMidway) {
    std::ostringstream out;
    {
        ProgressLine line(out, true, 80);
        line(1, 5, "a");
    }
    EXPECT_THAT(out.str(), EndsWith("\r\x1b[K"));
}

TEST(Progress, IsSafeFromManyThreads) {
    std::ostringstream out;
    ProgressLine line(out, true, 80);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&] {
            for (int i = 0; i < 1000; ++i) line(static_cast<std::size_t>(i), 1000, "work");
        });
    for (auto& t : threads) t.join();
    line(1000, 1000, "");
    EXPECT_THAT(out.str(), HasSubstr("work"));
    EXPECT_THAT(out.str(), EndsWith("\r\x1b[K"));
}

TEST(Progress, StderrCallbackIsCallable) {
    // Under ctest stderr is not a terminal: the callback must simply do nothing.
    const ProgressCallback callback = stderr_progress();
    ASSERT_TRUE(callback);
    callback(1, 2, "x");
    callback(2, 2, "x");
}

}  // namespace
}  // namespace warpcheck

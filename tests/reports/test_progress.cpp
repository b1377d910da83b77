#include <chrono>
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
using ::testing::Not;
using ::testing::StartsWith;

/// A clock the test moves by hand.
struct FakeClock {
    ProgressDisplay::Clock::time_point now{};
    void advance(double seconds) {
        now += std::chrono::duration_cast<ProgressDisplay::Clock::duration>(std::chrono::duration<double>(seconds));
    }
};

ProgressDisplay::Options options(ProgressMode mode, FakeClock& clock, std::size_t width = 200) {
    ProgressDisplay::Options o;
    o.mode = mode;
    o.width = width;
    o.level = 1e-3;
    o.now = [&clock] { return clock.now; };
    return o;
}

CheckResult row(Verdict verdict, std::string summary = "fine", std::optional<double> p = std::nullopt) {
    CheckResult r;
    r.verdict = verdict;
    r.summary = std::move(summary);
    r.p_value = p;
    return r;
}

TEST(Progress, ModesFromTheOption) {
    EXPECT_EQ(progress_mode("auto", true), ProgressMode::Bar);
    EXPECT_EQ(progress_mode("auto", false), ProgressMode::Log);
    EXPECT_EQ(progress_mode("log", true), ProgressMode::Log);
    EXPECT_EQ(progress_mode("none", true), ProgressMode::Off);
    EXPECT_FALSE(progress_mode("sometimes", true));
}

TEST(Progress, OffWritesNothing) {
    std::ostringstream out;
    FakeClock clock;
    const CheckResult failed = row(Verdict::Fail);
    {
        ProgressDisplay display(out, options(ProgressMode::Off, clock));
        clock.advance(30);
        display({1, 2, "chi2", "a", &failed});
        display({2, 2, "chi2", "b", &failed});
    }
    EXPECT_EQ(out.str(), "");
}

// The bar: done/total, percent, elapsed, ETA at the pace so far, failures so far.
TEST(Progress, BarShowsTheFactsThenClears) {
    std::ostringstream out;
    FakeClock clock;
    const CheckResult passed = row(Verdict::Pass);
    ProgressDisplay display(out, options(ProgressMode::Bar, clock));
    clock.advance(12);
    display({30, 120, "chi2", "trowbridge_reitz[alpha=0.3]", &passed});
    EXPECT_EQ(out.str(), "\r\x1b[K[=====>              ]  30/120  25%  0:12 elapsed  ETA 0:36  0 failed  chi2 "
                         "trowbridge_reitz[alpha=0.3]");
    clock.advance(1);
    display({120, 120, "chi2", "x", &passed});
    EXPECT_THAT(out.str(), EndsWith("\r\x1b[K"));
}

// A failing row is printed above the bar as soon as it is known, in the
// table's words; a p-value below the run's level counts as a failure already.
TEST(Progress, FailuresShowAsTheyHappen) {
    std::ostringstream out;
    FakeClock clock;
    const CheckResult passed = row(Verdict::Pass, "p 0.5", 0.5);
    const CheckResult low_p = row(Verdict::Pass, "chi2 900 dof 40 p 1e-30", 1e-30);
    const CheckResult nan_p = row(Verdict::Pass, "p NaN", std::nan(""));
    ProgressDisplay display(out, options(ProgressMode::Bar, clock));
    display({1, 10, "chi2", "good", &passed});
    clock.advance(1);
    display({2, 10, "chi2", "power_wrong[n=2]", &low_p});
    EXPECT_THAT(out.str(), HasSubstr("\r\x1b[KFAIL   chi2  power_wrong[n=2]  chi2 900 dof 40 p 1e-30\n"));
    EXPECT_THAT(out.str(), EndsWith("1 failed  chi2 power_wrong[n=2]"));
    clock.advance(1);
    display({3, 10, "unbinned", "nan", &nan_p});
    EXPECT_THAT(out.str(), HasSubstr("FAIL   unbinned  nan  p NaN\n"));
    EXPECT_THAT(out.str(), EndsWith("2 failed  unbinned nan"));
}

TEST(Progress, BarNeverWrapsTheLine) {
    std::ostringstream out;
    FakeClock clock;
    const CheckResult passed = row(Verdict::Pass);
    ProgressDisplay display(out, options(ProgressMode::Bar, clock, 30));
    display({1, 9, "chi2", std::string(100, 'x') + "\xCF\x80", &passed});
    const std::string shown = out.str().substr(4);  // after "\r\x1b[K"
    EXPECT_THAT(shown, EndsWith("\xE2\x80\xA6"));
    std::size_t columns = 0;
    for (char c : shown) columns += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
    EXPECT_EQ(columns, 29u);
}

// In a log: nothing in the first 2 s, then a line per tenth of the run or per
// 10 s of silence, failures at once, and a closing line.
TEST(Progress, LogWritesALineEveryTenthOrTenSeconds) {
    std::ostringstream out;
    FakeClock clock;
    const CheckResult passed = row(Verdict::Pass);
    const CheckResult error = row(Verdict::Error, "error: worker died");
    ProgressDisplay display(out, options(ProgressMode::Log, clock));
    display({15, 100, "chi2", "a", &passed});  // at 0 s: too soon
    EXPECT_EQ(out.str(), "");
    clock.advance(3);
    display({16, 100, "chi2", "b", &passed});  // a tenth crossed, after the quiet start
    EXPECT_EQ(out.str(), "validate: 16/100 done (16%), 0:03 elapsed, ETA 0:15, 0 failed\n");
    clock.advance(1);
    display({17, 100, "chi2", "c", &passed});  // same tenth, 1 s later: nothing
    clock.advance(11);
    display({18, 100, "roundtrip", "d", &error});  // a failure at once, then the 10 s line
    EXPECT_THAT(out.str(), HasSubstr("validate: ERROR  roundtrip  d  error: worker died\n"
                                     "validate: 18/100 done (18%), 0:15 elapsed, ETA 1:08, 1 failed\n"));
    clock.advance(5);
    display({100, 100, "chi2", "e", &passed});
    EXPECT_THAT(out.str(), EndsWith("validate: 100/100 done in 0:20, 1 failed\n"));
    EXPECT_THAT(out.str(), Not(HasSubstr("(100%)")));
}

TEST(Progress, ShortLogRunIsSilent) {
    std::ostringstream out;
    FakeClock clock;
    const CheckResult passed = row(Verdict::Pass);
    {
        ProgressDisplay display(out, options(ProgressMode::Log, clock));
        clock.advance(0.5);
        display({1, 2, "chi2", "a", &passed});
        display({2, 2, "chi2", "b", &passed});
    }
    EXPECT_EQ(out.str(), "");
}

TEST(Progress, ClearsWhenDestroyedMidway) {
    std::ostringstream out;
    FakeClock clock;
    const CheckResult passed = row(Verdict::Pass);
    {
        ProgressDisplay display(out, options(ProgressMode::Bar, clock));
        display({1, 5, "chi2", "a", &passed});
    }
    EXPECT_THAT(out.str(), StartsWith("\r\x1b[K["));
    EXPECT_THAT(out.str(), EndsWith("\r\x1b[K"));
}

TEST(Progress, IsSafeFromManyThreads) {
    std::ostringstream out;
    ProgressDisplay::Options o;
    o.mode = ProgressMode::Bar;
    o.width = 200;
    ProgressDisplay display(out, o);
    const CheckResult passed = row(Verdict::Pass);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&] {
            for (std::size_t i = 0; i < 999; ++i) display({i, 1000, "work", "case", &passed});
        });
    for (auto& t : threads) t.join();
    display({1000, 1000, "work", "case", &passed});
    EXPECT_THAT(out.str(), HasSubstr("work case"));
    EXPECT_THAT(out.str(), EndsWith("\r\x1b[K"));
}

TEST(Progress, StderrCallbackIsCallable) {
    ProgressDisplay::Options o;
    o.mode = ProgressMode::Off;
    EXPECT_FALSE(stderr_progress(o)) << "no callback at all when progress is off";
    o.mode = ProgressMode::Log;
    const ProgressCallback callback = stderr_progress(o);
    ASSERT_TRUE(callback);
    const CheckResult passed = row(Verdict::Pass);
    callback({1, 2, "chi2", "x", &passed});
    callback({2, 2, "chi2", "x", &passed});
}

}  // namespace
}  // namespace warpcheck

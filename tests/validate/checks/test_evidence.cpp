// The shared bookkeeping of checks: the worst-K list, first examples and the
// in-order merge must not depend on how inputs were split into chunks.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "validate/checks/shared/evidence.h"

namespace warpcheck {
namespace {

std::vector<uint64_t> indices(const WorstK<int>& w) {
    std::vector<uint64_t> out;
    for (const auto& e : w.entries()) out.push_back(e.index);
    return out;
}

TEST(WorstK, KeepsLargestKeysWorstFirstWithTiesToTheEarlierInput) {
    WorstK<int> w(3);
    const double keys[] = {1.0, 5.0, 3.0, 5.0, 0.5, 4.0};
    for (uint64_t i = 0; i < 6; ++i) w.offer(keys[i], i, static_cast<int>(i));
    EXPECT_EQ(indices(w), (std::vector<uint64_t>{1, 3, 5}));
    EXPECT_TRUE(w.wants(4.5));
    EXPECT_FALSE(w.wants(1.0));
}

TEST(WorstK, NaNRanksAboveEveryNumber) {
    WorstK<int> w(2);
    w.offer(std::numeric_limits<double>::infinity(), 0, 0);
    w.offer(std::nan(""), 1, 1);
    w.offer(1e300, 2, 2);
    EXPECT_EQ(indices(w), (std::vector<uint64_t>{0, 1}));  // inf and NaN rank equal: earlier index first
    EXPECT_TRUE(std::isnan(w.entries()[1].key));
}

TEST(WorstK, MergeIsIndependentOfChunkOrder) {
    std::vector<double> keys;
    for (int i = 0; i < 40; ++i) keys.push_back(std::fmod(i * 7.3, 5.0));
    WorstK<int> a(5), b(5), whole(5), ab(5), ba(5);
    for (uint64_t i = 0; i < keys.size(); ++i) {
        (i < 20 ? a : b).offer(keys[i], i, 0);
        whole.offer(keys[i], i, 0);
    }
    ab.merge(a);
    ab.merge(b);
    ba.merge(b);
    ba.merge(a);
    EXPECT_EQ(indices(ab), indices(whole));
    EXPECT_EQ(indices(ba), indices(whole));
}

TEST(Tally, CountsAndKeepsTheFirstExampleInInputOrder) {
    Tally<std::string> early, late;
    late.add(10, "ten");
    late.add(11, "eleven");
    early.add(2, "two");
    late.merge(early);
    EXPECT_EQ(late.count, 3u);
    EXPECT_EQ(late.first, "two");
    Tally<std::string> none;
    late.merge(none);
    EXPECT_EQ(late.count, 3u);
}

TEST(Evidence, MaxLetsNaNWinAndReasonsJoinInOrder) {
    EXPECT_TRUE(std::isnan(max_nan_wins(1.0, std::nan(""))));
    EXPECT_TRUE(std::isnan(max_nan_wins(std::nan(""), 2.0)));
    EXPECT_EQ(max_nan_wins(1.0, 2.0), 2.0);
    EXPECT_EQ(join_reasons({"a", "", "b"}), "a; b");
}

}  // namespace
}  // namespace warpcheck

// lane_cells (validate/lanes/lane_cells.h) against Binning::bin, point by point: every point the
// lanes classify must be in the cell bin() puts it in, and the points they
// leave (-1) must be the ones bin() counts as NaN, outside or at a pole.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "chi2/binning.h"
#include "validate/lanes/lane_cells.h"
#include "sampling/pcg32.h"

#pragma GCC diagnostic ignored "-Wpsabi"  // lane vectors between inline test helpers

namespace warpcheck {
// chi2's names for this file alone: a using-directive at warpcheck's scope
// reached the other files of a unity batch (kTwoPi became ambiguous).
namespace lane_cells_test {
using namespace chi2;
namespace {

constexpr int W = lanes::kWidth;
using Point = std::array<float, 3>;

/// Points of every kind the binning meets: on the domain (uniform directions or
/// disk points), exactly on the octant and quadrant edges, on the axes, at the
/// poles and the centre, just inside and outside the slack, NaN and infinite.
std::vector<Point> hostile_points(const Binning& b) {
    const bool disk = b.domain().is<Disk>();
    std::vector<Point> pts;
    Pcg32 rng(11, 12);
    for (int i = 0; i < 100000; ++i) {
        const double phi = 2.0 * std::numbers::pi * rng.next_double();
        if (disk) {
            const double r = std::sqrt(rng.next_double());
            pts.push_back({static_cast<float>(r * std::cos(phi)), static_cast<float>(r * std::sin(phi)), 0.0f});
        } else {
            const double z = 2.0 * rng.next_double() - 1.0, r = std::sqrt(1.0 - z * z);
            pts.push_back({static_cast<float>(r * std::cos(phi)), static_cast<float>(r * std::sin(phi)),
                           static_cast<float>(z)});
        }
    }
    // Directions on column edges (phi = k du) and their float neighbours.
    for (int k = 0; k < b.cols(); ++k) {
        const double phi = 2.0 * std::numbers::pi * k / b.cols();
        float x = static_cast<float>(0.6 * std::cos(phi)), y = static_cast<float>(0.6 * std::sin(phi));
        for (int s = -2; s <= 2; ++s) {
            const float xs = x + s * std::numeric_limits<float>::epsilon() * 0.6f;
            pts.push_back({xs, y, disk ? 0.0f : 0.8f});
            pts.push_back({y, xs, disk ? 0.0f : 0.8f});
        }
    }
    const float t = 1e-5f;  // kDomainTolerance: membership's slack
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    for (const Point& p : std::vector<Point>{{0, 0, 1}, {0, 0, -1}, {0, 0, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0},
                                             {0, -1, 0}, {-0.0f, 0, 1}, {0, -0.0f, 1}, {-0.0f, -0.0f, 1},
                                             {1 + 0.9f * t, 0, 0}, {1 + 2 * t, 0, 0}, {0, 0, -2 * t},
                                             {0.6f, 0.8f, -0.5f * t}, {nan, 0, 1}, {0, nan, 1}, {0, 0, nan},
                                             {inf, 0, 0}, {0, -inf, 0}, {0.3f, 0.4f, 2.0f}})
        pts.push_back(disk ? Point{p[0], p[1], 0.0f} : p);
    while (pts.size() % W) pts.push_back({0, 0, disk ? 0.0f : 1.0f});
    return pts;
}

/// The number of points where lane_cells disagrees with Binning::bin.
std::size_t disagreements(const Binning& b, const LanePlan& plan) {
    const std::vector<Point> pts = hostile_points(b);
    std::size_t bad = 0, unclassified = 0;
    for (std::size_t i = 0; i < pts.size(); i += W) {
        lanes::F32 x, y, z;
        for (int l = 0; l < W; ++l) {
            x[l] = pts[i + l][0];
            y[l] = pts[i + l][1];
            z[l] = pts[i + l][2];
        }
        const lanes::I64 cells = lane_cells(plan, x, y, z);
        for (int l = 0; l < W; ++l) {
            Histogram h;
            h.counts.assign(b.cell_count(), 0);
            const Point p = pts[i + l];
            b.bin(std::span<const Point>(&p, 1), h);
            if (cells[l] < 0) {
                ++unclassified;
                uint64_t poles = 0;
                for (uint64_t c : h.poles) poles += c;
                bad += h.nan + h.outside + poles != 1;
            } else {
                bad += h.counts[static_cast<std::size_t>(cells[l])] != 1;
            }
        }
    }
    EXPECT_GE(unclassified, 5u);  // the NaN and infinite points at least
    return bad;
}

TEST(LaneCells, AgreesWithBinOnEveryAzimuthalDomain) {
    for (const Domain& d : {Domain::hemisphere(), Domain::sphere(), Domain::spherical_cap(0.3), Domain::unit_disk()}) {
        for (const BinResolution r : {BinResolution{}, BinResolution{48, 20}, BinResolution{128, 7}, BinResolution{8, 1}}) {
            const Binning b(d, r);
            const auto plan = b.lane_plan();
            ASSERT_TRUE(plan) << d.describe() << " " << r.first;
            EXPECT_EQ(disagreements(b, *plan), 0u) << d.describe() << " at " << r.first << " x " << r.second;
        }
    }
}

TEST(LaneCells, NoPlanWhereTheLanesDoNotApply) {
    EXPECT_FALSE(Binning(Domain::unit_square()).lane_plan());
    EXPECT_FALSE(Binning(Domain::interval(0.0, 1.0)).lane_plan());
    EXPECT_FALSE(Binning(Domain::hemisphere(), {36, 32}).lane_plan());   // no octant table
    EXPECT_FALSE(Binning(Domain::hemisphere(), {256, 32}).lane_plan());  // 32 columns per octant: too many
}

TEST(LaneCells, ComparisonCanFail) {
    // A plan with the rows' scale wrong puts points in other cells, and is caught.
    const Binning b(Domain::hemisphere());
    LanePlan wrong = *b.lane_plan();
    wrong.inv_dv *= 1.01;
    EXPECT_GT(disagreements(b, wrong), 1000u);
}

}  // namespace
}  // namespace lane_cells_test
}  // namespace warpcheck

// The vectorised chi-square path (validate/lanes/lane_sampling.h) against the scalar
// one: for every built-in case with a lane form, on both code paths (AVX-512
// where the processor has it, and the portable build), the histogram equals
// the one chi2::sample_histogram builds from draw_inputs and WarpCase::sample,
// field by field, including a partial last chunk and group, samples moved out
// of zero-expected cells, and any thread count. The chi-square check's result
// is the same with and without the lane form.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "chi2/chi2_test.h"
#include "sampling/hemisphere.h"
#include "support/builtin_case.h"
#include "validate/api/check.h"
#include "validate/checks/checks.h"
#include "validate/lanes/lane_sampling.h"
#include "validate/api/thread_pool.h"
#include "validate/api/warp_case.h"

namespace warpcheck {
namespace {

const char* const kLaneCases[] = {"uniform_disk_polar", "uniform_disk_concentric", "cosine_hemisphere",
                                  "uniform_hemisphere", "uniform_sphere"};

std::vector<LanePath> paths() {
    std::vector<LanePath> p = {LanePath::Portable};
    if (avx512_available()) p.push_back(LanePath::Avx512);
    return p;
}

void expect_equal(const chi2::Histogram& a, const chi2::Histogram& b, const std::string& what) {
    EXPECT_EQ(a.counts, b.counts) << what;
    EXPECT_EQ(a.outside, b.outside) << what;
    EXPECT_EQ(a.nan, b.nan) << what;
    EXPECT_EQ(a.snapped, b.snapped) << what;
    EXPECT_EQ(a.on_boundary, b.on_boundary) << what;
}

chi2::Histogram scalar_histogram(const WarpCase& warp, const chi2::Binning& binning, uint64_t samples,
                                 std::span<const unsigned char> zero, const CheckContext& ctx) {
    return chi2::sample_histogram(binning, samples, 4096, chi2_sample_chunks(warp, ctx), zero, ctx.executor());
}

TEST(LaneSampling, EveryLaneCaseBuildsTheScalarHistogramOnEveryPath) {
    // 300,007 samples: 74 chunks, the last one partial, in 4 groups of 24 chunks, the last one partial.
    constexpr uint64_t kSamples = 300'007;
    RunOptions options;
    ThreadPool pool(2);
    for (const char* name : kLaneCases) {
        const WarpCase& warp = testing::builtin_case(name);
        ASSERT_NE(warp.info().lanes, nullptr) << name;
        const CheckContext ctx(options, pool, stream_for(warp.name(), 7));
        const chi2::Binning binning(warp.domain());
        // No zero cells, and every third cell flagged as zero (its samples move
        // to a neighbour within the tolerance or are counted by Binning::bin).
        std::vector<unsigned char> flagged(binning.cell_count(), 0);
        for (std::size_t c = 0; c < flagged.size(); c += 3) flagged[c] = 1;
        for (const auto& zero : {std::vector<unsigned char>{}, flagged}) {
            const chi2::Histogram expected = scalar_histogram(warp, binning, kSamples, zero, ctx);
            ASSERT_EQ(expected.total(), kSamples);
            for (const LanePath path : paths()) {
                const auto rng = [&](uint64_t chunk) { return ctx.chunk_rng(chunk); };
                const chi2::Histogram got =
                    lane_histogram(binning, kSamples, 4096, rng, *warp.info().lanes, zero, ctx.executor(), path);
                expect_equal(got, expected, std::string(name) + " on the " + lane_path_name(path) + " path" +
                                                (zero.empty() ? "" : ", zero cells flagged"));
            }
        }
    }
}

TEST(LaneSampling, SameHistogramForAnyThreadCount) {
    const WarpCase& warp = testing::builtin_case("cosine_hemisphere");
    const chi2::Binning binning(warp.domain());
    RunOptions options;
    std::vector<chi2::Histogram> results;
    for (const unsigned threads : {1u, 2u, 3u}) {
        ThreadPool pool(threads);
        const CheckContext ctx(options, pool, stream_for(warp.name(), 3));
        const auto rng = [&](uint64_t chunk) { return ctx.chunk_rng(chunk); };
        results.push_back(lane_histogram(binning, 200'000, 4096, rng, *warp.info().lanes, {}, ctx.executor()));
    }
    expect_equal(results[1], results[0], "2 threads vs 1");
    expect_equal(results[2], results[0], "3 threads vs 1");
}

TEST(LaneSampling, ComparisonCanFail) {
    // Another warp's lane form gives another histogram, and the comparison sees it.
    const WarpCase& warp = testing::builtin_case("uniform_hemisphere");
    const chi2::Binning binning(warp.domain());
    RunOptions options;
    ThreadPool pool(1);
    const CheckContext ctx(options, pool, stream_for(warp.name(), 1));
    const auto rng = [&](uint64_t chunk) { return ctx.chunk_rng(chunk); };
    const chi2::Histogram other =
        lane_histogram(binning, 100'000, 4096, rng, builtin_lanes::cosine_hemisphere(), {}, ctx.executor());
    EXPECT_NE(other.counts, scalar_histogram(warp, binning, 100'000, {}, ctx).counts);
}

TEST(LaneSampling, RefusesWhatItCannotDo) {
    const chi2::Binning square(chi2::Domain::unit_square());
    const auto rng = [](uint64_t chunk) { return Pcg32(1, chunk); };
    EXPECT_THROW(lane_histogram(square, 10, 4096, rng, builtin_lanes::cosine_hemisphere(), {}, chi2::serial_for),
                 std::invalid_argument);
    if (!avx512_available()) {
        const chi2::Binning hemi(chi2::Domain::hemisphere());
        EXPECT_THROW(lane_histogram(hemi, 10, 4096, rng, builtin_lanes::cosine_hemisphere(), {}, chi2::serial_for,
                                    LanePath::Avx512),
                     std::runtime_error);
    }
}

TEST(LaneSampling, Chi2CheckGivesTheSameResultWithoutTheLaneForm) {
    // The built-in case (lanes) and the same warp registered without its lane
    // form (the scalar path): the same statistic, p-value and figures.
    const WarpCase& with_lanes = testing::builtin_case("cosine_hemisphere");
    WarpCaseInfo info = with_lanes.info();
    info.lanes = nullptr;
    const auto without = make_warp_case(info, CosineHemisphere{});
    RunOptions options;
    options.samples = 500'000;
    ThreadPool pool(2);
    const auto check = make_chi2_check();
    const CheckContext ctx(options, pool, stream_for(with_lanes.name(), options.seed));
    const CheckResult a = check->run(with_lanes, ctx), b = check->run(*without, ctx);
    EXPECT_EQ(a.verdict, b.verdict);
    EXPECT_EQ(a.p_value, b.p_value);
    EXPECT_EQ(a.summary, b.summary);
    EXPECT_EQ(a.message, b.message);
}

}  // namespace
}  // namespace warpcheck

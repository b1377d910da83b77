// The vectorised chi-square path (validate/lanes/lane_sampling.h) against the scalar
// one: for every built-in case with a lane form, on every code path (AVX-512
// and AVX2 where the processor has them, and the portable build), the histogram equals
// the one chi2::sample_histogram builds from draw_inputs and WarpCase::sample,
// field by field, including a partial last chunk and group, samples moved out
// of zero-expected cells, and any thread count. The chi-square check's result
// is the same with and without the lane form.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "chi2/chi2_test.h"
#include "sampling/hemisphere.h"
#include "sampling/sphere.h"
#include "support/builtin_case.h"
#include "validate/checks/check.h"
#include "validate/checks/checks.h"
#include "validate/lanes/lane_sampling.h"
#include "validate/api/registry.h"
#include "validate/run/thread_pool.h"
#include "validate/api/warp_case.h"

namespace warpcheck {
namespace {

const char* const kLaneCases[] = {"uniform_disk_polar",
                                  "uniform_disk_concentric",
                                  "cosine_hemisphere",
                                  "uniform_hemisphere",
                                  "uniform_sphere",
                                  "uniform_cone[cos_theta_max=-0.5]",
                                  "uniform_cone[cos_theta_max=0.99]",
                                  "cosine_power_hemisphere[exponent=0.5]",
                                  "cosine_power_hemisphere[exponent=50]",
                                  "trowbridge_reitz_normals[ax=0.05,ay=0.05]",
                                  "trowbridge_reitz_normals[ax=0.3,ay=0.05]",
                                  "trowbridge_reitz_visible[ax=0.05,ay=0.05,theta_o=0]",
                                  "trowbridge_reitz_visible[ax=0.3,ay=0.05,theta_o=85]"};

std::vector<LanePath> paths() {
    std::vector<LanePath> p = {LanePath::Portable};
    if (avx2_available()) p.push_back(LanePath::Avx2);
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
        const CheckContext ctx(options, pool.executor(), stream_for(warp.name(), 7));
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

// A case that keeps WarpCase's default sample_planar (through sample()).
class ConeThroughSpans final : public WarpCase {
public:
    ConeThroughSpans()
        : WarpCase({.family = "cone_through_spans", .domain = chi2::Domain::sphere()},
                   {.input = InputKind::Uniform2D, .output_dimension = 3}) {}
    void sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const override {
        for (std::size_t k = 0; k < in.size(); ++k) {
            const Vector3f v = cone_.sample({in[k].u[0], in[k].u[1]});
            out[k] = {v.x, v.y, v.z};
        }
    }
    void pdf(std::span<const WarpOutput> x, std::span<double> out) const override {
        for (std::size_t k = 0; k < x.size(); ++k) out[k] = cone_.pdf({x[k][0], x[k][1], x[k][2]});
    }
    void invert(std::span<const WarpOutput>, std::span<WarpInput>) const override {
        throw std::logic_error("no inverse");
    }

private:
    UniformCone cone_{0.3f};
};

// The lane path of warps without a lane form (planar_lane_sampler): every
// built-in 2D case the lanes can bin, a renderer's plain struct through
// make_warp_case, and a case with the default sample_planar.
TEST(LaneSampling, WarpsWithoutLaneFormBuildTheScalarHistogramOnEveryPath) {
    constexpr uint64_t kSamples = 300'007;  // a partial last chunk and group, as above
    RunOptions options;
    ThreadPool pool(2);
    std::vector<const WarpCase*> cases;
    Registry registry;
    register_builtin_cases(registry);
    for (const auto& c : registry.cases())
        if (c->input_kind() == InputKind::Uniform2D && chi2::Binning(c->domain()).lane_plan()) cases.push_back(c.get());
    WarpCaseInfo info = testing::builtin_case("cosine_hemisphere").info();
    info.lanes = nullptr;
    const auto plain = make_warp_case(info, CosineHemisphere{});
    const ConeThroughSpans spans;
    cases.push_back(plain.get());
    cases.push_back(&spans);
    ASSERT_GE(cases.size(), 15u);  // the five lane forms, cones, cosine powers, Trowbridge-Reitz, ...
    for (const WarpCase* warp : cases) {
        const CheckContext ctx(options, pool.executor(), stream_for(warp->name(), 5));
        const chi2::Binning binning(warp->domain());
        const chi2::Histogram expected = scalar_histogram(*warp, binning, kSamples, {}, ctx);
        for (const LanePath path : paths()) {
            const auto rng = [&](uint64_t chunk) { return ctx.chunk_rng(chunk); };
            const chi2::Histogram got = lane_histogram(binning, kSamples, 4096, rng, planar_lane_sampler(*warp), {},
                                                       ctx.executor(), path);
            expect_equal(got, expected, warp->name() + " planar on the " + lane_path_name(path) + " path");
        }
    }
}

TEST(LaneSampling, PlanarComparisonCanFail) {
    // Another warp's samples through the planar path give another histogram.
    const WarpCase& warp = testing::builtin_case("uniform_cone[cos_theta_max=0.3]");
    const WarpCase& other = testing::builtin_case("uniform_cone[cos_theta_max=0.99]");
    const chi2::Binning binning(warp.domain());
    RunOptions options;
    ThreadPool pool(1);
    const CheckContext ctx(options, pool.executor(), stream_for(warp.name(), 1));
    const auto rng = [&](uint64_t chunk) { return ctx.chunk_rng(chunk); };
    const chi2::Histogram got =
        lane_histogram(binning, 100'000, 4096, rng, planar_lane_sampler(other), {}, ctx.executor());
    EXPECT_NE(got.counts, scalar_histogram(warp, binning, 100'000, {}, ctx).counts);
}

TEST(LaneSampling, SameHistogramForAnyThreadCount) {
    const WarpCase& warp = testing::builtin_case("cosine_hemisphere");
    const chi2::Binning binning(warp.domain());
    RunOptions options;
    std::vector<chi2::Histogram> results;
    for (const unsigned threads : {1u, 2u, 3u}) {
        ThreadPool pool(threads);
        const CheckContext ctx(options, pool.executor(), stream_for(warp.name(), 3));
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
    const CheckContext ctx(options, pool.executor(), stream_for(warp.name(), 1));
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
    if (!avx2_available()) {
        const chi2::Binning hemi(chi2::Domain::hemisphere());
        EXPECT_THROW(lane_histogram(hemi, 10, 4096, rng, builtin_lanes::cosine_hemisphere(), {}, chi2::serial_for,
                                    LanePath::Avx2),
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
    const CheckContext ctx(options, pool.executor(), stream_for(with_lanes.name(), options.seed));
    const CheckResult a = check->run(with_lanes, ctx), b = check->run(*without, ctx);
    EXPECT_EQ(a.verdict, b.verdict);
    EXPECT_EQ(a.p_value, b.p_value);
    EXPECT_EQ(a.summary, b.summary);
    EXPECT_EQ(a.message, b.message);
}

}  // namespace
}  // namespace warpcheck

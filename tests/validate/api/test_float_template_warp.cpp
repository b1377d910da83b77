// Warps written as a template over their float type (validate/api/float_template_warp.h):
// the lane instantiation gives the float instantiation's bits, the lane path's
// histogram is the scalar path's count for count, and a lane instantiation that
// differs is refused. This file is compiled with -ffp-contract=fast
// (tests/CMakeLists.txt), as a renderer's GNU-mode build is: the lane
// instantiation must still match, FMA or not.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <type_traits>

#include "chi2/chi2_test.h"
#include "sampling/hemisphere.h"
#include "sampling/lanes.h"
#include "sampling/math.h"
#include "sampling/sphere.h"
#include "validate/api/float_template_warp.h"
#include "validate/checks/check.h"
#include "validate/checks/checks.h"
#include "validate/lanes/lane_sampling.h"
#include "validate/run/thread_pool.h"

namespace warpcheck {
namespace {

// A renderer's own point types, templated on the float type.
template <typename F>
struct Vec2 {
    F x, y;
};
template <typename F>
struct Vec3 {
    F x, y, z;
};

/// The uniform cone (sampling/sphere.h), written once over its float type.
struct TemplatedCone {
    float cos_theta_max = 0.3f;

    template <typename F>
    Vec3<F> sample(Vec2<F> u) const {
        const F one_minus_cos = u.x * (1.0f - cos_theta_max);
        const F z = 1.0f - one_minus_cos;
        const F r = lanes::safe_sqrt(one_minus_cos * (2.0f - one_minus_cos));
        const auto sc = lanes::sin_cos(kTwoPi * u.y);
        return {r * sc.cos, r * sc.sin, z};
    }
    float pdf(Vector3f v) const { return UniformCone(cos_theta_max).pdf(v); }
    Point2f invert(Vector3f v) const { return UniformCone(cos_theta_max).invert(v); }
};

/// Sums of products, each product used once: a build that contracts fuses them
/// where the target has FMA (the lane instantiation's, were FMA allowed there).
struct SumsOfProducts {
    template <typename F>
    Vec3<F> sample(Vec2<F> u) const {
        const F a = u.x * 0.7f + u.y * 0.3f;
        const F b = u.y * u.y - u.x * 0.25f;
        return {a, b, a * b + 0.125f};
    }
    float pdf(Vector3f) const { return 1.0f; }
};

/// x * 0.7 + y * 0.3 in a function built for x86-64-v4 (FMA allowed): fused here,
/// as this file is built with -ffp-contract=fast.
[[gnu::target("arch=x86-64-v3")]] float sum_of_products_with_fma(float x, float y) { return x * 0.7f + y * 0.3f; }

/// A template whose lane instantiation is off by one rounding from its float one.
struct SplitTemplate {
    template <typename F>
    Vec3<F> sample(Vec2<F> u) const {
        Vec3<F> p = TemplatedCone{0.0f}.sample(u);
        if constexpr (!std::is_same_v<F, float>) p.z = p.z * (1.0f + 0x1p-23f);
        return p;
    }
    float pdf(Vector3f v) const { return UniformHemisphere{}.pdf(v); }
};

/// A disk warp: its sample returns a 2D point.
struct TemplatedDisk {
    template <typename F>
    Vec2<F> sample(Vec2<F> u) const {
        const F r = lanes::sqrt(u.x);
        const auto sc = lanes::sin_cos(kTwoPi * u.y);
        return {r * sc.cos, r * sc.sin};
    }
    float pdf(Point2f p) const { return p.x * p.x + p.y * p.y <= 1.0f ? kInvPi : 0.0f; }
};

template <typename W>
const std::string& refused(const WarpCase& c) {
    return dynamic_cast<const detail::FloatTemplateWarpCase<W>&>(c).lane_form_refused();
}

/// The histogram of `samples` samples by the scalar chunks and by each lane path, which must agree.
void expect_lane_histograms_match(const WarpCase& warp) {
    RunOptions options;
    ThreadPool pool(2);
    const CheckContext ctx(options, pool.executor(), stream_for(warp.name(), 3));
    const chi2::Binning binning(warp.domain());
    constexpr uint64_t kSamples = 300'007;  // a partial last chunk and group of chunks
    const chi2::Histogram expected =
        chi2::sample_histogram(binning, kSamples, 4096, chi2_sample_chunks(warp, ctx), {}, ctx.executor());
    ASSERT_EQ(expected.total(), kSamples);
    std::vector<LanePath> paths = {LanePath::Portable};
    if (avx2_available()) paths.push_back(LanePath::Avx2);
    if (avx512_available()) paths.push_back(LanePath::Avx512);
    for (const LanePath path : paths) {
        const auto rng = [&](uint64_t chunk) { return ctx.chunk_rng(chunk); };
        const chi2::Histogram got =
            lane_histogram(binning, kSamples, 4096, rng, planar_lane_sampler(warp), {}, ctx.executor(), path);
        EXPECT_EQ(got.counts, expected.counts) << warp.name() << " on the " << lane_path_name(path) << " path";
        EXPECT_EQ(got.outside, expected.outside);
    }
}

TEST(FloatTemplateWarp, ItsFloatInstantiationIsTheWarpEveryCheckSees) {
    const auto c = make_warp_case({.family = "templated_cone", .domain = chi2::Domain::spherical_cap(0.3)},
                                  TemplatedCone{});
    EXPECT_TRUE(c->has_inverse());
    const UniformCone plain(0.3f);
    for (const float a : {0.0f, 0.1f, 0.5f, 0.9999f})
        for (const float b : {0.0f, 0.3f, 0.75f}) {
            const WarpInput in{{a, b}, 0};
            WarpOutput out{};
            c->sample(std::span(&in, 1), std::span(&out, 1));
            const Vector3f v = plain.sample({a, b});
            EXPECT_EQ(out, (WarpOutput{v.x, v.y, v.z}));
        }
}

TEST(FloatTemplateWarp, ItsLaneInstantiationGivesTheSameBitsAndHistogram) {
    for (const float c : {-0.5f, 0.3f, 0.99f}) {
        const auto warp = make_warp_case(
            {.family = "templated_cone", .params = {{"c", c}}, .domain = chi2::Domain::spherical_cap(c)},
            TemplatedCone{c});
        if (detail::processor_runs_lanes()) {
            EXPECT_EQ(refused<TemplatedCone>(*warp), "") << "cos_theta_max " << c;
        }
        expect_lane_histograms_match(*warp);
    }
    const auto disk = make_warp_case({.family = "templated_disk", .domain = chi2::Domain::unit_disk()}, TemplatedDisk{});
    if (detail::processor_runs_lanes()) {
        EXPECT_EQ(refused<TemplatedDisk>(*disk), "");
    }
    EXPECT_FALSE(disk->has_inverse());
    expect_lane_histograms_match(*disk);
}

TEST(FloatTemplateWarp, ContractionDoesNotReachTheLaneInstantiation) {
    if (!avx2_available()) GTEST_SKIP() << "no AVX2 (x86-64-v3, with FMA) here: the control below needs it";
    // This file's build contracts a * b + c where the target has FMA: the control differs.
    int fused = 0;
    for (int i = 1; i < 1000; ++i) {
        const float x = 1.0f / static_cast<float>(i), y = static_cast<float>(i) / 1000.0f;
        fused += sum_of_products_with_fma(x, y) != x * 0.7f + y * 0.3f;
    }
    ASSERT_GT(fused, 0) << "this file is not built with -ffp-contract=fast, or FMA is not used: the test shows nothing";
    const auto warp = make_warp_case({.family = "sums_of_products", .domain = chi2::Domain::sphere()}, SumsOfProducts{});
    EXPECT_EQ(refused<SumsOfProducts>(*warp), "");
}

TEST(FloatTemplateWarp, ALaneInstantiationThatDiffersIsRefusedAndTheScalarOneUsed) {
    const auto warp = make_warp_case({.family = "split_template", .domain = chi2::Domain::hemisphere()},
                                     SplitTemplate{});
    EXPECT_NE(refused<SplitTemplate>(*warp), "");
    expect_lane_histograms_match(*warp);
}

TEST(FloatTemplateWarp, TheChiSquareCheckPassesOnTheLanePath) {
    const auto warp = make_warp_case({.family = "templated_cone", .domain = chi2::Domain::spherical_cap(0.3)},
                                     TemplatedCone{});
    RunOptions options;
    options.samples = 200'000;
    ThreadPool pool(2);
    const CheckContext ctx(options, pool.executor(), stream_for(warp->name(), 1));
    const CheckResult r = make_chi2_check()->run(*warp, ctx);
    EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
}

}  // namespace
}  // namespace warpcheck

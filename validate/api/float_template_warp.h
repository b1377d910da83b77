// A warp written once as a template over its float type, as Mitsuba 3's
// warp.h is written over Value: make_warp_case instantiates its sample on
// float for every check, and on eight floats at once (lanes::F32,
// sampling/lanes.h) for the chi-square check's lane path, which then draws,
// warps and bins eight samples at a time with no scalar call between.
//
//   template <typename F> struct Vec2 { F x, y; };
//   template <typename F> struct Vec3 { F x, y, z; };
//   struct MyCone {
//       float cos_theta_max;
//       template <typename F> Vec3<F> sample(Vec2<F> u) const;  // the one definition
//       float pdf(Vector3f v) const;
//       Point2f invert(Vector3f v) const;                       // optional
//   };
//   registry.add_case(make_warp_case(info, MyCone{0.3f}));
//
// What the template must be: a member `template <typename Float> ... sample(P u)
// const` where P is an aggregate of two Float (u.x, u.y), returning a point
// with members x, y (and z) of type Float; its arithmetic written so that it
// compiles for Float = lanes::F32: the operators of float, comparisons inside
// ?: (a lane mask there), and the functions of warpcheck::lanes, which take a
// float or lanes of floats alike (sqrt, safe_sqrt, sin_from_cos, sin_cos, pow,
// abs, max_zero, select). pdf and invert stay plain functions of float.
//
// The lane instantiation is compiled for AVX-512 in a function of its own
// (and for AVX2 without FMA in another, run by processors without AVX-512),
// with the warp inlined into it, and with contraction off: the renderer's
// build may contract a * b + c into one rounding (GCC in GNU mode, Clang by
// default), which its scalar build on the baseline target cannot, and the two
// would then differ (tests/validate/api/test_float_template_warp.cpp builds with
// -ffp-contract=fast to hold it to that). Clang decides contraction where the
// warp is written, so under Clang the lane instantiation is built for AVX2
// without FMA instead. Whatever else could make them differ, the
// case compares the two forms when it is made (the edge inputs of each
// coordinate against each other, and 4,096 others): the lane form is used
// only where it gave the scalar form's bits on all of them, and
// lane_form_refused() says why not otherwise. Either way the figures are the
// scalar form's: the lane path's histogram is the scalar path's, count for
// count (tests/validate/api/test_float_template_warp.cpp).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstring>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "sampling/lanes.h"
#include "sampling/pcg32.h"
#include "validate/api/warp_case.h"

// GCC notes the ABI of lane vectors passed by value wherever a function that
// takes them is built for the baseline target: the warp's lane instantiation
// is, besides its inlined copies in the AVX-512 and AVX2 functions below, and GCC reports
// that at the end of the file, beyond any push and pop. No vector crosses a
// call there (everything is inlined), so the note is off for a file that
// includes this header.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace warpcheck {

namespace detail {

/// Whether W's sample is a template that instantiates on float and on lanes.
template <typename W>
concept FloatTemplateSample = requires(const W& w, lanes::F32 v) {
    w.template sample<float>({0.0f, 0.0f}).y;
    w.template sample<lanes::F32>({v, v}).y;
};

/// The z of a point that has one, else 0.
template <typename P, typename F>
[[gnu::always_inline]] inline F z_of(const P& p, F zero) {
    if constexpr (requires { p.z; }) return p.z;
    else return zero;
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define WARPCHECK_FLOAT_TEMPLATE_LANES 1

// How the lane instantiation is built (see the top of this file): for AVX-512
// with contraction off (GCC contracts after inlining, under the function's own
// setting), and a second time for AVX2 without FMA for processors without
// AVX-512; Clang contracts where the warp is written, so there once, for AVX2
// without FMA, which has nothing to contract into.
#if defined(__clang__)
#define WARPCHECK_LANE_INSTANTIATION [[gnu::target("avx2,no-fma"), gnu::flatten]]
#define WARPCHECK_LANE_INSTANTIATION_AVX2 WARPCHECK_LANE_INSTANTIATION
#else
#define WARPCHECK_LANE_INSTANTIATION [[gnu::target("arch=x86-64-v4"), gnu::optimize("fp-contract=off"), gnu::flatten]]
#define WARPCHECK_LANE_INSTANTIATION_AVX2 \
    [[gnu::target("arch=x86-64-v3,no-fma"), gnu::optimize("fp-contract=off"), gnu::flatten]]
#endif

/// The lane instantiation of W's sample over planar arrays, eight at a time
/// (the last n % 8 by the scalar instantiation), inlined into each target's
/// function below.
template <typename W>
[[gnu::always_inline]] inline void sample_planar_lane_loop(const W& warp, const float* u0, const float* u1, float* x,
                                                           float* y, float* z, std::size_t n) {
    constexpr std::size_t kWidth = lanes::kWidth;
    std::size_t i = 0;
    for (; i + kWidth <= n; i += kWidth) {
        lanes::F32 a, b;
        std::memcpy(&a, u0 + i, sizeof a);
        std::memcpy(&b, u1 + i, sizeof b);
        const auto p = warp.template sample<lanes::F32>({a, b});
        const lanes::F32 pz = z_of(p, lanes::F32{});
        std::memcpy(x + i, &p.x, sizeof a);
        std::memcpy(y + i, &p.y, sizeof a);
        std::memcpy(z + i, &pz, sizeof a);
    }
    for (; i < n; ++i) {
        const auto p = warp.template sample<float>({u0[i], u1[i]});
        x[i] = p.x, y[i] = p.y, z[i] = z_of(p, 0.0f);
    }
}

/// The lane instantiation built for AVX-512 (Clang: AVX2 without FMA).
template <typename W>
WARPCHECK_LANE_INSTANTIATION void sample_planar_lanes_wide(const W& warp, const float* u0, const float* u1, float* x,
                                                           float* y, float* z, std::size_t n) {
    sample_planar_lane_loop(warp, u0, u1, x, y, z, n);
}

/// The lane instantiation built for AVX2 without FMA.
template <typename W>
WARPCHECK_LANE_INSTANTIATION_AVX2 void sample_planar_lanes_avx2(const W& warp, const float* u0, const float* u1,
                                                                float* x, float* y, float* z, std::size_t n) {
    sample_planar_lane_loop(warp, u0, u1, x, y, z, n);
}

/// Which lane instantiation this processor runs: 2 for the AVX-512 one (AVX-512
/// F, CD, BW, DQ, VL, as validate/lanes/lane_sampling.h asks; under Clang, AVX2),
/// 1 for the AVX2 one (x86-64-v3), 0 for none.
inline int processor_lane_instantiation() {
    static const int level = [] {
        __builtin_cpu_init();
#if defined(__clang__)
        return __builtin_cpu_supports("avx2") ? 2 : 0;
#else
        if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
            __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
            __builtin_cpu_supports("avx512vl"))
            return 2;
        return __builtin_cpu_supports("x86-64-v3") ? 1 : 0;
#endif
    }();
    return level;
}

/// Whether this processor runs a lane instantiation.
inline bool processor_runs_lanes() { return processor_lane_instantiation() != 0; }

/// The lane instantiation of W's sample over planar arrays, the one this
/// processor runs (processor_runs_lanes() must be true).
template <typename W>
void sample_planar_lanes(const W& warp, const float* u0, const float* u1, float* x, float* y, float* z,
                         std::size_t n) {
    if (processor_lane_instantiation() == 2) return sample_planar_lanes_wide(warp, u0, u1, x, y, z, n);
    sample_planar_lanes_avx2(warp, u0, u1, x, y, z, n);
}
#endif

/// Why the lane instantiation cannot stand in for the scalar one: empty when
/// it gives the same bits on the edge inputs of each coordinate against each
/// other and on 4,096 inputs from a fixed stream.
template <typename W>
std::string lane_mismatch(const W& warp) {
#ifndef WARPCHECK_FLOAT_TEMPLATE_LANES
    (void)warp;
    return "the lane instantiation is built for x86-64 only";
#else
    if (!processor_runs_lanes()) return "this processor has neither AVX-512 nor AVX2";
    std::vector<float> edges = {0.0f, 0.25f, 0.75f, 0x1.fffffep-1f};
    for (int k = 1; k <= 40; ++k) edges.push_back(std::ldexp(1.0f, -k));
    std::vector<float> u0, u1;
    for (const float a : edges)
        for (const float b : edges) u0.push_back(a), u1.push_back(b);
    Pcg32 rng(0x5eed, 27);
    while (u0.size() < 4096 + edges.size() * edges.size()) u0.push_back(rng.next_float()), u1.push_back(rng.next_float());
    const std::size_t n = u0.size() / lanes::kWidth * lanes::kWidth;
    std::vector<float> x(n), y(n), z(n);
    sample_planar_lanes(warp, u0.data(), u1.data(), x.data(), y.data(), z.data(), n);
    for (std::size_t i = 0; i < n; ++i) {
        const auto p = warp.template sample<float>({u0[i], u1[i]});
        const float expected[3] = {p.x, p.y, z_of(p, 0.0f)}, got[3] = {x[i], y[i], z[i]};
        if (std::memcmp(expected, got, sizeof got) != 0)
            return "its lane instantiation differs from its float instantiation at u = (" + std::to_string(u0[i]) +
                   ", " + std::to_string(u1[i]) + ")";
    }
    return {};
#endif
}

/// A case whose warp's sample is a template over the float type: the scalar
/// instantiation's case (make_warp_case of the plain warp object), whose
/// sample_planar takes the lane instantiation where it was found to agree.
template <typename W>
class FloatTemplateWarpCase final : public WarpCase {
public:
    FloatTemplateWarpCase(std::unique_ptr<WarpCase> scalar, W warp)
        : WarpCase(scalar->info(), scalar->signature()), scalar_(std::move(scalar)), warp_(std::move(warp)),
          refused_(lane_mismatch(warp_)) {}

    const std::string& lane_form_refused() const { return refused_; }

    void sample_planar(const float* u0, const float* u1, float* x, float* y, float* z, std::size_t n) const override {
#ifdef WARPCHECK_FLOAT_TEMPLATE_LANES
        if (refused_.empty()) return sample_planar_lanes(warp_, u0, u1, x, y, z, n);
#endif
        scalar_->sample_planar(u0, u1, x, y, z, n);
    }
    void sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const override { scalar_->sample(in, out); }
    void pdf(std::span<const WarpOutput> x, std::span<double> out) const override { scalar_->pdf(x, out); }
    void invert(std::span<const WarpOutput> x, std::span<WarpInput> out) const override { scalar_->invert(x, out); }

private:
    std::unique_ptr<WarpCase> scalar_;
    W warp_;
    std::string refused_;
};

}  // namespace detail

/// A warp object whose sample is a template over the float type (this file's
/// top), with a plain pdf and, where it has one, a plain invert.
template <typename W>
concept FloatTemplateWarp = detail::FloatTemplateSample<W> && detail::warp_has_pdf<W>;

/// Makes the case of a warp written as a template over its float type: the
/// float instantiation is the warp every check sees, a warp object whose
/// sample takes a Point2f and returns pdf's argument; the chi-square check's
/// lane path runs the lane instantiation where it gives the same bits.
template <FloatTemplateWarp W>
std::unique_ptr<WarpCase> make_warp_case(WarpCaseInfo info, W warp) {
    using Out = typename detail::CallOf<decltype(&W::pdf)>::Arg;
    const auto sampled = warp_of([warp](Point2f u) {
                             const auto p = warp.template sample<float>({u.x, u.y});
                             if constexpr (requires { Out{p.x, p.y, detail::z_of(p, 0.0f)}; })
                                 return Out{p.x, p.y, detail::z_of(p, 0.0f)};
                             else
                                 return Out{p.x, p.y};
                         }).with_pdf([warp](Out x) { return warp.pdf(x); });
    std::unique_ptr<WarpCase> scalar;
    if constexpr (detail::warp_has_invert<W>)
        scalar = make_warp_case(std::move(info), sampled.with_invert([warp](Out x) { return warp.invert(x); }));
    else
        scalar = make_warp_case(std::move(info), sampled);
    return std::make_unique<detail::FloatTemplateWarpCase<W>>(std::move(scalar), std::move(warp));
}

}  // namespace warpcheck

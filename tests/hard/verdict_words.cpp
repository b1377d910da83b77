// Class 8 of issue 22: verdict words.
//
// - nan_everywhere_1d (sample, pdf and inverse), nan_everywhere_sphere (the
//   samples, beside a valid pdf): warps that return NaN for every input. Wrong, and plainly so: every check that runs must say FAIL (the
//   warp ran and its output is wrong), never ERROR (which says the check could
//   not run: today three rows were ERRORs blaming a discontinuous density).
// - Rows that test nothing must say n/a, and passing rows must not show NaN
//   figures: run_hard.sh asserts both over every row of the catalogue (an
//   unbinned row that judged no marginal, as on hg_float[g=0.99], rect_light
//   and sliver_light; "binade mass nan", "+nan"). unit_interval_1_2: a float
//   of [1, 2) from the top 23 of 64 bits, every float of that binade equally
//   likely. Correct: exactly uniform on the binade's floats. Its binade row
//   passes with a NaN mass test (one binade has no degree of freedom) and a
//   "+nan" power figure.
// - The known-flaw marks must agree with the rules: lerp_blend is marked as a
//   flaw in validate/cases/interval.cpp while its row passes and reports its
//   steps down. Here a renderer's lerp used for stratified sampling claims to
//   be monotone: (1 - t) a + t b over [0.2, 0.3) steps down and reaches b, and
//   is marked as the twin of a + t (b - a) over [-3, 5), which is monotone and
//   never reaches b on the 2^-24 grid; run_hard.sh asserts that every mark is
//   caught by the check it names.
#include <cstdint>
#include <limits>

#include "hard_warps.h"

namespace hard {
namespace {

using warpcheck::chi2::Domain;
using warpcheck::InputKind;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Everything NaN: sample, pdf and inverse (a warp whose parameters went NaN).
struct NanInterval {
    float sample(float) const { return kNaN; }
    float pdf(float) const { return kNaN; }
    float invert(float) const { return kNaN; }
};

// Only the samples NaN, beside a valid density.

struct NanSphere {
    Vector3f sample(Point2f) const { return {kNaN, kNaN, kNaN}; }
    float pdf(Vector3f) const { return 1 / (4 * kPi); }
};

/// t = (u >> 8) 2^-24, then the lerp: the 2^-24 grid of a renderer's lerp.
float lerp_of_bits(uint32_t u, float a, float b, bool blend) {
    const float t = static_cast<float>(u >> 8) * 0x1p-24f;
    return blend ? (1 - t) * a + t * b : a + t * (b - a);
}

void register_nan_free_rows(warpcheck::Registry& registry) {
    registry.add_case(warpcheck::make_u64_float_case(
        {.family = "unit_interval_1_2",
         .description = "1 + (u >> 41) 2^-23: every float of [1, 2) from 64 bits",
         .domain = Domain::interval(1, 2)},
        {.shift = 41}, warpcheck::Monotone::Claimed,
        warpcheck::warp_of([](uint64_t u) { return 1 + static_cast<float>(u >> 41) * 0x1p-23f; })
            .with_pdf([](float x) { return x >= 1 && x < 2 ? 1.0f : 0.0f; })));
}

}  // namespace

void register_verdict_words(warpcheck::Registry& registry) {
    registry.add_case(warpcheck::make_warp_case({.family = "nan_everywhere_1d",
                                                 .description = "sample, pdf and inverse return NaN for every input",
                                                 .domain = Domain::interval(0, 1)},
                                                NanInterval{}));
    mark_twin(registry, "nan_everywhere_1d", "every check", "sample, pdf and inverse are NaN");
    registry.add_case(warpcheck::make_warp_case(
        {.family = "nan_everywhere_sphere", .description = "returns NaN for every input; pdf 1/(4 pi)",
         .domain = Domain::sphere()},
        NanSphere{}));
    mark_twin(registry, "nan_everywhere_sphere", "every check", "every sample is NaN");
    register_nan_free_rows(registry);

    registry.add_case(warpcheck::make_u32_float_case(
        {.family = "lerp_offset_bits", .params = {{"a", -3}, {"b", 5}},
         .description = "a + t (b - a), t the top 24 of 32 bits: monotone, as claimed",
         .domain = Domain::interval(-3, 5)},
        warpcheck::Monotone::Claimed,
            warpcheck::warp_of([](uint32_t u) { return lerp_of_bits(u, -3, 5, false); })
                .with_pdf([](float x) { return x >= -3 && x < 5 ? 0.125f : 0.0f; })));
    registry.add_case(warpcheck::make_u32_float_case(
        {.family = "lerp_blend_bits", .params = {{"a", 0.2}, {"b", 0.3}},
         .description = "(1 - t) a + t b, t the top 24 of 32 bits, claimed monotone",
         .domain = Domain::interval(0.2f, 0.3f)},
        warpcheck::Monotone::Claimed,
            warpcheck::warp_of([](uint32_t u) { return lerp_of_bits(u, 0.2f, 0.3f, true); })
                .with_pdf([](float x) { return x >= 0.2f && x < 0.3f ? 10.0f : 0.0f; })));
    mark_twin(registry, "lerp_blend_bits[a=0.2,b=0.3]", "exhaustive", "steps down although claimed monotone, reaches b");
}

}  // namespace hard

// The exhaustive check's fast path opened to external samplers
// (validate/api/external.h): a renderer's u32 -> float and u64 -> float samplers,
// monotone by claim or not.
#include <gtest/gtest.h>

#include <cstdint>

#include "support/check_harness.h"
#include "validate/checks/checks.h"
#include "validate/api/external.h"

namespace warpcheck {
namespace {

// A renderer's own samplers, as plain functions outside warpcheck.
float renderer_unit_float(uint32_t u) { return static_cast<float>(u >> 8) * 0x1p-24f; }
float renderer_unit_float_pdf(float x) { return x >= 0.0f && x < 1.0f ? 1.0f : 0.0f; }
// A permutation of the 2^-24 grid by the high 24 bits of a u64: every value of
// the grid once, in scrambled order (not monotone).
float renderer_scrambled_unit_float(uint64_t u) {
    const auto k = static_cast<uint32_t>(u >> 40);
    return static_cast<float>((k * 2654435761u) & 0xffffffu) * 0x1p-24f;
}

WarpCaseInfo unit_interval_info(const char* family) {
    return {.family = family, .description = "a renderer's [0,1) sampler", .domain = chi2::Domain::interval(0, 1)};
}

TEST(ExternalSweep, U32SamplerIsSweptOverAllInputsOnTheFastPath) {
    const auto warp = make_u32_float_case(
        unit_interval_info("renderer_unit_float"), Monotone::Claimed,
            warp_of([](uint32_t u) { return renderer_unit_float(u); })
                .with_pdf(renderer_unit_float_pdf)
                .with_invert([](float x) { return static_cast<uint32_t>(x * 0x1p24f) << 8; }));
    const auto* sweepable = dynamic_cast<const SweepableCase*>(warp.get());
    ASSERT_NE(sweepable, nullptr);
    EXPECT_EQ(warp->input_kind(), InputKind::Bits32);
    EXPECT_EQ(sweepable->sweep_inputs(), uint64_t{1} << 32);
    EXPECT_TRUE(sweepable->claims_monotone());
    const auto check = make_exhaustive_check();
    ASSERT_TRUE(check->applies_to(*warp));
    const CheckResult r = testing::run_check(*check, *warp);
    EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
    EXPECT_EQ(r.figure("distinct"), double(1 << 24));
    EXPECT_EQ(r.figure("non_monotone_steps"), 0.0);
}

// The same non-monotone u64 sampler over a 2^24-input subrange: swept and
// recounted exactly when monotonicity is not claimed (every grid value once:
// a pass), a failure when it is.
TEST(ExternalSweep, U64SubrangeMonotoneClaimDecidesTheVerdict) {
    const auto check = make_exhaustive_check();
    for (const Monotone claim : {Monotone::NotClaimed, Monotone::Claimed}) {
        const auto warp = make_u64_float_case(unit_interval_info("renderer_scrambled"), {.shift = 40}, claim,
                                              warp_of(renderer_scrambled_unit_float)
                                                  .with_pdf(renderer_unit_float_pdf));
        const auto* sweepable = dynamic_cast<const SweepableCase*>(warp.get());
        ASSERT_NE(sweepable, nullptr);
        EXPECT_EQ(sweepable->sweep_inputs(), uint64_t{1} << 24);
        const CheckResult r = testing::run_check(*check, *warp);
        EXPECT_EQ(r.figure("distinct"), double(1 << 24));
        EXPECT_GT(r.figure("non_monotone_steps").value_or(0), 1e6);
        EXPECT_EQ(r.verdict, claim == Monotone::Claimed ? Verdict::Fail : Verdict::Pass) << r.message;
    }
}

TEST(ExternalSweep, RejectsNonIntervalDomainsAndBadSubranges) {
    WarpCaseInfo square = unit_interval_info("bad");
    square.domain = chi2::Domain::unit_square();
    EXPECT_THROW(make_u32_float_case(square, Monotone::Claimed,
        warp_of(renderer_unit_float).with_pdf(renderer_unit_float_pdf)),
                 std::invalid_argument);
    EXPECT_THROW(make_u64_float_case(unit_interval_info("bad"), {.shift = 31}, Monotone::Claimed,
                                     warp_of(renderer_scrambled_unit_float).with_pdf(renderer_unit_float_pdf)),
                 std::invalid_argument);
}

}  // namespace
}  // namespace warpcheck

// The round-trip and consistency checks: correct warps pass, broken ones fail
// with their own message, NaN never passes.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "sampling/disk.h"
#include "sampling/hemisphere.h"
#include "sampling/sphere.h"
#include "support/builtin_case.h"
#include "support/check_harness.h"
#include "validate/checks/checks.h"

namespace warpcheck {
namespace {

using testing::run_check;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

WarpCaseInfo disk_info(const char* family) { return {family, {}, "test warp", InputKind::Uniform2D, chi2::Domain::unit_disk()}; }

TEST(RoundtripCheck, CorrectWarpPasses) {
    const CheckResult r = run_check(*make_roundtrip_check(), testing::builtin_case("uniform_disk_polar"));
    EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
    EXPECT_LT(*r.figure("max_error"), 1e-6);
    EXPECT_EQ(*r.figure("failures"), 0.0);
}

// The inverse forgets that r = sqrt(u.x): it returns r instead of r^2.
TEST(RoundtripCheck, InverseWithoutSquareFails) {
    auto warp = make_warp_case(
        disk_info("polar_broken"),
            warp_of([](Point2f u) { return UniformDiskPolar{}.sample(u); })
                .with_pdf([](Point2f x) { return UniformDiskPolar{}.pdf(x); })
                .with_invert([](Point2f p) {
                    return Point2f{std::sqrt(p.x * p.x + p.y * p.y), azimuth_to_unit(p.x, p.y)};
                }));
    const CheckResult r = run_check(*make_roundtrip_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_GT(*r.figure("failures"), 1000.0);
    EXPECT_GT(*r.figure("max_error"), 0.2);
    EXPECT_NE(r.message.find("come back further"), std::string::npos) << r.message;
    ASSERT_FALSE(r.tables.empty());
    EXPECT_FALSE(r.tables[0].rows.empty());
}

// An inverse that is off by half of a 1/64 cell in u.x.
TEST(RoundtripCheck, InverseOffByHalfACellFails) {
    auto warp = make_warp_case(
        disk_info("polar_shifted"),
            warp_of([](Point2f u) { return UniformDiskPolar{}.sample(u); })
                .with_pdf([](Point2f x) { return UniformDiskPolar{}.pdf(x); })
                .with_invert([](Point2f p) {
                    Point2f u = UniformDiskPolar{}.invert(p);
                    u.x = std::min(u.x + 1.0f / 128.0f, kOneMinusEpsilon);
                    return u;
                }));
    EXPECT_EQ(run_check(*make_roundtrip_check(), *warp).verdict, Verdict::Fail);
}

// NaN only at one edge of the input square must still fail: NaN never compares as small.
TEST(RoundtripCheck, NaNAtOneEdgeFails) {
    auto warp = make_warp_case(
        disk_info("polar_nan_edge"),
            warp_of([](Point2f u) { return UniformDiskPolar{}.sample(u); })
                .with_pdf([](Point2f x) { return UniformDiskPolar{}.pdf(x); })
                .with_invert([](Point2f p) {
                    Point2f u = UniformDiskPolar{}.invert(p);
                    if (u.x == 0.0f) u.y = kNaN;
                    return u;
                }));
    const CheckResult r = run_check(*make_roundtrip_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_GE(*r.figure("failures"), 4.0);  // the four edge inputs with u.x = 0
}

TEST(RoundtripCheck, RawBitInversesMustBeExact) {
    WarpCaseInfo info{"bits24", {}, "24-bit float", InputKind::Bits32, chi2::Domain::interval(0, 1)};
    info.exact_inverse = true;
    auto sample = [](uint32_t b) { return static_cast<float>(b >> 8) * 0x1p-24f; };
    auto pdf = [](float) { return 1.0f; };
    auto good = make_warp_case(info,
        warp_of(sample).with_pdf(pdf).with_invert([](float x) { return static_cast<uint32_t>(x * 0x1p24f) << 8; }));
    EXPECT_EQ(run_check(*make_roundtrip_check(), *good).verdict, Verdict::Pass);
    info.family = "bits24_last";  // returns the last preimage, not the first
    auto late = make_warp_case(info,
        warp_of(sample)
            .with_pdf(pdf)
            .with_invert([](float x) { return (static_cast<uint32_t>(x * 0x1p24f) << 8) | 0xffu; }));
    EXPECT_EQ(run_check(*make_roundtrip_check(), *late).verdict, Verdict::Fail);
}

TEST(ConsistencyCheck, CorrectWarpsPass) {
    const CheckResult r = run_check(*make_consistency_check(), testing::builtin_case("cosine_hemisphere"));
    EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
    // u.x = 0 reaches the rim, where cos(theta)/pi is 0: accepted, and counted.
    EXPECT_GE(*r.figure("zero_pdf_on_boundary"), 1.0);
}

TEST(ConsistencyCheck, EachViolationHasItsOwnMessage) {
    const auto domain = chi2::Domain::hemisphere();
    auto nan_sample = make_warp_case(
        {"nan_sample", {}, "", InputKind::Uniform2D, domain},
        warp_of([](Point2f u) {
                    Vector3f v = UniformHemisphere{}.sample(u);
                    if (u.x > 0.999f) v.x = kNaN;
                    return v;
                })
            .with_pdf([](Vector3f x) { return UniformHemisphere{}.pdf(x); })
            .with_invert([](Vector3f x) { return UniformHemisphere{}.invert(x); }));
    auto outside = make_warp_case(
        {"outside", {}, "", InputKind::Uniform2D, domain},
            warp_of([](Point2f u) { return UniformSphere{}.sample(u); })
                .with_pdf([](Vector3f) { return 0.5f; })
                .with_invert([](Vector3f x) { return UniformHemisphere{}.invert(x); }));
    auto zero_pdf = make_warp_case(
        {"zero_pdf", {}, "", InputKind::Uniform2D, domain},
            warp_of([](Point2f u) { return UniformHemisphere{}.sample(u); })
                .with_pdf([](Vector3f v) { return v.z > 0.5f ? 0.0f : 0.3f; })
                .with_invert([](Vector3f x) { return UniformHemisphere{}.invert(x); }));
    auto nan_pdf = make_warp_case(
        {"nan_pdf", {}, "", InputKind::Uniform2D, domain},
            warp_of([](Point2f u) { return UniformHemisphere{}.sample(u); })
                .with_pdf([](Vector3f v) { return v.z > 0.5f ? kNaN : 0.3f; })
                .with_invert([](Vector3f x) { return UniformHemisphere{}.invert(x); }));
    const auto check = make_consistency_check();
    const CheckResult a = run_check(*check, *nan_sample), b = run_check(*check, *outside),
                      c = run_check(*check, *zero_pdf), d = run_check(*check, *nan_pdf);
    EXPECT_EQ(a.verdict, Verdict::Fail);
    EXPECT_NE(a.message.find("NaN or infinite coordinates"), std::string::npos) << a.message;
    EXPECT_EQ(b.verdict, Verdict::Fail);
    EXPECT_NE(b.message.find("outside the hemisphere"), std::string::npos) << b.message;
    EXPECT_EQ(c.verdict, Verdict::Fail);
    EXPECT_NE(c.message.find("pdf 0 inside the domain"), std::string::npos) << c.message;
    EXPECT_EQ(d.verdict, Verdict::Fail);
    EXPECT_NE(d.message.find("NaN, infinite or negative pdf"), std::string::npos) << d.message;
}

}  // namespace
}  // namespace warpcheck

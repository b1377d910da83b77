// EXPECT_FUZZ_CLEAN: a family whose parameters are correct at every point of
// its declared ranges passes; one with a bug at the end of a range fails with
// the finding shrunk to that end and its rerun line; a family that declares
// no range is a failure that says so.
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "sampling/bsdf_diffuse.h"
#include "validate/api/bsdf_grid.h"
#include "validate/gtest/warpcheck_gtest.h"

namespace warpcheck {
namespace {

/// A Lambertian of reflectance R whose f turns NaN for R above 0.999 when `planted`.
struct EndBugDiffuse {
    float R;
    bool planted;
    BsdfFlags flags() const { return BsdfFlags::Reflection | BsdfFlags::Continuous; }
    float value() const { return planted && R > 0.999f ? std::numeric_limits<float>::quiet_NaN() : R / 3.14159265f; }
    BsdfSample sample(Vector3f wo, float uc, Point2f u) const {
        BsdfSample s = Lambertian(R).sample(wo, uc, u);
        if (s.pdf > 0.0f) s.f = value();
        return s;
    }
    float f(Vector3f wo, Vector3f wi) const { return Lambertian(R).f(wo, wi) > 0.0f ? value() : 0.0f; }
    float pdf(Vector3f wo, Vector3f wi) const { return Lambertian(R).pdf(wo, wi); }
};

/// The family over R in r_range and theta_o in [0, 90) (without ranges at all where r_range is empty).
CaseFamily diffuse_family(const char* name, bool planted, std::vector<ParamRange> r_range) {
    std::vector<ParamRange> theta_range;
    if (!r_range.empty()) theta_range = {{0, 90, false, true}};
    return {{.family = name, .description = "a Lambertian over its reflectance"},
            {{"R", {0.5}, std::move(r_range)}, {"theta_o", {30}, std::move(theta_range)}},
            [planted](WarpCaseInfo info, const GridPoint& p) {
                return make_bsdf_case(std::move(info), {.wo = grid_wo(p)},
                                      EndBugDiffuse{static_cast<float>(p["R"]), planted});
            }};
}

TEST(FuzzAssertion, ACorrectFamilyIsClean) {
    EXPECT_FUZZ_CLEAN(diffuse_family("fuzz_clean_diffuse", false, {{0, 1}}));
}

TEST(FuzzAssertion, ABugAtARangesEndFailsWithTheShrunkPointAndItsRerun) {
    EXPECT_NONFATAL_FAILURE(EXPECT_FUZZ_CLEAN(diffuse_family("fuzz_bug_diffuse", true, {{0, 1}})),
                            "shrunk to  fuzz_bug_diffuse[R=1,theta_o=0]");
    EXPECT_NONFATAL_FAILURE(EXPECT_FUZZ_CLEAN(diffuse_family("fuzz_bug_diffuse", true, {{0, 1}})),
                            "--fuzz-case 'fuzz_bug_diffuse[R=1,theta_o=0]'");
}

TEST(FuzzAssertion, AFamilyWithoutRangesIsAFailureThatSaysSo) {
    EXPECT_NONFATAL_FAILURE(EXPECT_FUZZ_CLEAN(diffuse_family("fuzz_no_range", false, {})), "declares no parameter range");
}

}  // namespace
}  // namespace warpcheck

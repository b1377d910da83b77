// A case declared inconsistently is refused where it is made (a case class
// written by hand, where it is registered), with one message that names the
// case and lists every problem; consistent declarations (every built-in case
// among them) are accepted.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "sampling/bsdf_diffuse.h"
#include "validate/api/bsdf_case.h"
#include "validate/api/case_grid.h"
#include "validate/api/external.h"
#include "validate/api/registry.h"

namespace warpcheck {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

/// The message with which making the case (by `make`) and registering it is
/// refused, or "".
template <typename Make>
std::string refusal(Make make) {
    Registry registry;
    try {
        registry.add_case(make());
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

MonotoneMarginal view(std::string label, double lo, double hi) {
    MonotoneMarginal m;
    m.label = std::move(label);
    m.lo = lo;
    m.hi = hi;
    return m;
}

auto linear_1d(WarpCaseInfo info) {
    return [info] {
        return make_warp_case(info, warp_of([](float u) { return u; }).with_pdf([](float) { return 1.0f; }));
    };
}

constexpr const char* kHeading = "warp case lin is declared inconsistently:\n  - ";

TEST(CaseValidation, AViewOutsideTheDomainIsRefused) {
    EXPECT_THAT(
        refusal(linear_1d({.family = "lin", .domain = chi2::Domain::interval(0, 1), .views = {view("x", 0.0, 2.0)}})),
        AllOf(HasSubstr(kHeading), HasSubstr("view 'x': [0, 2] lies outside the domain")));
    EXPECT_THAT(refusal(linear_1d(
                    {.family = "lin", .domain = chi2::Domain::lower_half_line(1), .views = {view("x", 0.0, 2.0)}})),
                HasSubstr("lies outside the domain half-line (-inf"));
    EXPECT_EQ(
        refusal(linear_1d({.family = "lin", .domain = chi2::Domain::interval(0, 1), .views = {view("x", 0.0, 1.0)}})),
        "");
}

TEST(CaseValidation, AViewOfAMissingInputCoordinateIsRefused) {
    MonotoneMarginal m = view("x", 0.0, 1.0);
    m.input_coordinate = 1;
    EXPECT_THAT(refusal(linear_1d({.family = "lin", .domain = chi2::Domain::interval(0, 1), .views = {m}})),
                AllOf(HasSubstr(kHeading), HasSubstr("input coordinate 1 does not exist")));
}

TEST(CaseValidation, ViewsNeedDistinctLabelsAndACoordinateOn2DDomains) {
    auto disk = [](std::vector<MonotoneMarginal> views) {
        return [views] {
            return make_warp_case({.family = "disk", .domain = chi2::Domain::unit_disk(), .views = views},
                                  warp_of([](Point2f u) { return Point2f{u.x - 0.5f, u.y - 0.5f}; })
                                      .with_pdf([](Point2f) { return 1.0f; }));
        };
    };
    MonotoneMarginal r = view("r", 0.0, 1.0);
    r.pdf = [](double x) { return 2.0 * x; };
    EXPECT_THAT(refusal(disk({r})), HasSubstr("needs a coordinate function on a 2-dimensional domain"));
    r.coordinate = [](const WarpOutput& o) { return std::hypot(o[0], o[1]); };
    EXPECT_EQ(refusal(disk({r})), "");
    EXPECT_THAT(refusal(disk({r, r})), HasSubstr("two views are labelled 'r'"));
}

TEST(CaseValidation, TypesThatDisagreeWithTheDeclarationAreRefused) {
    // A 1D warp on the default domain (the unit square), and one that states
    // an input its sample does not take: refused where the case is made.
    EXPECT_THAT(refusal(linear_1d({.family = "lin"})),
                AllOf(HasSubstr(kHeading), HasSubstr("its points have 1 coordinates, but the box")));
    EXPECT_THAT(refusal(linear_1d({.family = "lin", .input = InputKind::Uniform2D,
                                   .domain = chi2::Domain::interval(0, 1)})),
                AllOf(HasSubstr(kHeading), HasSubstr("its sample takes Uniform1D (a float) but .input is Uniform2D")));
    EXPECT_THAT(
        refusal(linear_1d({.family = "lin", .domain = chi2::Domain::interval(0, 1), .roundtrip_tolerance = 0.0})),
        HasSubstr("roundtrip_tolerance 0 is not in (0, 1)"));
}

// A case class written by hand is checked where it is registered, in the same words.
class HandWritten final : public WarpCase {
public:
    HandWritten()
        : WarpCase({.family = "lin", .domain = chi2::Domain::interval(0, 1), .roundtrip_tolerance = 2.0},
                   {.input = InputKind::Uniform1D, .output_dimension = 1}) {}
    void sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const override {
        for (std::size_t k = 0; k < in.size(); ++k) out[k] = {in[k].u[0], 0.0f, 0.0f};
    }
    void pdf(std::span<const WarpOutput>, std::span<double> out) const override {
        std::fill(out.begin(), out.end(), 1.0);
    }
    void invert(std::span<const WarpOutput>, std::span<WarpInput>) const override {}
};

TEST(CaseValidation, ACaseWrittenByHandIsRefusedWhereItIsRegistered) {
    EXPECT_THAT(refusal([] { return std::make_unique<HandWritten>(); }),
                AllOf(HasSubstr(kHeading), HasSubstr("roundtrip_tolerance 2 is not in (0, 1)")));
}

// A BSDF case states wo twice, in its name (theta_o, phi_o) and in its claims:
// where they disagree it is refused, so that no figure is reported under the
// name of a direction the BSDF was not seen from. A renderer's own float
// trigonometry for the same angles is accepted.
TEST(CaseValidation, ABsdfSeenFromAnotherDirectionThanItsNameIsRefused) {
    const auto lambertian = Lambertian(0.5f);
    const auto make = [&](std::vector<Parameter> params, Vector3f wo) {
        return [=] { return make_bsdf_case({.family = "lin", .params = params}, {.wo = wo}, lambertian); };
    };
    const Vector3f at30 = bsdf_direction(30.0);
    EXPECT_THAT(refusal(make({{"theta_o", 60}}, at30)),
                AllOf(HasSubstr("warp case lin[theta_o=60] is declared inconsistently"),
                      HasSubstr("is not the direction its name states: theta_o = 60")));
    const float r = 30.0f * 3.14159265f / 180.0f;  // a renderer's own float trigonometry
    EXPECT_NO_THROW(make({{"theta_o", 30}}, {std::sin(r), 0.0f, std::cos(r)})());
    EXPECT_NO_THROW(make({{"theta_o", 30}}, at30)());
    EXPECT_NO_THROW(make({{"alpha", 0.3}}, at30)()) << "a name that states no direction";
    // phi_o counts too; so does a theta_o in radians (0.5236 is 30 degrees).
    EXPECT_NO_THROW(make({{"theta_o", 30}, {"phi_o", 45}}, bsdf_direction(30.0, 45.0))());
    EXPECT_THAT(refusal(make({{"theta_o", 30}, {"phi_o", 45}}, at30)), HasSubstr("phi_o = 45"));
    EXPECT_THAT(refusal(make({{"theta_o", 0.5235987755982988}}, at30)), HasSubstr("its name states"));
}

// The other declarations a case is made from are refused in the same words:
// a BSDF's claims, a swept float sampler's domain and subrange, a grid's axes.
TEST(CaseValidation, EveryKindIsRefusedInTheSameWords) {
    const auto lambertian = Lambertian(0.5f);
    EXPECT_THAT(refusal([&] { return make_bsdf_case({.family = "lin"}, {.wo = {0.0f, 0.0f, 2.0f}}, lambertian); }),
                AllOf(HasSubstr(kHeading), HasSubstr("wo (0, 0, 2) is not a unit vector")));
    const auto unit = warp_of([](uint32_t u) { return float(u >> 8) * 0x1p-24f; }).with_pdf([](float) { return 1.0f; });
    EXPECT_THAT(refusal([&] {
                    return make_u32_float_case({.family = "lin", .domain = chi2::Domain::half_line(0)},
                                               Monotone::Claimed, unit);
                }),
                AllOf(HasSubstr(kHeading), HasSubstr("a float sampler swept exhaustively needs an interval")));
    const auto unit64 =
        warp_of([](uint64_t u) { return float(u >> 40) * 0x1p-24f; }).with_pdf([](float) { return 1.0f; });
    EXPECT_THAT(refusal([&] {
                    return make_u64_float_case({.family = "lin", .domain = chi2::Domain::interval(0, 1)},
                                               {.shift = 20}, Monotone::Claimed, unit64);
                }),
                AllOf(HasSubstr(kHeading), HasSubstr("its U64Subrange needs 32 <= shift < 64")));
    Registry registry;
    try {
        add_case_grid(registry, {.family = "lin", .domain = chi2::Domain::interval(0, 1)}, {{"a", {}}, {"a", {1}}},
                      [](WarpCaseInfo, const GridPoint&) { return std::unique_ptr<WarpCase>(); });
        ADD_FAILURE() << "a grid without values was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(),
                     "parameter grid of lin is declared inconsistently:\n  - axis a has no values\n"
                     "  - two parameters are named a");
    }
}

TEST(CaseValidation, EveryBuiltInCaseIsConsistent) {
    Registry registry;
    EXPECT_NO_THROW(register_builtin_cases(registry));
    EXPECT_NO_THROW(register_flawed_interval_cases(registry));
    EXPECT_NO_THROW(register_flawed_bsdf_cases(registry));
}

}  // namespace
}  // namespace warpcheck

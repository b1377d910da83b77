// A case declared inconsistently is refused at registration, with a message
// that names the case and the problem; consistent declarations (every built-in
// case among them) are accepted.
#include <cmath>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "validate/api/registry.h"

namespace warpcheck {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

std::string refusal(std::unique_ptr<WarpCase> warp) {
    Registry registry;
    try {
        registry.add_case(std::move(warp));
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
    return make_warp_case(std::move(info), [](float u) { return u; }, [](float) { return 1.0f; });
}

TEST(CaseValidation, AViewOutsideTheDomainIsRefused) {
    EXPECT_THAT(refusal(linear_1d({.family = "lin", .input = InputKind::Uniform1D,
                                   .domain = chi2::Domain::interval(0, 1), .views = {view("x", 0.0, 2.0)}})),
                AllOf(HasSubstr("warp case lin "), HasSubstr("view 'x': [0, 2] lies outside the domain")));
    EXPECT_THAT(refusal(linear_1d({.family = "lin", .input = InputKind::Uniform1D,
                                   .domain = chi2::Domain::lower_half_line(1), .views = {view("x", 0.0, 2.0)}})),
                HasSubstr("lies outside the domain half-line (-inf"));
    EXPECT_EQ(refusal(linear_1d({.family = "lin", .input = InputKind::Uniform1D,
                                 .domain = chi2::Domain::interval(0, 1), .views = {view("x", 0.0, 1.0)}})),
              "");
}

TEST(CaseValidation, AViewOfAMissingInputCoordinateIsRefused) {
    MonotoneMarginal m = view("x", 0.0, 1.0);
    m.input_coordinate = 1;
    EXPECT_THAT(refusal(linear_1d({.family = "lin", .input = InputKind::Uniform1D,
                                   .domain = chi2::Domain::interval(0, 1), .views = {m}})),
                AllOf(HasSubstr("warp case lin "), HasSubstr("input coordinate 1 does not exist")));
}

TEST(CaseValidation, ViewsNeedDistinctLabelsAndACoordinateOn2DDomains) {
    auto disk = [](std::vector<MonotoneMarginal> views) {
        return make_warp_case({.family = "disk", .domain = chi2::Domain::unit_disk(), .views = std::move(views)},
                              [](Point2f u) { return Point2f{u.x - 0.5f, u.y - 0.5f}; },
                              [](Point2f) { return 1.0f; });
    };
    MonotoneMarginal r = view("r", 0.0, 1.0);
    r.pdf = [](double x) { return 2.0 * x; };
    EXPECT_THAT(refusal(disk({r})), HasSubstr("needs a coordinate function on a 2-dimensional domain"));
    r.coordinate = [](const WarpOutput& o) { return std::hypot(o[0], o[1]); };
    EXPECT_EQ(refusal(disk({r})), "");
    EXPECT_THAT(refusal(disk({r, r})), HasSubstr("two views are labelled 'r'"));
}

TEST(CaseValidation, TypesThatDisagreeWithTheDeclarationAreRefused) {
    // A 1D warp left at the default input (Uniform2D), on a 2D domain: its
    // types are checked when the case is made (WarpCase::validate_declaration).
    try {
        (void)linear_1d({.family = "lin"});
        ADD_FAILURE() << "a 1D warp declared with 2D input was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_THAT(e.what(), AllOf(HasSubstr("warp case lin: "),
                                    HasSubstr("its sample takes Uniform1D (a float) but .input is Uniform2D")));
    }
    EXPECT_THAT(refusal(linear_1d({.family = "lin", .input = InputKind::Uniform1D,
                                   .domain = chi2::Domain::interval(0, 1), .roundtrip_tolerance = 0.0})),
                HasSubstr("roundtrip_tolerance 0 is not in (0, 1)"));
}

TEST(CaseValidation, EveryBuiltInCaseIsConsistent) {
    Registry registry;
    EXPECT_NO_THROW(register_builtin_cases(registry));
    EXPECT_NO_THROW(register_flawed_interval_cases(registry));
}

}  // namespace
}  // namespace warpcheck

// The C++17 registration header (validate/api/register17.h) against the C++20
// API it mirrors, member for member: every kind of case, every domain, and
// every member of the case descriptions and claims has a C++17 form that
// reaches the C++20 case, or is listed here with why C++17 has none. A member,
// domain or kind added on the C++20 side alone fails a test below, naming it.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "validate/run/case_kind.h"
#include "validate/api/register17.h"
#include "validate/api/registry.h"

namespace warpcheck {
namespace {

namespace c17 = cxx17;

// ---- members of an aggregate, counted ---------------------------------------
// An aggregate of n members takes up to n initialisers; `Any` converts to
// any member's type, so the largest count that compiles is the member count.

struct Any {
    template <typename T>
    operator T() const;  // never called: only its overload is looked at
};
template <typename T, std::size_t... I>
constexpr bool takes(std::index_sequence<I...>) {
    return requires { T{(void(I), Any{})...}; };
}
template <typename T, std::size_t N = 0>
constexpr std::size_t member_count() {
    if constexpr (N > 64) return N;
    else if constexpr (takes<T>(std::make_index_sequence<N + 1>{})) return member_count<T, N + 1>();
    else return N;
}

// The counter itself, on aggregates whose members are known.
struct Three {
    int a;
    std::string b;
    std::vector<double> c;
};
static_assert(member_count<Three>() == 3);
static_assert(member_count<c17::BinResolution>() == 4);

/// Each C++20 member of a description: the C++17 member that carries it, or
/// (after "none: ") why C++17 has none.
using MemberMap = std::vector<std::pair<const char*, const char*>>;

// WarpCaseInfo: what a warp case declares.
const MemberMap kWarpCaseInfo = {
    {"family", "CaseInfo::family"},
    {"params", "CaseInfo::params"},
    {"description", "CaseInfo::description"},
    {"input", "none: read off the type of sample's argument, as make_warp_case does when it is unset"},
    {"domain", "CaseInfo::domain"},
    {"roundtrip_tolerance", "CaseInfo::roundtrip_tolerance"},
    {"exact_inverse", "CaseInfo::exact_inverse"},
    {"chi2_resolution", "CaseInfo::chi2_resolution (and BsdfInfo's, LightInfo's, MisInfo's)"},
    {"views", "CaseInfo::views"},
    {"inversion", "CaseInfo::inversion"},
    {"support_measure", "CaseInfo::support_measure"},
    {"categories", "CaseInfo::categories"},
    {"lanes", "none: the built-in warps' hand-written lane forms; a renderer's warp takes the scalar path"},
};
const MemberMap kBsdfClaims = {
    {"wo", "BsdfInfo::wo"},
    {"lobes", "BsdfInfo::reflection, transmission, continuous, delta"},
    {"reciprocal", "BsdfInfo::reciprocal"},
    {"transport", "BsdfInfo::importance"},
    {"eta", "BsdfInfo::eta (a spectral BSDF's: eta(hero))"},
    {"phase_function", "BsdfInfo::phase_function"},
    {"stochastic", "BsdfInfo::stochastic"},
};
const MemberMap kLightClaims = {{"ref", "LightInfo::ref"}, {"normal", "LightInfo::normal"}};
const MemberMap kMisClaims = {{"heuristic", "MisInfo::power_heuristic"},
                              {"pdfs", "add_mis's bsdf_mis_pdf and each MisLight's mis_pdf"}};
const MemberMap kMisPdfs = {
    {"bsdf", "add_mis's bsdf_mis_pdf"},
    {"lights", "MisLight::mis_pdf, per light"},
    {"bsdf_batch", "none: the batch form is for callers whose every call costs (Python's NumPy functions); a C++ "
                   "renderer's per-direction bsdf_mis_pdf costs a function call"},
    {"lights_batch", "none: as bsdf_batch, for MisLight::mis_pdf"}};
const MemberMap kBinResolution = {{"first", "BinResolution::first"},
                                  {"second", "BinResolution::second"},
                                  {"half_line_scale", "BinResolution::half_line_scale"},
                                  {"line_center", "BinResolution::line_center"}};
const MemberMap kMonotoneMarginal = {
    {"input_coordinate", "View::input_coordinate"}, {"increasing", "View::increasing"}, {"lo", "View::lo"},
    {"hi", "View::hi"}, {"tail_mass", "View::tail_mass"}, {"lower_tail_mass", "View::lower_tail_mass"},
    {"label", "View::label"}, {"coordinate", "View::coordinate"}, {"pdf", "View::pdf"}};
const MemberMap kGridAxis = {{"name", "GridAxis::name"}, {"values", "GridAxis::values"}, {"ranges", "GridAxis::ranges"}};
const MemberMap kParamRange = {
    {"lo", "ParamRange::lo"}, {"hi", "ParamRange::hi"}, {"lo_open", "ParamRange::lo_open"}, {"hi_open", "ParamRange::hi_open"}};
const MemberMap kBsdfSample = {{"wi", "BsdfSample::wi"},
                               {"f", "BsdfSample::f"},
                               {"pdf", "BsdfSample::pdf"},
                               {"flags", "BsdfSample::transmission, delta"},
                               {"eta", "BsdfSample::eta"}};
const MemberMap kSpectralSample = {{"wi", "SpectralBsdfSample::wi"},
                                   {"f", "SpectralBsdfSample::f"},
                                   {"pdf", "SpectralBsdfSample::pdf"},
                                   {"flags", "SpectralBsdfSample::transmission, delta"},
                                   {"eta", "SpectralBsdfSample::eta"}};
const MemberMap kLightSample = {{"wi", "LightSample::wi"},
                                {"pdf", "LightSample::pdf"},
                                {"L", "LightSample::L"},
                                {"distance", "LightSample::distance"}};

std::string listed(const MemberMap& map) {
    std::string out;
    for (const auto& [member, carried_by] : map) out += std::string(out.empty() ? "" : ", ") + member;
    return out;
}

#define EXPECT_MEMBERS_MAPPED(Type, map)                                                                     \
    EXPECT_EQ(member_count<Type>(), (map).size())                                                            \
        << #Type " has " << member_count<Type>() << " members and the C++17 map lists " << (map).size()      \
        << " (" << listed(map) << "): give the new member a form in validate/api/register17.h, carry it in " \
        << "register17.cpp, and list it in " #map " (or list it with why C++17 has none)"

TEST(Register17Parity, EveryMemberOfTheCxx20DescriptionsIsCarriedOrExplained) {
    EXPECT_MEMBERS_MAPPED(WarpCaseInfo, kWarpCaseInfo);
    EXPECT_MEMBERS_MAPPED(BsdfClaims, kBsdfClaims);
    EXPECT_MEMBERS_MAPPED(LightClaims, kLightClaims);
    EXPECT_MEMBERS_MAPPED(MisClaims, kMisClaims);
    EXPECT_MEMBERS_MAPPED(MisPdfs, kMisPdfs);
    EXPECT_MEMBERS_MAPPED(chi2::BinResolution, kBinResolution);
    EXPECT_MEMBERS_MAPPED(MonotoneMarginal, kMonotoneMarginal);
    EXPECT_MEMBERS_MAPPED(GridAxis, kGridAxis);
    EXPECT_MEMBERS_MAPPED(ParamRange, kParamRange);
    EXPECT_MEMBERS_MAPPED(BsdfSample, kBsdfSample);
    EXPECT_MEMBERS_MAPPED(SpectralSample<3>, kSpectralSample);
    EXPECT_MEMBERS_MAPPED(LightSample, kLightSample);
    // The C++17 forms, so that a member added there without its conversion shows too.
    EXPECT_EQ(member_count<c17::CaseInfo>(), 11u);
    EXPECT_EQ(member_count<c17::BsdfInfo>(), 14u);
    EXPECT_EQ(member_count<c17::LightInfo>(), 6u);
    EXPECT_EQ(member_count<c17::MisInfo>(), 5u);
    EXPECT_EQ(member_count<c17::View>(), 9u);
}

// ---- what the C++17 forms carry arrives -------------------------------------

constexpr float kPiF = 3.14159265f;

struct Uniform01 {
    float sample(float u) const { return u; }
    float pdf(float x) const { return x >= 0 && x < 1 ? 1.0f : 0.0f; }
    float invert(float x) const { return x; }
};

TEST(Register17Parity, EveryDomainKindOfTheCxx20ApiHasACxx17Form) {
    const std::vector<c17::Domain> forms = {
        c17::Domain::interval(0, 1),      c17::Domain::half_line(0),      c17::Domain::lower_half_line(1),
        c17::Domain::real_line(),         c17::Domain::box(0, 1, 0, 2),   c17::Domain::unit_disk(),
        c17::Domain::spherical_cap(0.5),  c17::Domain::triangle({0, 0}, {2, 0}, {0, 1})};
    std::set<std::size_t> reached;
    for (const c17::Domain& d : forms) {
        Registry registry;
        c17::CaseInfo info;
        info.family = "d";
        info.domain = d;
        // Registration is what is tested: the densities are never evaluated.
        struct Point2Warp {
            c17::Point2 sample(const c17::Point2& u) const { return u; }
            float pdf(const c17::Point2&) const { return 1.0f; }
        };
        struct LineWarp {
            float sample(float u) const { return u; }
            float pdf(float) const { return 1.0f; }
        };
        struct DirectionWarp {
            c17::Point sample(const c17::Point2& u) const { return {u[0], u[1], 1.0f}; }
            float pdf(const c17::Point&) const { return 1.0f; }
        };
        const bool line = d.kind <= c17::Domain::Kind::RealLine;
        if (line) c17::add_case(registry, info, LineWarp{});
        else if (d.kind == c17::Domain::Kind::SphericalCap) c17::add_case(registry, info, DirectionWarp{});
        else c17::add_case(registry, info, Point2Warp{});
        ASSERT_EQ(registry.cases().size(), 1u);
        reached.insert(registry.cases()[0]->domain().shape().index());
    }
    EXPECT_EQ(reached.size(), std::variant_size_v<chi2::Domain::Shape>)
        << "chi2::Domain has a kind that register17.h's Domain cannot name";
    // The triangle's vertices arrive as given.
    Registry registry;
    c17::CaseInfo info;
    info.family = "t";
    info.domain = c17::Domain::triangle({0, 0}, {2, 0}, {0, 1});
    struct Point2Warp {
        c17::Point2 sample(const c17::Point2& u) const { return u; }
        float pdf(const c17::Point2&) const { return 2.0f; }
    };
    c17::add_case(registry, info, Point2Warp{});
    EXPECT_DOUBLE_EQ(registry.cases()[0]->domain().measure(), 1.0);
}

TEST(Register17Parity, EveryWarpDescriptionMemberArrives) {
    Registry registry;
    c17::CaseInfo info;
    info.family = "carried";
    info.params = {{"k", 2.5}};
    info.description = "all members set";
    info.domain = c17::Domain::interval(0, 1);
    info.roundtrip_tolerance = 0x1p-10;
    info.exact_inverse = true;
    info.chi2_resolution = {64, 0, 0.0, 0.0};
    c17::View view;
    view.input_coordinate = 0;
    view.increasing = false;
    view.lo = 0.25;
    view.hi = 0.75;
    view.tail_mass = 0.25;
    view.lower_tail_mass = 0.25;
    view.label = "x";
    view.coordinate = [](const c17::Point& p) { return static_cast<double>(p[0]); };
    view.pdf = [](double) { return 1.0; };
    info.views = {view};
    info.inversion = c17::Inversion::NotInversion;
    info.support_measure = 0.5;
    c17::add_case(registry, info, Uniform01{});
    const WarpCaseInfo& got = registry.cases()[0]->info();
    EXPECT_EQ(got.family, "carried");
    ASSERT_EQ(got.params.size(), 1u);
    EXPECT_EQ(got.params[0].value, 2.5);
    EXPECT_EQ(got.description, "all members set");
    EXPECT_EQ(got.roundtrip_tolerance, 0x1p-10);
    EXPECT_TRUE(got.exact_inverse);
    EXPECT_EQ(got.chi2_resolution.first, 64);
    ASSERT_EQ(got.views.size(), 1u);
    const MonotoneMarginal& m = got.views[0];
    EXPECT_EQ(m.input_coordinate, 0);
    EXPECT_FALSE(m.increasing);
    EXPECT_EQ(m.lo, 0.25);
    EXPECT_EQ(m.hi, 0.75);
    EXPECT_EQ(m.tail_mass, 0.25);
    EXPECT_EQ(m.lower_tail_mass, 0.25);
    EXPECT_EQ(m.label, "x");
    EXPECT_TRUE(static_cast<bool>(m.coordinate));
    EXPECT_TRUE(static_cast<bool>(m.pdf));
    EXPECT_EQ(got.inversion, Inversion::NotInversion);
    EXPECT_EQ(got.support_measure, 0.5);

    // A discrete case's categories, and a grid's axes with their fuzz ranges.
    struct Choice {
        c17::DiscreteSample sample(float u) const { return {u < 0.5f ? 0u : 1u, 0.0f}; }
        float pdf(std::uint32_t) const { return 0.5f; }
    };
    c17::CaseInfo discrete;
    discrete.family = "choice";
    discrete.categories = 2;
    c17::add_case(registry, discrete, Choice{});
    EXPECT_EQ(registry.cases()[1]->info().categories, 2u);

    c17::CaseInfo base;
    base.family = "grid";
    base.domain = c17::Domain::interval(0, 1);
    c17::add_case_grid(registry, base, {{"k", {1, 2}, {{0.5, 4.0, true, false}}}},
                       [](const c17::GridPoint&) { return Uniform01{}; });
    const CaseFamily* family = registry.find_family("grid");
    ASSERT_NE(family, nullptr);
    ASSERT_EQ(family->axes.size(), 1u);
    EXPECT_EQ(family->axes[0].values, (std::vector<double>{1, 2}));
    ASSERT_EQ(family->axes[0].ranges.size(), 1u);
    const ParamRange& r = family->axes[0].ranges[0];
    EXPECT_EQ(r.lo, 0.5);
    EXPECT_EQ(r.hi, 4.0);
    EXPECT_TRUE(r.lo_open);
    EXPECT_FALSE(r.hi_open);
}

// ---- one of every kind -------------------------------------------------------

struct Diffuse {
    c17::BsdfSample sample(const c17::Point&, float, const c17::Point2& u) const {
        const float r = std::sqrt(u[0]), phi = 2 * kPiF * u[1];
        c17::BsdfSample s;
        s.wi = {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1 - u[0]))};
        s.f = 0.5f / kPiF;
        s.pdf = s.wi[2] / kPiF;
        return s;
    }
    float f(const c17::Point&, const c17::Point& wi) const { return wi[2] > 0 ? 0.5f / kPiF : 0.0f; }
    float pdf(const c17::Point&, const c17::Point& wi) const { return wi[2] > 0 ? wi[2] / kPiF : 0.0f; }
};

struct Isotropic {
    c17::BsdfSample sample(const c17::Point&, const c17::Point2& u) const {
        const float z = 1 - 2 * u[0], r = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * kPiF * u[1];
        c17::BsdfSample s;
        s.wi = {r * std::cos(phi), r * std::sin(phi), z};
        s.f = s.pdf = 0.25f / kPiF;
        s.transmission = z < 0;
        return s;
    }
    float p(const c17::Point&, const c17::Point&) const { return 0.25f / kPiF; }
    float pdf(const c17::Point&, const c17::Point&) const { return 0.25f / kPiF; }
};

/// A grey diffuse in three channels, the third terminated.
struct DiffuseRgb {
    c17::SpectralBsdfSample<3> sample(const c17::Point& wo, float uc, const c17::Point2& u, int) const {
        const c17::BsdfSample s = Diffuse{}.sample(wo, uc, u);
        c17::SpectralBsdfSample<3> out;
        out.wi = s.wi;
        out.f = {s.f, s.f, s.f};
        out.pdf = {s.pdf, s.pdf, s.pdf};
        return out;
    }
    std::array<float, 3> f(const c17::Point& wo, const c17::Point& wi) const {
        const float v = Diffuse{}.f(wo, wi);
        return {v, v, v};
    }
    std::array<float, 3> pdf(const c17::Point& wo, const c17::Point& wi) const {
        const float v = Diffuse{}.pdf(wo, wi);
        return {v, v, v};
    }
    float eta(int channel) const { return 1.0f + 0.25f * static_cast<float>(channel); }
};

/// A light of constant radiance over the cap z >= 0.5, seen from the origin.
struct CapLight {
    c17::LightSample sample(const c17::Point&, const c17::Point2& u) const {
        const float z = 1 - 0.5f * u[0], r = std::sqrt(1 - z * z), phi = 2 * kPiF * u[1];
        c17::LightSample s;
        s.wi = {r * std::cos(phi), r * std::sin(phi), z};
        s.pdf = 1 / kPiF;
        s.L = 1;
        s.distance = 1;
        return s;
    }
    double pdf(const c17::Point&, const c17::Point& wi) const { return wi[2] >= 0.5f ? 1 / kPiF : 0.0; }
    double L(const c17::Point&, const c17::Point& wi) const { return wi[2] >= 0.5f ? 1.0 : 0.0; }
};

struct UnitFloat {
    float sample(std::uint32_t u) const { return static_cast<float>(u >> 8) * 0x1p-24f; }
    float pdf(float x) const { return x >= 0 && x < 1 ? 1.0f : 0.0f; }
};

TEST(Register17Parity, EveryKindOfCaseHasACxx17Form) {
    Registry registry;
    c17::CaseInfo warp;
    warp.family = "warp";
    warp.domain = c17::Domain::interval(0, 1);
    c17::add_case(registry, warp, Uniform01{});
    struct Choice {
        std::uint32_t sample(float u) const { return u < 0.5f ? 0u : 1u; }
        float pdf(std::uint32_t) const { return 0.5f; }
    };
    c17::CaseInfo choice;
    choice.family = "choice";
    choice.categories = 2;
    c17::add_case(registry, choice, Choice{});
    warp.family = "sweep";
    c17::add_u32_float_case(registry, warp, c17::Monotone::Claimed, UnitFloat{});
    c17::BsdfInfo bsdf;
    bsdf.family = "diffuse";
    bsdf.wo = c17::bsdf_direction(30);
    c17::add_bsdf(registry, bsdf, Diffuse{});
    c17::BsdfInfo phase;
    phase.family = "isotropic";
    phase.phase_function = true;
    c17::add_bsdf(registry, phase, Isotropic{});
    c17::BsdfInfo rgb = bsdf;
    rgb.family = "diffuse_rgb";
    rgb.params = {{"hero", 2}};
    rgb.chi2_resolution = {16, 16, 0.0, 0.0};
    c17::add_spectral_bsdf(registry, rgb, DiffuseRgb{}, 2);
    c17::LightInfo light;
    light.family = "cap";
    light.normal = {0, 0, 1};
    light.chi2_resolution = {8, 8, 0.0, 0.0};
    c17::add_light(registry, light, CapLight{});
    c17::MisInfo mis;
    mis.family = "direct";
    mis.power_heuristic = false;
    c17::LightInfo second = light;
    second.family = "cap_again";
    c17::add_mis(registry, mis, bsdf, Diffuse{},
                 {c17::mis_light(light, CapLight{}),
                  c17::mis_light(second, CapLight{}, [](const c17::Point&, const c17::Point& wi) {
                      return wi[2] >= 0.5f ? 1 / kPiF : 0.0;
                  })});

    std::set<CaseKind> made;
    for (const auto& c : registry.cases()) made.insert(case_kind(*c));
    for (CaseKind kind : kCaseKinds)
        EXPECT_TRUE(made.count(kind)) << "no C++17 form made a case of kind " << to_string(kind);

    // What the new forms carry arrives.
    const WarpCase* spectral = registry.find_case("diffuse_rgb[hero=2]");
    ASSERT_NE(spectral, nullptr);
    ASSERT_NE(as_spectral(*spectral), nullptr);
    EXPECT_EQ(as_spectral(*spectral)->channels(), 3);
    EXPECT_EQ(as_spectral(*spectral)->hero(), 2);
    EXPECT_EQ(as_bsdf(*spectral)->claims().eta, 1.5f);  // eta(hero)
    EXPECT_EQ(spectral->info().chi2_resolution.first, 16);
    const WarpCase* cap = registry.find_case("cap");
    ASSERT_NE(cap, nullptr);
    EXPECT_EQ(cap->info().chi2_resolution.second, 8);
    const MisCase* direct = as_mis(*registry.find_case("direct"));
    ASSERT_NE(direct, nullptr);
    EXPECT_EQ(direct->light_count(), 2u);
    EXPECT_EQ(direct->heuristic(), MisHeuristic::Balance);
    EXPECT_FALSE(direct->has_mis_pdf(0));
    EXPECT_FALSE(direct->has_mis_pdf(1));
    EXPECT_TRUE(direct->has_mis_pdf(2));
    // A channel outside the object's is refused, as make_spectral_bsdf_case refuses it.
    EXPECT_THROW(c17::add_spectral_bsdf(registry, rgb, DiffuseRgb{}, 3), std::invalid_argument);
}

TEST(Register17Parity, EveryBsdfClaimArrives) {
    Registry registry;
    c17::BsdfInfo info;
    info.family = "claims";
    info.wo = c17::bsdf_direction(60);
    info.reflection = true;
    info.transmission = true;
    info.continuous = true;
    info.delta = false;
    info.reciprocal = false;
    info.importance = true;
    info.eta = 1.33f;
    info.stochastic = true;
    struct Both {
        c17::BsdfSample sample(const c17::Point& wo, float uc, const c17::Point2& u) const {
            c17::BsdfSample s = Diffuse{}.sample(wo, uc, u);
            if (uc < 0.5f) s.wi[2] = -s.wi[2], s.transmission = true, s.eta = 1.33f;
            s.pdf *= 0.5f;
            return s;
        }
        float f(const c17::Point&, const c17::Point& wi) const { return 0.5f / kPiF + 0.0f * wi[2]; }
        float pdf(const c17::Point&, const c17::Point& wi) const { return std::abs(wi[2]) / (2 * kPiF); }
    };
    c17::add_bsdf(registry, info, Both{});
    const BsdfCase* b = as_bsdf(*registry.cases()[0]);
    ASSERT_NE(b, nullptr);
    const BsdfClaims& c = b->claims();
    EXPECT_NEAR(c.wo.z, 0.5f, 1e-6f);
    EXPECT_EQ(c.lobes, BsdfFlags::Reflection | BsdfFlags::Transmission | BsdfFlags::Continuous);
    EXPECT_FALSE(c.reciprocal);
    EXPECT_EQ(c.transport, Transport::Importance);
    EXPECT_EQ(c.eta, 1.33f);
    EXPECT_FALSE(c.phase_function);
    EXPECT_TRUE(c.stochastic);
    // The sample's two bools arrive as its flags.
    std::array<WarpInput, 2> in{};
    in[0].u = {0.25f, 0.3f, 0.6f};
    in[1].u = {0.75f, 0.3f, 0.6f};
    std::array<BsdfRecord, 2> out{};
    b->sample_bsdf(in, out);
    EXPECT_EQ(out[0].flags, BsdfFlags::Transmission | BsdfFlags::Continuous);
    EXPECT_EQ(out[0].eta, 1.33f);
    EXPECT_EQ(out[1].flags, BsdfFlags::Reflection | BsdfFlags::Continuous);
}

}  // namespace
}  // namespace warpcheck

// The one place a case's declaration is checked (warp_case.h: case_problems,
// validate_case): its types against what its description says, its settings,
// its views, a BSDF's claims and a swept float sampler's domain. Every problem
// is a sentence; the refusal lists them all under the case's name.
#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <string_view>

#include <fmt/format.h>

#include "validate/api/bsdf_case.h"
#include "validate/api/exhaustive_sweep.h"
#include "validate/api/light_case.h"
#include "validate/api/warp_case.h"

namespace warpcheck {
namespace {

const char* input_name(InputKind k) {
    switch (k) {
        case InputKind::Uniform1D: return "Uniform1D (a float)";
        case InputKind::Uniform2D: return "Uniform2D (a Point2f)";
        case InputKind::Bits32: return "Bits32 (a uint32_t)";
        case InputKind::Bits64: return "Bits64 (a uint64_t)";
        case InputKind::Uniform3D: return "Uniform3D (a BSDF's uc and u)";
    }
    return "?";
}

/// Whether the domain is the one WarpCaseInfo starts with, i.e. left unset.
bool default_domain(const chi2::Domain& d) {
    if (!d.is<chi2::Box>()) return false;
    const chi2::Box& b = d.as<chi2::Box>();
    return b.x0 == 0.0 && b.x1 == 1.0 && b.y0 == 0.0 && b.y1 == 1.0;
}

// The first thing wrong with a discrete case, or "".
std::string discrete_problem(const WarpCaseInfo& info, const WarpSignature& s) {
    if (info.categories == 0) return "its sample returns an index, so it needs .categories (how many there are)";
    if (info.categories > (std::size_t{1} << 24))
        return fmt::format("{} categories: at most 2^24 (indices travel as exact floats)", info.categories);
    if (!default_domain(info.domain))
        return fmt::format("a discrete case has no continuous domain, but .domain is the {} (leave it unset: "
                           ".categories declares the choices)", info.domain.describe());
    if (s.has_inverse) return "a discrete case has no inverse";
    if (s.has_eval) return "a discrete case has no eval";
    if (!info.views.empty()) return "a discrete case has no monotone views";
    return "";
}

// The first thing wrong with a continuous case, or "".
std::string continuous_problem(const WarpCaseInfo& info, const WarpSignature& s) {
    if (info.categories != 0) return "it declares .categories but its sample returns a point, not an index";
    if (s.output_dimension != info.domain.point_dimension())
        return fmt::format("its points have {} coordinates, but the {} has {}", s.output_dimension,
                           info.domain.describe(), info.domain.point_dimension());
    if (s.returns == SampleReturns::PointAndWeight && !s.has_eval)
        return "its sample returns a weight but there is no eval to check it against "
               "(an eval member, or warp_of(sample).with_pdf(pdf).with_eval(eval))";
    if (s.has_eval && s.returns != SampleReturns::PointAndWeight)
        return "it has an eval but its sample returns no weight (return a WeightedSample)";
    if (!s.has_pdf && s.returns != SampleReturns::PointAndPdf)
        return "it has no pdf: give a pdf function, or return the pdf with each sample (PdfSample)";
    return "";
}

/// The case's types against its description: the first thing wrong, or "".
std::string type_problem(const WarpCase& warp) {
    const WarpCaseInfo& info = warp.info();
    const WarpSignature& s = warp.signature();
    if (info.input && *info.input != s.input)
        return fmt::format("its sample takes {} but .input is {}", input_name(s.input), input_name(*info.input));
    return warp.is_discrete() ? discrete_problem(info, s) : continuous_problem(info, s);
}

/// The case's own settings.
void setting_problems(const WarpCase& warp, std::vector<std::string>& out) {
    const double tol = warp.info().roundtrip_tolerance;
    if (!(tol > 0.0 && tol < 1.0)) out.push_back(fmt::format("roundtrip_tolerance {} is not in (0, 1)", tol));
    const double support = warp.info().support_measure, domain = warp.domain().measure();
    if (support != 0.0 && !(support > 0.0 && std::isfinite(support) && support <= domain))
        out.push_back(fmt::format("support_measure {} is not in (0, {}] (the domain's measure)", support, domain));
    if (dynamic_cast<const SweepableCase*>(&warp) && !warp.domain().is<chi2::Interval>())
        out.push_back(fmt::format("a float sampler swept exhaustively needs an interval [a, b) as its domain, not "
                                  "the {}", warp.domain().describe()));
}

/// A BSDF's claims: the first thing wrong, or "".
std::string claims_problem(const BsdfClaims& c) {
    const double len =
        std::hypot(static_cast<double>(c.wo.x), static_cast<double>(c.wo.y), static_cast<double>(c.wo.z));
    // A float direction rounded from a unit vector is within 2^-23 of unit length;
    // 2^-16 leaves room for a renderer's own normalisation and still refuses a
    // wo that was never normalised.
    if (!(std::abs(len - 1.0) <= 0x1p-16))
        return fmt::format("wo ({}, {}, {}) is not a unit vector (length {})", c.wo.x, c.wo.y, c.wo.z, len);
    if (c.wo.z == 0.0f && !c.phase_function) return "wo lies on the horizon (z = 0): on neither side of the surface";
    if (!has(c.lobes, BsdfFlags::Continuous) && !has(c.lobes, BsdfFlags::Delta))
        return "claims.lobes names no lobe: set BsdfFlags::Continuous and/or BsdfFlags::Delta";
    if (c.phase_function && c.lobes != BsdfFlags::Continuous)
        return "a phase function has one continuous lobe on the sphere (claims.lobes = BsdfFlags::Continuous)";
    if (!c.phase_function && !has(c.lobes, BsdfFlags::Reflection) && !has(c.lobes, BsdfFlags::Transmission))
        return "claims.lobes names neither Reflection nor Transmission";
    if (!(c.eta > 0.0f && std::isfinite(c.eta))) return fmt::format("claims.eta {} is not a positive index", c.eta);
    return "";
}

/// A parameter of the case's name, if it has one.
std::optional<double> named_parameter(const WarpCaseInfo& info, std::string_view name) {
    for (const Parameter& p : info.params)
        if (p.name == name) return p.value;
    return std::nullopt;
}

/// A BSDF's wo against the direction its name states (theta_o and phi_o in
/// degrees, bsdf_direction), where it states one: a case named for one
/// direction and seen from another reports every figure under the wrong name.
/// 2^-16 per component, as for wo's length: a renderer's own float
/// trigonometry is within a few 2^-24 of bsdf_direction's, while a wo of
/// another angle (or in radians, or measured from the horizon) is off by far
/// more (2^-16 is 0.0009 degrees at the least).
std::string named_wo_problem(const WarpCaseInfo& info, const BsdfClaims& c) {
    const auto theta = named_parameter(info, "theta_o");
    if (!theta) return "";
    const auto phi = named_parameter(info, "phi_o");
    const Vector3f named = bsdf_direction(*theta, phi.value_or(0.0));
    const float off = std::max({std::abs(named.x - c.wo.x), std::abs(named.y - c.wo.y), std::abs(named.z - c.wo.z)});
    if (off <= 0x1p-16f) return "";
    return fmt::format("wo ({}, {}, {}) is not the direction its name states: theta_o = {}{} gives ({}, {}, {}) "
                       "(bsdf_direction, degrees)",
                       c.wo.x, c.wo.y, c.wo.z, *theta, phi ? fmt::format(", phi_o = {}", *phi) : std::string(),
                       named.x, named.y, named.z);
}

/// A light's claims: the first thing wrong, or "".
std::string light_claims_problem(const LightClaims& c) {
    if (!(std::isfinite(c.ref.x) && std::isfinite(c.ref.y) && std::isfinite(c.ref.z)))
        return fmt::format("the reference point ({}, {}, {}) is not finite", c.ref.x, c.ref.y, c.ref.z);
    if (c.normal == Vector3f{}) return "";
    const double len = std::hypot(static_cast<double>(c.normal.x), static_cast<double>(c.normal.y),
                                  static_cast<double>(c.normal.z));
    // As for a BSDF's wo: a rounded unit vector is within 2^-23 of unit length.
    if (!(std::abs(len - 1.0) <= 0x1p-16))
        return fmt::format("the normal ({}, {}, {}) is neither zero (a point in a medium) nor a unit vector "
                           "(length {})", c.normal.x, c.normal.y, c.normal.z, len);
    return "";
}

/// One view against the warp's input and domain.
void view_problems(const WarpCase& warp, const MonotoneMarginal& m, std::vector<std::string>& out) {
    const std::string name = "view '" + m.label + "'";
    const chi2::Domain& d = warp.domain();
    const InputKind input = warp.input_kind();
    if (takes_bits(input)) out.push_back(name + ": views need uniform float input, not raw bits");
    if (m.input_coordinate < 0 || m.input_coordinate >= input_dimension(input))
        out.push_back(fmt::format("{}: input coordinate {} does not exist (the warp takes {} uniform coordinate{})",
                                  name, m.input_coordinate, input_dimension(input),
                                  input_dimension(input) == 1 ? "" : "s"));
    if (!(std::isfinite(m.lo) && std::isfinite(m.hi) && m.lo < m.hi))
        out.push_back(fmt::format("{}: needs a finite range lo < hi, not [{}, {}]", name, m.lo, m.hi));
    if (!(m.tail_mass >= 0.0 && m.lower_tail_mass >= 0.0 && m.tail_mass + m.lower_tail_mass < 1.0))
        out.push_back(fmt::format("{}: tail masses {} (below) and {} (above) must be >= 0 and sum to less than 1",
                                  name, m.lower_tail_mass, m.tail_mass));
    if (!m.pdf && input != InputKind::Uniform1D)
        out.push_back(name + ": without a density of its own it needs a 1D warp (whose pdf it then uses)");
    if (!m.coordinate && d.point_dimension() != 1)
        out.push_back(fmt::format("{}: needs a coordinate function on a {}-dimensional domain ({})", name,
                                  d.point_dimension(), d.describe()));
    if (!m.coordinate && d.point_dimension() == 1) {
        // The view is x itself: its range must lie in the domain (within the domain's slack).
        const double slack = d.slack().x;
        if (m.lo < d.a() - slack || m.hi > d.b() + slack)
            out.push_back(fmt::format("{}: [{}, {}] lies outside the domain {}", name, m.lo, m.hi, d.describe()));
        if ((m.lower_tail_mass > 0.0 && m.lo <= d.a()) || (m.tail_mass > 0.0 && m.hi >= d.b()))
            out.push_back(fmt::format("{}: declares tail mass beyond an end of the domain {}", name, d.describe()));
    }
}

}  // namespace

std::vector<std::string> case_problems(const WarpCase& warp) {
    std::vector<std::string> out;
    if (std::string problem = type_problem(warp); !problem.empty()) out.push_back(std::move(problem));
    if (const BsdfCase* bsdf = as_bsdf(warp)) {
        if (std::string problem = claims_problem(bsdf->claims()); !problem.empty()) out.push_back(std::move(problem));
        if (std::string problem = named_wo_problem(warp.info(), bsdf->claims()); !problem.empty())
            out.push_back(std::move(problem));
    }
    if (const LightCase* light = as_light(warp))
        if (std::string problem = light_claims_problem(light->claims()); !problem.empty())
            out.push_back(std::move(problem));
    setting_problems(warp, out);
    std::set<std::string> labels;
    for (const MonotoneMarginal& m : warp.info().views) {
        if (m.label.empty() && warp.info().views.size() > 1)
            out.push_back("each of several views needs a label (results name the view by it)");
        else if (!labels.insert(m.label).second) out.push_back("two views are labelled '" + m.label + "'");
        view_problems(warp, m, out);
    }
    return out;
}

std::invalid_argument declaration_error(const std::string& what, const std::vector<std::string>& problems) {
    std::string text = what + " is declared inconsistently:";
    for (const std::string& p : problems) text += "\n  - " + p;
    return std::invalid_argument(text);
}

void validate_case(const WarpCase& warp) {
    if (std::vector<std::string> problems = case_problems(warp); !problems.empty())
        throw declaration_error("warp case " + warp.name(), problems);
}

}  // namespace warpcheck

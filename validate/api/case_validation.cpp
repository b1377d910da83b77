#include "validate/api/case_validation.h"

#include <cmath>
#include <set>

#include <fmt/format.h>

namespace warpcheck {
namespace {

/// The case's own settings. (Its types against .input and the domain are
/// checked when the case is made: WarpCase::validate_declaration.)
void type_problems(const WarpCase& warp, std::vector<std::string>& out) {
    const double tol = warp.info().roundtrip_tolerance;
    if (!(tol > 0.0 && tol < 1.0)) out.push_back(fmt::format("roundtrip_tolerance {} is not in (0, 1)", tol));
    const double support = warp.info().support_measure, domain = warp.domain().measure();
    if (support != 0.0 && !(support > 0.0 && std::isfinite(support) && support <= domain))
        out.push_back(fmt::format("support_measure {} is not in (0, {}] (the domain's measure)", support, domain));
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
    type_problems(warp, out);
    std::set<std::string> labels;
    for (const MonotoneMarginal& m : warp.info().views) {
        if (m.label.empty() && warp.info().views.size() > 1)
            out.push_back("each of several views needs a label (results name the view by it)");
        else if (!labels.insert(m.label).second) out.push_back("two views are labelled '" + m.label + "'");
        view_problems(warp, m, out);
    }
    return out;
}

}  // namespace warpcheck

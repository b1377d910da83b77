#include "validate/checks/shared/cell_power.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "chi2/power.h"

namespace warpcheck {

std::string figure_label(const std::string& label) {
    std::string s;
    for (char ch : label) s += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
    return s;
}

void add_cell_power(CheckResult& r, const chi2::Binning& binning, const chi2::Chi2Outcome& o, double level,
                    uint64_t samples) {
    const double lambda = chi2::pearson_noncentrality_for_power(o.dof(), level, 0.9, o.pearson.noncentrality);
    r.figures.push_back({"power_noncentrality", lambda});
    double weakest = 0.0;
    for (int axis = 0; axis < binning.parameter_dimension(); ++axis) {
        const std::vector<double> gradient = chi2::tilt_gradient(binning, o.integrals.probability, axis);
        const double per_unit =
            chi2::tilt_noncentrality(gradient, o.integrals.probability, o.pearson.term_of_cell, samples);
        // The tilt whose mean shift of the statistic, its noncentrality less the
        // first-order loss of the sign that empties heavy cells, reaches lambda.
        const double shift = chi2::tilt_mean_shift(gradient, o.integrals.probability, o.pearson.term_of_cell);
        const double eps = chi2::tilt_for_noncentrality(lambda, per_unit, shift);
        const std::string label = axis == 0 ? binning.u_label() : binning.v_label();
        r.figures.push_back({"power_tilt_eps_" + figure_label(label), eps});
        weakest = std::isnan(eps) || std::isnan(weakest) ? std::nan("") : std::max(weakest, eps);
    }
    r.figures.push_back({"power_tilt_eps", weakest});
    r.figures.push_back({"power_level", level});
}

std::string weakness(const CheckResult& r) {
    const std::optional<double> eps = r.figure("power_tilt_eps");
    if (!eps || *eps <= kWeakTilt) return "";
    constexpr std::string_view prefix = "power_tilt_eps_";
    std::string which = "a marginal";
    double worst = -1.0;
    for (const Figure& f : r.figures)
        if (f.name.starts_with(prefix) && !(f.value <= worst)) {
            worst = std::isnan(f.value) ? std::numeric_limits<double>::infinity() : f.value;
            which = f.name.substr(prefix.size());
        }
    std::replace(which.begin(), which.end(), '_', ' ');
    return std::isfinite(*eps) ? fmt::format("cannot see a {:g}% tilt of {} (90% power only at a tilt of {:.2g})",
                                             100.0 * kWeakTilt, which, *eps)
                               : fmt::format("cannot see a tilt of {} at all: its cells do not resolve it", which);
}

}  // namespace warpcheck

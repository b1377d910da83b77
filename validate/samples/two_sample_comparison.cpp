#include "validate/samples/two_sample_comparison.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "chi2/binning.h"
#include "chi2/min_p.h"
#include "chi2/power.h"
#include "chi2/two_sample.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/power_level.h"

namespace warpcheck {
namespace {

using Point = chi2::AdaptiveCells::Point;

/// The tested coordinates of each sample, with the samples that have none
/// (NaN, outside the domain) counted instead.
struct Coordinates {
    int dims = 2;
    std::string u_label, v_label;
    std::vector<Point> a, b;
    uint64_t nan_a = 0, nan_b = 0, outside_a = 0, outside_b = 0;
};

Coordinates coordinates(std::span<const WarpOutput> a, std::span<const WarpOutput> b, const TwoSampleComparison& how) {
    Coordinates c;
    std::optional<chi2::Binning> binning;
    if (how.domain && how.domain->point_dimension() > 1) binning.emplace(*how.domain);
    c.dims = how.domain ? (how.domain->point_dimension() == 1 ? 1 : 2) : std::min(how.dimension, 2);
    c.u_label = binning ? binning->u_label() : how.dimension == 3 ? "phi" : "x";
    c.v_label = binning ? binning->v_label() : how.dimension == 3 ? "z" : "y";
    const auto convert = [&](std::span<const WarpOutput> in, std::vector<Point>& out, uint64_t& nan, uint64_t& outside) {
        out.reserve(in.size());
        for (const WarpOutput& o : in) {
            const chi2::DomainPoint p = to_domain_point(o);
            if (std::isnan(p[0]) || std::isnan(p[1]) || std::isnan(p[2])) {
                ++nan;
                continue;
            }
            if (how.domain && !how.domain->contains(p)) {
                ++outside;
                continue;
            }
            if (binning) out.push_back(binning->parameters_of(p));
            else if (c.dims == 1) out.push_back({p[0], 0.0});
            else if (how.dimension == 3) out.push_back({exact_phi(p[0], p[1]), p[2]});
            else out.push_back({p[0], p[1]});
        }
    };
    convert(a, c.a, c.nan_a, c.outside_a);
    convert(b, c.b, c.nan_b, c.outside_b);
    return c;
}

/// The difference of the two empirical CDFs along one coordinate, at 200
/// quantiles of the pooled samples: where they part.
Series cdf_difference(const std::vector<double>& a, const std::vector<double>& b, const std::string& label) {
    std::vector<double> pooled(a);
    pooled.insert(pooled.end(), b.begin(), b.end());
    std::sort(pooled.begin(), pooled.end());
    Series s{label, {}, {}};
    for (int k = 1; k < 200 && !pooled.empty(); ++k) {
        const double q = pooled[pooled.size() * static_cast<std::size_t>(k) / 200];
        const auto below = [q](const std::vector<double>& v) {
            return static_cast<double>(std::upper_bound(v.begin(), v.end(), q) - v.begin()) / static_cast<double>(v.size());
        };
        s.x.push_back(q);
        s.y.push_back(below(a) - below(b));
    }
    return s;
}

struct Marginal {
    std::string label;
    chi2::AndersonDarlingTwoSample ad;
    Series cdf_gap;
};

Marginal test_marginal(const Coordinates& c, int axis, const std::string& label) {
    std::vector<double> a, b;
    for (const Point& p : c.a) a.push_back(p[static_cast<std::size_t>(axis)]);
    for (const Point& p : c.b) b.push_back(p[static_cast<std::size_t>(axis)]);
    Marginal m{label, chi2::anderson_darling_two_sample(a, b), {}};
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    m.cdf_gap = cdf_difference(a, b, label);
    return m;
}

}  // namespace

CheckResult compare_independent(std::span<const WarpOutput> a, std::span<const WarpOutput> b,
                                const TwoSampleComparison& how, const RunOptions& options) {
    const Coordinates c = coordinates(a, b, how);
    CheckResult r;
    r.check_name = "two_sample";
    r.samples = a.size() + b.size();
    // About 1000 cells, as the one-sample chi-square uses (chi2/binning.h says
    // why), and no fewer than 20 expected per cell from the smaller sample, so
    // that a smooth density needs no merging.
    const double smaller = static_cast<double>(std::min(c.a.size(), c.b.size()));
    const int per_axis = std::clamp(static_cast<int>(std::sqrt(smaller / 20.0)), 1, 32);
    const int strips = c.dims == 1 ? std::clamp(static_cast<int>(smaller / 20.0), 1, 1024) : per_axis;
    const chi2::AdaptiveCells cells(c.a, c.b, c.dims, strips, c.dims == 1 ? 1 : per_axis);
    const chi2::HomogeneityResult h = chi2::homogeneity_test(cells.counts(c.a), cells.counts(c.b));
    std::vector<Marginal> marginals{test_marginal(c, 0, c.u_label)};
    if (c.dims == 2) marginals.push_back(test_marginal(c, 1, c.v_label));
    std::vector<double> p_values{h.p_value};
    for (const Marginal& m : marginals) p_values.push_back(m.ad.p_value);
    const int tests = static_cast<int>(p_values.size());
    const double level = power_level(options, tests);
    const auto n_eff = static_cast<uint64_t>(h.effective_samples);
    const double chi2_tilt =
        h.dof >= 1 && n_eff > 0
            ? chi2::pearson_tilt_for_noncentrality(chi2::pearson_noncentrality_for_power(h.dof, level), n_eff)
            : std::nan("");
    const double ad_tilt = n_eff > 0 ? chi2::unbinned_tilt_for_power(chi2::UnbinnedTest::AndersonDarling, level, n_eff)
                                     : std::nan("");
    r.figures = {{"homogeneity_statistic", h.statistic},  {"homogeneity_dof", static_cast<double>(h.dof)},
                 {"homogeneity_p_value", h.p_value},      {"cells", static_cast<double>(cells.cell_count())},
                 {"merged_cells", static_cast<double>(h.merged_cells)},
                 {"effective_samples", h.effective_samples}, {"samples_a", static_cast<double>(a.size())},
                 {"samples_b", static_cast<double>(b.size())}, {"nan_a", static_cast<double>(c.nan_a)},
                 {"nan_b", static_cast<double>(c.nan_b)},  {"outside_a", static_cast<double>(c.outside_a)},
                 {"outside_b", static_cast<double>(c.outside_b)}, {"power_level", level},
                 {"power_tilt_chi2", chi2_tilt},           {"power_tilt_ad", ad_tilt}};
    std::string ad_text;
    Plot gaps{Plot::Kind::Lines, fmt::format("F_{} - F_{} per coordinate", how.label_a, how.label_b), "coordinate",
              "difference of the empirical CDFs", false, false, {}, {}};
    for (const Marginal& m : marginals) {
        r.figures.push_back({"ad_" + m.label + "_a2", m.ad.a2});
        r.figures.push_back({"ad_" + m.label + "_p_value", m.ad.p_value});
        ad_text += fmt::format("{}{} p {:.3g}", ad_text.empty() ? "" : ", ", m.label, m.ad.p_value);
        gaps.series.push_back(m.cdf_gap);
    }
    r.p_value = chi2::sidak_min_p(p_values);
    r.plots.push_back(std::move(gaps));
    Plot residuals{Plot::Kind::Points, "homogeneity residuals of " + how.label_a + " per cell", "cell (after merging)",
                   "(a - E_a) / sqrt(E_a)", false, false, {}, {}};
    Series res{"residual", {}, h.residual};
    for (std::size_t k = 0; k < h.residual.size(); ++k) res.x.push_back(static_cast<double>(k));
    residuals.series.push_back(std::move(res));
    r.plots.push_back(std::move(residuals));
    r.summary = fmt::format("chi2 {:.1f} dof {} p {:.3g}; AD {}; 90% power: tilt {:.2g} (chi2), {:.2g} (AD)", h.statistic,
                            h.dof, h.p_value, ad_text, chi2_tilt, ad_tilt);
    r.verdict = Verdict::Pass;
    std::vector<std::string> failures;
    if (c.nan_a + c.nan_b > 0) failures.push_back(fmt::format("NaN samples: {} in {}, {} in {}", c.nan_a, how.label_a, c.nan_b, how.label_b));
    if (c.outside_a + c.outside_b > 0)
        failures.push_back(fmt::format("samples outside {}: {} in {}, {} in {}", how.domain ? how.domain->describe() : "",
                                       c.outside_a, how.label_a, c.outside_b, how.label_b));
    if (!failures.empty()) {
        r.verdict = Verdict::Fail;
        r.summary = failures.front();
        r.message = join_reasons(failures);
        r.p_value.reset();  // decided without a level
    }
    return r;
}

}  // namespace warpcheck

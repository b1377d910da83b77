// "tabulated": the warp against the inversion method on a tabulated copy of its
// own density.
//
// The density of a 1D warp (or the marginal density of a monotone coordinate of
// a 2D warp, see MonotoneMarginal) is tabulated into kBuckets equal buckets,
// each the supersampled average of the density, and a PiecewiseConstant1D is
// built from them. For the same u, the table's sample and the warp's sample then
// differ only by the table's discretisation - by an amount that follows from the
// bucket width and how much the density varies across the bucket:
//
//   x: the exact CDF F and the table's piecewise-linear CDF L agree at bucket
//      edges, so the two samples lie in the same bucket. Within it, with the
//      density between fmin and fmax, |F - L| <= (fmax - fmin) w / 2, and the
//      slope of F is at least fmin, so |x_warp - x_table| <= min(w, (fmax - fmin) w / (2 fmin)).
//   pdf: the table's density is the bucket average, the warp's density at x lies
//      in [fmin, fmax]: |pdf_warp - pdf_table| <= fmax - fmin.
//
//   CDF accuracy: the table's CDF at bucket edges is off by its float rounding
//      (2^-24, and 2^-24 more for rounding u), the float rounding of the density
//      values (2^-22, relative, if systematic), and the quadrature error of the
//      bucket averages accumulated up to there. That error is estimated per bucket
//      from the one-panel trapezoid T (edges) against the 16-point midpoint rule M:
//      their errors are -2 x 16^2 : 1 for smooth f, so |T - M| / 256 overstates
//      M's error by ~2x. So x is only determined to within the interval C^-1(u -+ delta) of
//      the table's CDF C (in double): its width is added to the x tolerance. It
//      is ~delta / density, and large only where the density is tiny (in the tail
//      of c = 100 on [0, 1], the last 2^-24 of mass spans x in [0.166, 1]).
//
// fmin and fmax come from the supersample points and bucket edges; a 25% margin
// covers extrema between those points. The densities compared are the warp's at
// its sample and the table's in the bucket holding that sample (with its
// neighbour when the sample is within float slack of an edge), relative to the
// larger of the two. Float slack on top: 16 ulps of the range for x (the warp's
// own rounding) and 1e-5 relative for densities. A density that does not
// integrate to 1 - tail_mass over the range fails on its own, with the midpoint
// rule's error bound (sum over buckets of (fmax - fmin) w / supersamples) as tolerance.
// A truncated half-line: inputs beyond 1 - tail_mass are checked to land beyond
// the truncation point, and the rest compare with the table scaled to 1 - tail_mass.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "sampling/float_bits.h"
#include "sampling/piecewise_constant.h"
#include "sampling/tabulate.h"
#include "validate/checks/checks.h"
#include "validate/checks/formatting.h"
#include "validate/checks/input_chunks.h"

namespace warpcheck {
namespace {

constexpr int kBuckets = 1 << 16;
constexpr int kSupersamples = 16;
constexpr double kMargin = 1.25;
constexpr double kFloatEps = 0x1p-24;
constexpr double kPdfRelativeSlack = 1e-5;
constexpr std::size_t kWorstKept = 10;
constexpr int kPlotPoints = 257;

/// The resolved 1D view: what is compared, from which input.
struct View {
    MonotoneMarginal m;
    bool use_warp_pdf = false;
};

struct Point {
    double ratio = 0.0;  ///< max(x error / tolerance, pdf error / tolerance); inf for a failure of kind
    WarpInput input;
    double x_warp = 0.0, x_table = 0.0, x_tol = 0.0;
    double pdf_warp = 0.0, pdf_table = 0.0, pdf_tol = 0.0;
    bool tail = false;
};

struct Stats {
    uint64_t count = 0, x_failures = 0, pdf_failures = 0, tail_samples = 0, tail_failures = 0, undetermined = 0;
    double max_x_error = 0.0, max_x_ratio = 0.0, where_x = 0.0, x_tol_at_worst = 0.0;
    double max_pdf_error = 0.0, max_pdf_ratio = 0.0, where_pdf = 0.0, pdf_tol_at_worst = 0.0;
    std::vector<Point> worst;

    void keep(const Point& p) {
        worst.push_back(p);
        std::stable_sort(worst.begin(), worst.end(), [](const Point& a, const Point& b) {
            const double ra = std::isnan(a.ratio) ? std::numeric_limits<double>::infinity() : a.ratio;
            const double rb = std::isnan(b.ratio) ? std::numeric_limits<double>::infinity() : b.ratio;
            return ra > rb;
        });
        if (worst.size() > kWorstKept) worst.resize(kWorstKept);
    }
    void merge(const Stats& s) {
        count += s.count;
        x_failures += s.x_failures;
        pdf_failures += s.pdf_failures;
        tail_samples += s.tail_samples;
        tail_failures += s.tail_failures;
        undetermined += s.undetermined;
        if (!(s.max_x_ratio <= max_x_ratio)) {
            max_x_ratio = s.max_x_ratio;
            where_x = s.where_x;
            x_tol_at_worst = s.x_tol_at_worst;
        }
        if (!(s.max_x_error <= max_x_error)) max_x_error = s.max_x_error;
        if (!(s.max_pdf_ratio <= max_pdf_ratio)) {
            max_pdf_ratio = s.max_pdf_ratio;
            where_pdf = s.where_pdf;
            pdf_tol_at_worst = s.pdf_tol_at_worst;
        }
        if (!(s.max_pdf_error <= max_pdf_error)) max_pdf_error = s.max_pdf_error;
        for (const Point& p : s.worst) keep(p);
    }
};

bool resolve(const WarpCase& warp, View& view) {
    const WarpCaseInfo& info = warp.info();
    const chi2::Domain& d = warp.domain();
    if (info.marginal) {
        view.m = *info.marginal;
        if (!view.m.pdf) {
            if (info.input != InputKind::Uniform1D) return false;
            view.use_warp_pdf = true;
        }
        return true;
    }
    if (info.input == InputKind::Uniform1D && d.kind == chi2::DomainKind::Interval) {
        view.m.lo = d.a;
        view.m.hi = d.b;
        view.m.label = std::string(1, 'x');  // not = "x": GCC 12 reports a false -Wrestrict there
        view.use_warp_pdf = true;
        return true;
    }
    return false;
}

class TabulatedCheck final : public Check {
public:
    std::string name() const override { return "tabulated"; }
    std::string description() const override {
        return "sample(u) and pdf against the inversion method on a 65536-bucket table of the density "
               "(1D warps and monotone 1D marginals)";
    }
    bool applies_to(const WarpCase& warp) const override {
        View v;
        return !takes_bits(warp.input_kind()) && resolve(warp, v);
    }

    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        View view;
        if (!resolve(warp, view)) throw std::runtime_error("the tabulated check does not apply to this case");
        const MonotoneMarginal& m = view.m;
        if (!(m.lo < m.hi) || !(m.tail_mass >= 0.0 && m.tail_mass < 1.0) || (m.tail_mass > 0.0 && !m.increasing))
            throw std::runtime_error("invalid marginal: needs lo < hi, 0 <= tail_mass < 1, and increasing if truncated");
        const int k = m.input_coordinate;
        if (k < 0 || k >= input_dimension(warp.input_kind()))
            throw std::runtime_error("invalid marginal: input_coordinate out of range");

        // The density as a function of the coordinate, in double.
        auto density = [&](double x) -> double {
            if (!view.use_warp_pdf) return m.pdf(x);
            const WarpOutput o{static_cast<float>(x), 0.0f, 0.0f};
            double p = 0.0;
            warp.pdf(std::span<const WarpOutput>(&o, 1), std::span<double>(&p, 1));
            return p;
        };
        auto coordinate = [&](const WarpOutput& o) -> double {
            return m.coordinate ? m.coordinate(o) : static_cast<double>(o[0]);
        };

        // The table.
        const std::vector<BucketSummary> buckets = tabulate_buckets(density, m.lo, m.hi, kBuckets, kSupersamples);
        std::vector<float> values(buckets.size());
        const double width = (m.hi - m.lo) / kBuckets;
        double integral = 0.0, integral_tol = 1e-5;
        for (std::size_t i = 0; i < buckets.size(); ++i) {
            values[i] = static_cast<float>(buckets[i].mean);
            integral += buckets[i].mean * width;
            integral_tol += (buckets[i].max - buckets[i].min) * width / kSupersamples;
        }
        if (!std::isfinite(integral))
            throw std::runtime_error("the density is not finite everywhere on the tabulated range");
        const PiecewiseConstant1D table(values, static_cast<float>(m.lo), static_cast<float>(m.hi));
        const double body_mass = 1.0 - m.tail_mass;
        const double x_slack_abs = 16.0 * kFloatEps * std::max(std::abs(m.lo), std::abs(m.hi));

        // The table's CDF in double, for the interval of x that its float CDF cannot tell apart.
        std::vector<double> cdf(buckets.size() + 1, 0.0);
        for (std::size_t i = 0; i < buckets.size(); ++i) cdf[i + 1] = cdf[i] + buckets[i].mean * width;
        for (double& c : cdf) c /= integral;
        double quadrature_error = 0.0;
        {
            double left = density(m.lo);
            for (std::size_t i = 0; i < buckets.size(); ++i) {
                const double right = density(m.lo + width * static_cast<double>(i + 1));
                quadrature_error += std::abs(0.5 * (left + right) - buckets[i].mean) * width / 256.0;
                left = right;
            }
        }
        const double cdf_delta = 2.0 * kFloatEps + 4.0 * kFloatEps + quadrature_error / integral;
        auto inverse_cdf = [&](double v) {
            v = std::clamp(v, 0.0, 1.0);
            const auto it = std::upper_bound(cdf.begin(), cdf.end(), v);
            const std::size_t o = std::min<std::size_t>(static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - cdf.begin() - 1, 0)),
                                                        buckets.size() - 1);
            const double w = cdf[o + 1] - cdf[o];
            const double t = w > 0.0 ? std::clamp((v - cdf[o]) / w, 0.0, 1.0) : 0.0;
            return m.lo + (static_cast<double>(o) + t) * width;
        };
        auto x_tolerance = [&](int o, double u_body) {
            const BucketSummary& b = buckets[static_cast<std::size_t>(o)];
            const double shape = b.min > 0.0 ? (b.max - b.min) * width / (2.0 * b.min) : width;
            const double cdf_spread = inverse_cdf(u_body + cdf_delta) - inverse_cdf(u_body - cdf_delta);
            return kMargin * std::min(width, shape) + x_slack_abs + cdf_spread;
        };
        // The table's density around x (the bucket holding x, and its neighbour if
        // x is within float slack of the edge): [min, max] of f and the bucket's density.
        struct Envelope {
            double lo, hi, table_pdf;
        };
        auto envelope = [&](double x) -> Envelope {
            if (!(x >= m.lo - x_slack_abs && x <= m.hi + x_slack_abs)) return {0.0, 0.0, 0.0};
            const double t = (x - m.lo) / width;
            const int o = std::clamp(static_cast<int>(t), 0, kBuckets - 1);
            Envelope e{buckets[static_cast<std::size_t>(o)].min, buckets[static_cast<std::size_t>(o)].max,
                       buckets[static_cast<std::size_t>(o)].mean / integral * body_mass};
            for (int n : {o - 1, o + 1}) {
                if (n < 0 || n >= kBuckets) continue;
                const double edge = m.lo + (n < o ? o : o + 1) * width;
                if (std::abs(x - edge) > x_slack_abs) continue;
                e.lo = std::min(e.lo, buckets[static_cast<std::size_t>(n)].min);
                e.hi = std::max(e.hi, buckets[static_cast<std::size_t>(n)].max);
            }
            return e;
        };
        auto pdf_tolerance = [&](const Envelope& e, double reference) {  // relative to `reference`
            return kMargin * (e.hi - e.lo) / integral * body_mass / reference + integral_tol / body_mass +
                   kPdfRelativeSlack;
        };

        auto chunks = map_input_chunks<Stats>(ctx, warp.input_kind(), ctx.options().samples, true,
                                              [&](std::size_t, std::span<const WarpInput> inputs) {
            Stats s;
            std::vector<WarpOutput> x(inputs.size());
            std::vector<double> warp_pdf(inputs.size());
            warp.sample(inputs, x);
            if (view.use_warp_pdf) warp.pdf(x, warp_pdf);
            for (std::size_t i = 0; i < inputs.size(); ++i) {
                ++s.count;
                Point p;
                p.input = inputs[i];
                p.x_warp = coordinate(x[i]);
                // A finite output whose coordinate is undefined (the azimuth at a pole) is
                // skipped; a non-finite output is not, and fails below.
                if (std::isnan(p.x_warp) && m.coordinate && std::isfinite(x[i][0]) && std::isfinite(x[i][1]) &&
                    std::isfinite(x[i][2])) {
                    ++s.undetermined;
                    continue;
                }
                const double u_in = inputs[i].u[static_cast<std::size_t>(k)];
                const double u = m.increasing ? u_in : 1.0 - u_in;  // exact for u on the float grid of [0,1)
                if (u >= body_mass) {
                    // The truncated tail: the warp must land beyond the truncation point.
                    ++s.tail_samples;
                    p.tail = true;
                    p.x_table = m.hi;
                    p.x_tol = x_slack_abs;
                    if (!(p.x_warp >= m.hi - x_slack_abs)) {
                        ++s.tail_failures;
                        p.ratio = std::numeric_limits<double>::infinity();
                        s.keep(p);
                    }
                    continue;
                }
                const double u_body = u / body_mass;
                const PiecewiseConstant1D::Sample t = table.sample(static_cast<float>(u_body));
                p.x_table = t.x;
                p.x_tol = x_tolerance(t.offset, u_body);
                p.pdf_warp = view.use_warp_pdf ? warp_pdf[i] : m.pdf(p.x_warp);
                const Envelope env = envelope(p.x_warp);
                p.pdf_table = env.table_pdf;
                const double reference = std::max(p.pdf_warp, p.pdf_table);  // 0 for both: NaN, a failure
                p.pdf_tol = pdf_tolerance(env, reference);
                const double dx = std::abs(p.x_warp - p.x_table);
                const double dp = std::abs(p.pdf_warp - p.pdf_table) / reference;
                const double rx = dx / p.x_tol, rp = dp / p.pdf_tol;
                if (!(dx <= p.x_tol)) ++s.x_failures;
                if (!(dp <= p.pdf_tol)) ++s.pdf_failures;
                if (!(dx <= s.max_x_error)) s.max_x_error = dx;
                if (!(dp <= s.max_pdf_error)) s.max_pdf_error = dp;
                if (!(rx <= s.max_x_ratio)) {
                    s.max_x_ratio = rx;
                    s.where_x = p.x_warp;
                    s.x_tol_at_worst = p.x_tol;
                }
                if (!(rp <= s.max_pdf_ratio)) {
                    s.max_pdf_ratio = rp;
                    s.where_pdf = p.x_warp;
                    s.pdf_tol_at_worst = p.pdf_tol;
                }
                p.ratio = std::isnan(rx) || std::isnan(rp) ? std::numeric_limits<double>::quiet_NaN()
                                                           : std::max(rx, rp);
                if (s.worst.size() < kWorstKept || !(p.ratio <= s.worst.back().ratio)) s.keep(p);
            }
            return s;
        });
        Stats total;
        for (const Stats& s : chunks) total.merge(s);

        // Verdict.
        const double integral_error = std::abs(integral + m.tail_mass - 1.0);
        const bool normalised = integral_error <= integral_tol;
        std::vector<std::string> problems;
        if (!normalised)
            problems.push_back(fmt::format("the density integrates to {:.6g} over [{:.6g}, {:.6g}]{}, not {:.6g} "
                                           "(tolerance {:.2g})",
                                           integral, m.lo, m.hi,
                                           m.tail_mass > 0.0 ? fmt::format(" with tail mass {:.3g}", m.tail_mass) : "",
                                           body_mass, integral_tol));
        if (total.x_failures > 0)
            problems.push_back(fmt::format("{} of {} samples differ from the table's by more than the bucket "
                                           "bound (worst {:.3g} x tolerance, at {} = {:.6g})",
                                           total.x_failures, total.count, total.max_x_ratio, m.label, total.where_x));
        if (total.pdf_failures > 0)
            problems.push_back(fmt::format("{} of {} densities differ from the table's by more than the bucket "
                                           "bound (worst {:.3g} x tolerance, at {} = {:.6g})",
                                           total.pdf_failures, total.count, total.max_pdf_ratio, m.label,
                                           total.where_pdf));
        if (total.tail_failures > 0)
            problems.push_back(fmt::format("{} of {} inputs in the tail (u >= {:.6g}) land below the truncation "
                                           "point {:.6g}",
                                           total.tail_failures, total.tail_samples, body_mass, m.hi));

        CheckResult r;
        r.samples = total.count;
        r.verdict = problems.empty() ? Verdict::Pass : Verdict::Fail;
        r.summary = fmt::format("max |dx| {:.2e} ({:.2f} of tol), pdf {:.2e} ({:.2f} of tol)", total.max_x_error,
                                total.max_x_ratio, total.max_pdf_error, total.max_pdf_ratio);
        if (!normalised) r.summary = fmt::format("density integrates to {:.6g}", integral + m.tail_mass);
        for (std::size_t i = 0; i < problems.size(); ++i) r.message += (i ? "; " : "") + problems[i];
        r.figures = {{"buckets", static_cast<double>(kBuckets)},
                     {"bucket_width", width},
                     {"max_x_error", total.max_x_error},
                     {"max_x_error_over_tolerance", total.max_x_ratio},
                     {"x_tolerance_at_worst", total.x_tol_at_worst},
                     {"where_x", total.where_x},
                     {"max_pdf_rel_error", total.max_pdf_error},
                     {"max_pdf_error_over_tolerance", total.max_pdf_ratio},
                     {"pdf_tolerance_at_worst", total.pdf_tol_at_worst},
                     {"where_pdf", total.where_pdf},
                     {"table_integral", integral},
                     {"integral_tolerance", integral_tol},
                     {"cdf_uncertainty", cdf_delta},
                     {"tail_mass", m.tail_mass},
                     {"tail_samples", static_cast<double>(total.tail_samples)},
                     {"x_failures", static_cast<double>(total.x_failures)},
                     {"pdf_failures", static_cast<double>(total.pdf_failures)},
                     {"tail_failures", static_cast<double>(total.tail_failures)},
                     {"undetermined_coordinate", static_cast<double>(total.undetermined)}};

        // Plots: the two inverse CDFs (the warp's with the other input at 0.5) and
        // their difference against the tolerance; the analytic and tabulated density.
        Plot inverse{Plot::Kind::Lines, "Inverse CDF: warp and table", "u", m.label, false, false, {}, {}};
        Plot diff{Plot::Kind::Lines, "|x_warp - x_table| and its tolerance", "u", "error", false, true, {}, {}};
        Series sw{"warp sample(u)", {}, {}}, st{"table sample(u)", {}, {}};
        Series sd{"|difference|", {}, {}}, stol{"tolerance", {}, {}};
        std::vector<WarpInput> grid(kPlotPoints);
        for (int i = 0; i < kPlotPoints; ++i) {
            const float u = std::min(static_cast<float>(i) / (kPlotPoints - 1) * 0.999f, kOneMinusEpsilon);
            grid[static_cast<std::size_t>(i)].u = {0.5f, 0.5f};
            grid[static_cast<std::size_t>(i)].u[static_cast<std::size_t>(k)] = m.increasing ? u : 1.0f - u;
        }
        std::vector<WarpOutput> gx(grid.size());
        warp.sample(grid, gx);
        for (int i = 0; i < kPlotPoints; ++i) {
            const double u = static_cast<double>(static_cast<float>(i) / (kPlotPoints - 1) * 0.999f);
            const double xw = coordinate(gx[static_cast<std::size_t>(i)]);
            if (std::isnan(xw)) continue;
            sw.x.push_back(u);
            sw.y.push_back(xw);
            if (u < body_mass) {
                const auto t = table.sample(static_cast<float>(u / body_mass));
                st.x.push_back(u);
                st.y.push_back(t.x);
                sd.x.push_back(u);
                sd.y.push_back(std::max(std::abs(xw - t.x), 1e-30));
                stol.x.push_back(u);
                stol.y.push_back(x_tolerance(t.offset, u / body_mass));
            }
        }
        inverse.series = {std::move(sw), std::move(st)};
        diff.series = {std::move(sd), std::move(stol)};
        Plot dens{Plot::Kind::Lines, "Density: analytic and tabulated", m.label, "density", false, false, {}, {}};
        Series sa{"analytic", {}, {}}, sb{"table", {}, {}}, sdd{"difference", {}, {}};
        const int stride = kBuckets / 512;
        for (int b = 0; b < kBuckets; b += stride) {
            const double xc = m.lo + (b + 0.5) * width;
            const double analytic = density(xc);
            const double tab = static_cast<double>(table.pdf(static_cast<float>(xc))) * body_mass;
            sa.x.push_back(xc);
            sa.y.push_back(analytic);
            sb.x.push_back(xc);
            sb.y.push_back(tab);
            sdd.x.push_back(xc);
            sdd.y.push_back(analytic - tab);
        }
        dens.series = {std::move(sa), std::move(sb), std::move(sdd)};
        r.plots = {std::move(inverse), std::move(diff), std::move(dens)};

        Table worst{"Worst points (largest error relative to tolerance)",
                    {"input u", m.label + " warp", m.label + " table", "|dx|", "x tol", "pdf warp", "pdf table",
                     "pdf rel err (of larger)", "pdf tol"},
                    {}};
        for (const Point& p : total.worst) {
            if (p.tail) {
                worst.rows.push_back({format_input(p.input, warp.input_kind()), fmt::format("{:.9g}", p.x_warp),
                                      fmt::format(">= {:.9g}", p.x_table), "tail", "", "", "", "", ""});
                continue;
            }
            worst.rows.push_back({format_input(p.input, warp.input_kind()), fmt::format("{:.9g}", p.x_warp),
                                  fmt::format("{:.9g}", p.x_table), fmt::format("{:.3e}", std::abs(p.x_warp - p.x_table)),
                                  fmt::format("{:.3e}", p.x_tol), fmt::format("{:.6g}", p.pdf_warp),
                                  fmt::format("{:.6g}", p.pdf_table),
                                  fmt::format("{:.3e}", std::abs(p.pdf_warp - p.pdf_table) /
                                                            std::max(p.pdf_warp, p.pdf_table)),
                                  fmt::format("{:.3e}", p.pdf_tol)});
        }
        r.tables.push_back(std::move(worst));
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_tabulated_check() { return std::make_unique<TabulatedCheck>(); }

}  // namespace warpcheck

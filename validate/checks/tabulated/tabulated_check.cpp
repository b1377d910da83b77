// "tabulated": the warp against the inversion method on a tabulated copy of its
// own density (validate/checks/tabulated/tabulated_reference.h explains the table and the
// tolerances its discretisation implies).
//
// The density of a 1D warp (or the marginal density of a monotone coordinate of
// a 2D warp, see MonotoneMarginal) is tabulated and, for the same u, the warp's
// sample and density are compared with the table's. A truncated line (a
// half-line either way, or the real line): inputs below lower_tail_mass are
// checked to land below lo, inputs beyond 1 - tail_mass beyond hi, and the rest
// compare with the table scaled to the body's mass between them.
//
// Only where sample is monotone in u is that comparison the right one: a
// declared view claims it (and fails where it is not), a case may declare it
// (WarpCaseInfo::inversion), and a 1D warp without views is measured on a grid
// of inputs (tabulated_monotonicity.h); one that is not monotone is n/a, with
// where it steps back.
//
// Three parts: compute (one pass over the input chunks), judge (the rule, with
// the table's tolerances) and evidence (inverse CDFs, densities, worst points).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "sampling/float_bits.h"
#include "validate/checks/checks.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/formatting.h"
#include "validate/checks/shared/input_chunks.h"
#include "validate/checks/tabulated/tabulated_monotonicity.h"
#include "validate/checks/tabulated/tabulated_reference.h"

namespace warpcheck {
namespace {

constexpr std::size_t kWorstKept = 10;
constexpr int kPlotPoints = 257;

/// The probability between the view's truncation points.
double body_mass(const MonotoneMarginal& m) { return 1.0 - m.tail_mass - m.lower_tail_mass; }

/// The resolved 1D view: what is compared, from which input, and whether its
/// monotonicity is to be measured (a 1D warp's own view that nothing claims).
struct View {
    MonotoneMarginal m;
    bool use_warp_pdf = false;
    bool measure_monotonicity = false;
};

/// The case's views: each declared one (one without a density uses the warp's
/// own pdf, 1D warps only), or a 1D warp on an interval as its own view.
std::vector<View> resolve(const WarpCase& warp) {
    const WarpCaseInfo& info = warp.info();
    const chi2::Domain& d = warp.domain();
    std::vector<View> views;
    for (const MonotoneMarginal& m : info.views) {
        View view{m, !m.pdf};
        if (view.use_warp_pdf && info.input != InputKind::Uniform1D) continue;
        views.push_back(std::move(view));
    }
    if (info.views.empty() && info.input == InputKind::Uniform1D && d.is<chi2::Interval>()) {
        View view;
        view.m.lo = d.a();
        view.m.hi = d.b();
        view.m.label = std::string(1, 'x');  // not = "x": GCC 12 reports a false -Wrestrict there
        view.use_warp_pdf = true;
        view.measure_monotonicity = info.inversion == Inversion::Measure;
        views.push_back(std::move(view));
    }
    return views;
}

void validate_view(const View& view, const WarpCase& warp) {
    const MonotoneMarginal& m = view.m;
    if (!(m.lo < m.hi) || !(m.tail_mass >= 0.0) || !(m.lower_tail_mass >= 0.0) ||
        !(m.tail_mass + m.lower_tail_mass < 1.0))
        throw std::runtime_error("invalid marginal: needs lo < hi and tail masses >= 0 that sum to less than 1");
    if (m.input_coordinate < 0 || m.input_coordinate >= input_dimension(warp.input_kind()))
        throw std::runtime_error("invalid marginal: input_coordinate out of range");
}

/// The view's coordinate and density as functions, in double.
struct ViewFunctions {
    const WarpCase& warp;
    const View& view;

    double density(double x) const {
        if (!view.use_warp_pdf) return view.m.pdf(x);
        const WarpOutput o{static_cast<float>(x), 0.0f, 0.0f};
        double p = 0.0;
        warp.pdf(std::span<const WarpOutput>(&o, 1), std::span<double>(&p, 1));
        return p;
    }
    double coordinate(const WarpOutput& o) const {
        return view.m.coordinate ? view.m.coordinate(o) : static_cast<double>(o[0]);
    }
    /// A finite output whose coordinate is undefined (the azimuth at a pole).
    bool undetermined(double coord, const WarpOutput& o) const {
        return std::isnan(coord) && view.m.coordinate && std::isfinite(o[0]) && std::isfinite(o[1]) &&
               std::isfinite(o[2]);
    }
};

struct Point {
    WarpInput input;
    double x_warp = 0.0, x_table = 0.0, x_tol = 0.0;
    double pdf_warp = 0.0, pdf_table = 0.0, pdf_tol = 0.0;
    bool tail = false;
};

/// The largest error over tolerance of one kind, where it was, and its tolerance there.
struct Extreme {
    double error = 0.0, ratio = 0.0, where = 0.0, tol_at_worst = 0.0;

    /// A NaN error or ratio is the worst and stays (a later number must not replace it).
    void see(double err, double ratio_here, double x, double tol) {
        if (!(err <= error) && !std::isnan(error)) error = err;
        if (!(ratio_here <= ratio) && !std::isnan(ratio)) {
            ratio = ratio_here;
            where = x;
            tol_at_worst = tol;
        }
    }
    void merge(const Extreme& o) { see(o.error, o.ratio, o.where, o.tol_at_worst); }
};

struct Stats {
    uint64_t count = 0, x_failures = 0, pdf_failures = 0, tail_samples = 0, tail_failures = 0, undetermined = 0;
    uint64_t nan_samples = 0;  ///< samples whose coordinate is NaN (not an undetermined azimuth)
    uint64_t nan_pdfs = 0;     ///< finite samples whose density is NaN (counted among the pdf failures too)
    uint64_t zero_density = 0;  ///< samples where the warp's and the table's densities are both 0
    Extreme x, pdf;
    /// The range the warp's samples reached (edge inputs included).
    double reach_lo = std::numeric_limits<double>::infinity(), reach_hi = -std::numeric_limits<double>::infinity();
    WorstK<Point> worst{kWorstKept};  // keyed by max(x error / tolerance, pdf error / tolerance)

    void merge(const Stats& s) {
        count += s.count;
        x_failures += s.x_failures;
        pdf_failures += s.pdf_failures;
        tail_samples += s.tail_samples;
        tail_failures += s.tail_failures;
        undetermined += s.undetermined;
        nan_samples += s.nan_samples;
        nan_pdfs += s.nan_pdfs;
        zero_density += s.zero_density;
        x.merge(s.x);
        pdf.merge(s.pdf);
        reach_lo = std::min(reach_lo, s.reach_lo);
        reach_hi = std::max(reach_hi, s.reach_hi);
        worst.merge(s.worst);
    }
};

/// What the compute part needs to compare one input.
struct Comparison {
    const ViewFunctions& f;
    const TabulatedReference& ref;
    double body_mass;

    /// Inputs beyond the body: the warp must land beyond the truncation point
    /// at that end, within the x extent of the CDF uncertainty there and the
    /// float slack: the allowance a body input next to it gets. (With the float
    /// slack alone, a correct float logistic, mu - s log(1/u - 1), failed at the
    /// one input float next to its truncation's u, where 1/u - 1 loses a float
    /// step of u and x lands 7.5e-5 short of hi: 15 times the slack, a twelfth
    /// of the body's allowance there.)
    void tail(Stats& s, Point p, bool upper, uint64_t index) const {
        ++s.tail_samples;
        p.tail = true;
        p.x_table = upper ? f.view.m.hi : f.view.m.lo;
        p.x_tol = ref.tail_allowance(upper);
        if (upper ? p.x_warp >= f.view.m.hi - p.x_tol : p.x_warp <= f.view.m.lo + p.x_tol) return;
        ++s.tail_failures;
        s.worst.offer(std::numeric_limits<double>::infinity(), index, p);
    }

    void body(Stats& s, Point p, const TabulatedReference::Lookup& t, double warp_pdf, uint64_t index) const {
        p.x_table = t.sample.x;
        p.x_tol = t.x_tolerance;
        p.pdf_warp = f.view.use_warp_pdf ? warp_pdf : f.view.m.pdf(p.x_warp);
        const TabulatedReference::Envelope& env = t.envelope;
        p.pdf_table = env.table_pdf;
        if (std::isfinite(p.x_warp)) {
            s.reach_lo = std::min(s.reach_lo, p.x_warp);
            s.reach_hi = std::max(s.reach_hi, p.x_warp);
        }
        // Both densities 0 agree inside the range: a sample at the edge of the
        // support (u = 0 of a cos^1000 lobe gives z = 0, where the density is 0
        // even in double); such samples are counted, and their x is still
        // judged, so one off in a zero-density gap fails there. Outside the
        // range (beyond the float slack) a zero density stays a failure.
        const bool inside = p.x_warp >= f.view.m.lo - ref.x_slack() && p.x_warp <= f.view.m.hi + ref.x_slack();
        const bool both_zero = inside && p.pdf_warp == 0.0 && p.pdf_table == 0.0;
        s.zero_density += both_zero ? 1 : 0;
        const double reference = std::max(p.pdf_warp, p.pdf_table);
        p.pdf_tol = both_zero ? 0.0 : ref.pdf_tolerance(env, reference);
        const double dp = both_zero ? 0.0 : std::abs(p.pdf_warp - p.pdf_table) / reference;
        record(s, p, dp, both_zero ? 0.0 : dp / p.pdf_tol, index);
    }

    /// Counts the point's failures and keeps it if it is among the worst.
    static void record(Stats& s, const Point& p, double dp, double rp, uint64_t index) {
        const double dx = std::abs(p.x_warp - p.x_table);
        const double rx = dx / p.x_tol;
        if (!(dx <= p.x_tol)) ++s.x_failures;
        if (!(dp <= p.pdf_tol)) ++s.pdf_failures;
        if (std::isnan(p.pdf_warp)) ++s.nan_pdfs;
        s.x.see(dx, rx, p.x_warp, p.x_tol);
        s.pdf.see(dp, rp, p.x_warp, p.pdf_tol);
        const double ratio = std::isnan(rx) || std::isnan(rp) ? std::numeric_limits<double>::quiet_NaN()
                                                              : std::max(rx, rp);
        if (s.worst.wants(ratio)) s.worst.offer(ratio, index, p);
    }

    /// The view's input u, in the direction the coordinate grows.
    double view_u(const WarpInput& in) const {
        const double u_in = in.u[static_cast<std::size_t>(f.view.m.input_coordinate)];
        return f.view.m.increasing ? u_in : 1.0 - u_in;  // exact for u on the float grid of [0,1)
    }
    bool in_tail(double u) const {
        const double lower = f.view.m.lower_tail_mass;
        return u < lower || u >= lower + body_mass;
    }
    /// Where the table is looked up for this input: its u within the body; NaN for a tail input.
    double u_body(const WarpInput& in) const {
        const double u = view_u(in);
        return in_tail(u) ? std::numeric_limits<double>::quiet_NaN() : (u - f.view.m.lower_tail_mass) / body_mass;
    }

    /// Compares one input's sample, whose view coordinate is `x`; `t` is the
    /// table's lookup at u_body(in) and x.
    void operator()(Stats& s, const WarpInput& in, const WarpOutput& out, double x, double warp_pdf,
                    const TabulatedReference::Lookup& t, uint64_t index) const {
        ++s.count;
        Point p;
        p.input = in;
        p.x_warp = x;
        if (f.undetermined(p.x_warp, out)) {
            ++s.undetermined;
            return;
        }
        if (std::isnan(p.x_warp)) {  // a failure of its own, not compared with the table
            ++s.nan_samples;
            s.worst.offer(std::numeric_limits<double>::quiet_NaN(), index, p);
            return;
        }
        const double u = view_u(in);
        if (in_tail(u)) tail(s, p, u >= f.view.m.lower_tail_mass, index);
        else body(s, p, t, warp_pdf, index);
    }
};

Stats compute(const WarpCase& warp, const CheckContext& ctx, const Comparison& compare) {
    auto parts = map_input_chunks<Stats>(ctx, warp.input_kind(), ctx.options().samples, true,
                                         [&](std::size_t chunk, std::span<const WarpInput> inputs) {
        Stats s;
        // In blocks that stay in the cache between the steps.
        constexpr std::size_t kBlock = 2048;
        std::vector<WarpOutput> x(kBlock);
        std::vector<double> warp_pdf(kBlock), u_body(kBlock), coordinate(kBlock);
        std::vector<TabulatedReference::Lookup> table(kBlock);
        for (std::size_t first = 0; first < inputs.size(); first += kBlock) {
            const std::size_t n = std::min(kBlock, inputs.size() - first);
            const std::span<const WarpInput> in = inputs.subspan(first, n);
            warp.sample(in, std::span(x).first(n));
            if (compare.f.view.use_warp_pdf) warp.pdf(std::span(x).first(n), std::span(warp_pdf).first(n));
            for (std::size_t i = 0; i < n; ++i) {
                u_body[i] = compare.u_body(in[i]);
                coordinate[i] = compare.f.coordinate(x[i]);
            }
            compare.ref.lookup(std::span(u_body).first(n), std::span(coordinate).first(n), std::span(table).first(n));
            for (std::size_t i = 0; i < n; ++i)
                compare(s, in[i], x[i], coordinate[i], warp_pdf[i], table[i], chunk * kInputChunkSize + first + i);
        }
        return s;
    });
    return merge_in_order(parts);
}

/// The mass of the view that the samples never reached, against what a float
/// warp can reach: at each end without a tail, the mass of the float step beyond
/// the reached extreme (the samples are floats: none can land strictly between
/// the last float reached and the next, so a correct warp that rounds the last
/// step's values onto the reached float, or clamps below the end as renderers
/// do, leaves that mass unreached), plus one input's mass (2^-24: the largest
/// input float below 1 stands for [1 - 2^-24, 1)) and the table CDF's own
/// uncertainty at both ends. A truncated end is a tail, checked apart. Under
/// --strict the float steps are reported but not granted.
struct Reach {
    double outside = 0.0, float_steps = 0.0, tolerance = 0.0;
};

/// The first float strictly above x (below, when !up), as a double.
double next_float_beyond(double x, bool up) {
    const auto f = static_cast<float>(x);
    if (up) return static_cast<double>(static_cast<double>(f) > x ? f : next_float_up(f));
    return static_cast<double>(static_cast<double>(f) < x ? f : next_float_down(f));
}

Reach reach_of(const Stats& s, const MonotoneMarginal& m, const TabulatedReference& ref, bool strict) {
    if (!(s.reach_lo <= s.reach_hi)) return {};  // no body sample: nothing reached, nothing to say
    double below = 0.0, above = 0.0, steps = 0.0;
    if (m.lower_tail_mass == 0.0) {
        below = ref.cdf(s.reach_lo);
        steps += below - ref.cdf(next_float_beyond(s.reach_lo, false));
    }
    if (m.tail_mass == 0.0) {
        above = 1.0 - ref.cdf(s.reach_hi);
        steps += ref.cdf(next_float_beyond(s.reach_hi, true)) - ref.cdf(s.reach_hi);
    }
    const double body = body_mass(m);
    const double granted = strict ? 0.0 : steps * body;
    return {(below + above) * body, steps * body, granted + 0x1p-24 + 2.0 * ref.cdf_uncertainty()};
}

/// The density's own problems: NaN values (no table), or an integral off the body's mass.
void density_problems(std::vector<std::string>& problems, const MonotoneMarginal& m, const TabulatedReference& ref) {
    const double tails = m.tail_mass + m.lower_tail_mass;
    if (ref.nan_values() > 0) {
        problems.push_back(fmt::format("the density is NaN at {} of the {} points where it was tabulated on "
                                       "[{:.6g}, {:.6g}] (first at {} = {:.9g})",
                                       ref.nan_values() == ref.evaluations() ? "all" : std::to_string(ref.nan_values()),
                                       ref.evaluations(), m.lo, m.hi, m.label, ref.first_nan_x()));
        return;
    }
    if (!(std::abs(ref.integral() + tails - 1.0) <= ref.integral_tolerance()))
        problems.push_back(fmt::format("the density integrates to {:.6g} over [{:.6g}, {:.6g}]{}, not {:.6g} "
                                       "(tolerance {:.2g})",
                                       ref.integral(), m.lo, m.hi,
                                       tails > 0.0 ? fmt::format(" with tail mass {:.3g}", tails) : "",
                                       body_mass(m), ref.integral_tolerance()));
}

/// NaN samples and densities, and samples or densities off the table's.
void sample_problems(std::vector<std::string>& problems, const Stats& s, const MonotoneMarginal& m) {
    if (s.nan_samples > 0 && s.nan_samples == s.count)
        problems.push_back(fmt::format("every sample is NaN ({} of {})", s.nan_samples, s.count));
    else if (s.nan_samples > 0)
        problems.push_back(fmt::format("{} of {} samples are NaN", s.nan_samples, s.count));
    if (s.nan_pdfs > 0) problems.push_back(fmt::format("the density is NaN at {} of the samples", s.nan_pdfs));
    if (s.x_failures > 0)
        problems.push_back(fmt::format("{} of {} samples differ from the table's by more than the bucket "
                                       "bound (worst {:.3g} x tolerance, at {} = {:.6g})",
                                       s.x_failures, s.count, s.x.ratio, m.label, s.x.where));
    if (s.pdf_failures > s.nan_pdfs)
        problems.push_back(fmt::format("{} of {} densities differ from the table's by more than the bucket "
                                       "bound (worst {:.3g} x tolerance, at {} = {:.6g})",
                                       s.pdf_failures - s.nan_pdfs, s.count, s.pdf.ratio, m.label, s.pdf.where));
}

/// Mass the samples never reach, and tail inputs that land inside the truncation.
void range_problems(std::vector<std::string>& problems, const Stats& s, const MonotoneMarginal& m,
                    const TabulatedReference& ref, bool strict) {
    const Reach reach = reach_of(s, m, ref, strict);
    if (!(reach.outside <= reach.tolerance))
        problems.push_back(fmt::format("the samples reach only [{:.9g}, {:.9g}] of [{:.6g}, {:.6g}]: {:.3g} of the "
                                       "mass lies where no input float can land (tolerance {:.2g}; the float steps "
                                       "beyond the reached ends hold {:.2g}{})",
                                       s.reach_lo, s.reach_hi, m.lo, m.hi, reach.outside, reach.tolerance,
                                       reach.float_steps, strict ? ", not granted under --strict" : ""));
    if (s.tail_failures > 0)
        problems.push_back(fmt::format("{} of {} inputs in the tails (u < {:.6g} or u >= {:.6g}) land inside the "
                                       "truncation points [{:.6g}, {:.6g}] by more than the allowance there "
                                       "({:.3g} below, {:.3g} above)",
                                       s.tail_failures, s.tail_samples, m.lower_tail_mass,
                                       m.lower_tail_mass + body_mass(m), m.lo, m.hi, ref.tail_allowance(false),
                                       ref.tail_allowance(true)));
}

/// The verdict: the density is a number everywhere on the range and integrates
/// to the body's mass within the midpoint rule's error bound; every sample is
/// a number and it and its density lie within the bucket bounds of
/// TabulatedReference (each justified there); the samples reach the range up
/// to the float steps beyond their extremes; every tail input lands beyond the
/// truncation point (within the CDF uncertainty and float slack there).
///
/// None of these can fail a correct warp by chance, so the check stays outside
/// the Sidak family: the normalisation uses no random input; x, pdf, NaN and
/// tail are judged input by input against bounds that hold at every input of
/// a warp whose float error stays within the stated allowances, so the draw
/// only chooses which inputs are looked at (a set of failing inputs of
/// probability p fails a run of N with probability ~N p, and for a correct
/// warp the set is empty); and the reach of a monotone view is set by the edge
/// inputs u = 0 and 1 - 2^-24, present in every run (random inputs can only
/// widen it). The one part that is not a proof is the 25% margin for extrema
/// between supersample points (TabulatedReference): a density with a feature
/// narrower than 1/16 of a bucket (2^-20 of the range) can exceed it, in that
/// bucket, at every seed alike.
void judge(CheckResult& r, const Stats& s, const MonotoneMarginal& m, const TabulatedReference& ref, bool strict) {
    std::vector<std::string> problems;
    density_problems(problems, m, ref);
    const bool density_ok = problems.empty();
    sample_problems(problems, s, m);
    range_problems(problems, s, m, ref, strict);
    r.verdict = problems.empty() ? Verdict::Pass : Verdict::Fail;
    r.summary = fmt::format("max |dx| {:.2e} ({:.2f} of tol), pdf {:.2e} ({:.2f} of tol)", s.x.error, s.x.ratio,
                            s.pdf.error, s.pdf.ratio);
    if (!density_ok)
        r.summary = fmt::format("density integrates to {:.6g}", ref.integral() + m.tail_mass + m.lower_tail_mass);
    if (s.nan_samples > 0)
        r.summary = s.nan_samples == s.count ? "every sample NaN" : fmt::format("{} NaN samples", s.nan_samples);
    r.message = join_reasons(problems);
}

void add_figures(CheckResult& r, const Stats& s, const MonotoneMarginal& m, const TabulatedReference& ref,
                 bool strict) {
    const Reach reach = reach_of(s, m, ref, strict);
    r.samples = s.count;
    r.figures = {{"buckets", static_cast<double>(TabulatedReference::kBuckets)},
                 {"bucket_width", ref.bucket_width()},
                 {"max_x_error", s.x.error},
                 {"max_x_error_over_tolerance", s.x.ratio},
                 {"x_tolerance_at_worst", s.x.tol_at_worst},
                 {"where_x", s.x.where},
                 {"max_pdf_rel_error", s.pdf.error},
                 {"max_pdf_error_over_tolerance", s.pdf.ratio},
                 {"pdf_tolerance_at_worst", s.pdf.tol_at_worst},
                 {"where_pdf", s.pdf.where},
                 {"table_integral", ref.integral()},
                 {"integral_tolerance", ref.integral_tolerance()},
                 {"cdf_uncertainty", ref.cdf_uncertainty()},
                 {"tail_mass", m.tail_mass},
                 {"lower_tail_mass", m.lower_tail_mass},
                 {"reach_lo", s.reach_lo},
                 {"reach_hi", s.reach_hi},
                 {"mass_outside_reach", reach.outside},
                 {"mass_outside_reach_tolerance", reach.tolerance},
                 {"mass_of_float_steps_beyond_reach", reach.float_steps},
                 {"tail_samples", static_cast<double>(s.tail_samples)},
                 {"x_failures", static_cast<double>(s.x_failures)},
                 {"pdf_failures", static_cast<double>(s.pdf_failures)},
                 {"tail_failures", static_cast<double>(s.tail_failures)},
                 {"nan_samples", static_cast<double>(s.nan_samples)},
                 {"nan_pdfs", static_cast<double>(s.nan_pdfs)},
                 {"samples_where_both_densities_are_0", static_cast<double>(s.zero_density)},
                 {"undetermined_coordinate", static_cast<double>(s.undetermined)}};
    if (m.lower_tail_mass > 0.0) r.figures.push_back({"lower_tail_allowance", ref.tail_allowance(false)});
    if (m.tail_mass > 0.0) r.figures.push_back({"upper_tail_allowance", ref.tail_allowance(true)});
}

/// What the grid of inputs showed about monotonicity, as figures.
void add_monotonicity_figures(CheckResult& r, const MonotonicityProbe& p, double noise) {
    r.figures.push_back({"monotonicity_grid_inputs", static_cast<double>(p.inputs)});
    r.figures.push_back({"monotonicity_finite_outputs", static_cast<double>(p.finite)});
    r.figures.push_back({"monotonicity_increasing", p.increasing ? 1.0 : 0.0});
    r.figures.push_back({"monotonicity_behind_within_noise", static_cast<double>(p.behind_within_noise)});
    r.figures.push_back({"monotonicity_largest_step_back", p.largest_step_back});
    r.figures.push_back({"monotonicity_noise_allowance", noise});
}

/// sample(u) on the grid of the monotonicity probe.
Plot monotonicity_plot(const MonotonicityProbe& p, const std::string& label) {
    Plot plot{Plot::Kind::Lines, "sample(u) on the monotonicity grid", "u", label, false, false, {}, {}};
    plot.series.push_back(Series{"warp sample(u)", p.plot_u, p.plot_x});
    return plot;
}

/// "x falls from 0.73 to 0.12 at u = 0.3": the largest step against the direction.
std::string step_back_text(const MonotonicityProbe& p, const std::string& label) {
    return fmt::format("{} {} from {:.6g} to {:.6g} at u = {:.9g}", label, p.increasing ? "falls" : "rises",
                       p.from_x, p.to_x, p.at_u);
}

/// The n/a result of a 1D warp whose sample the grid shows not to be monotone.
CheckResult not_monotone_result(const MonotonicityProbe& p, const std::string& label, double noise) {
    CheckResult r;
    r.verdict = Verdict::NotApplicable;
    r.summary = fmt::format("not applicable: sample is not monotone in u: {} (chi2 and unbinned test its "
                            "distribution)", step_back_text(p, label));
    r.message = fmt::format("the tabulated check compares sample with the inversion method, which is monotone "
                            "in u; on a grid of {} inputs {} (beyond the float noise allowance {:.3g}). Declare "
                            "WarpCaseInfo::inversion = Inversion::NotInversion to say so, or Claimed if it is an "
                            "inversion sampler",
                            p.inputs, step_back_text(p, label), noise);
    r.samples = p.inputs;
    add_monotonicity_figures(r, p, noise);
    r.plots.push_back(monotonicity_plot(p, label));
    return r;
}

/// The failure of a density that is NaN where it was tabulated: there is no
/// table to compare with. `grid` (when measured) says how the samples fared.
CheckResult nan_density_result(const MonotoneMarginal& m, const TabulatedReference& ref,
                               const std::optional<MonotonicityProbe>& grid) {
    CheckResult r;
    std::vector<std::string> problems;
    density_problems(problems, m, ref);
    if (grid && grid->finite < grid->inputs)
        problems.push_back(grid->finite == 0
                               ? fmt::format("sample is NaN at all {} inputs of the monotonicity grid", grid->inputs)
                               : fmt::format("sample is not finite at {} of the {} inputs of the monotonicity grid",
                                             grid->inputs - grid->finite, grid->inputs));
    r.verdict = Verdict::Fail;
    r.summary = ref.nan_values() == ref.evaluations() ? "density NaN everywhere"
                                                      : fmt::format("density NaN at {} points", ref.nan_values());
    r.message = join_reasons(problems);
    r.figures = {{"density_nan_values", static_cast<double>(ref.nan_values())},
                 {"density_evaluations", static_cast<double>(ref.evaluations())}};
    return r;
}

/// The two inverse CDFs (the warp's with the other input at 0.5) and their
/// difference against the tolerance.
std::vector<Plot> inverse_cdf_plots(const ViewFunctions& f, const TabulatedReference& ref) {
    const MonotoneMarginal& m = f.view.m;
    const auto k = static_cast<std::size_t>(m.input_coordinate);
    Plot inverse{Plot::Kind::Lines, "Inverse CDF: warp and table", "u", m.label, false, false, {}, {}};
    Plot diff{Plot::Kind::Lines, "|x_warp - x_table| and its tolerance", "u", "error", false, true, {}, {}};
    Series sw{"warp sample(u)", {}, {}}, st{"table sample(u)", {}, {}};
    Series sd{"|difference|", {}, {}}, stol{"tolerance", {}, {}};
    std::vector<WarpInput> grid(kPlotPoints);
    for (int i = 0; i < kPlotPoints; ++i) {
        const float u = std::min(static_cast<float>(i) / (kPlotPoints - 1) * 0.999f, kOneMinusEpsilon);
        grid[static_cast<std::size_t>(i)].u = {0.5f, 0.5f};
        grid[static_cast<std::size_t>(i)].u[k] = m.increasing ? u : 1.0f - u;
    }
    std::vector<WarpOutput> gx(grid.size());
    f.warp.sample(grid, gx);
    for (int i = 0; i < kPlotPoints; ++i) {
        const double u = static_cast<double>(static_cast<float>(i) / (kPlotPoints - 1) * 0.999f);
        const double xw = f.coordinate(gx[static_cast<std::size_t>(i)]);
        if (std::isnan(xw)) continue;
        sw.x.push_back(u);
        sw.y.push_back(xw);
        const double u_body = (u - m.lower_tail_mass) / body_mass(m);
        if (!(u_body >= 0.0 && u_body < 1.0)) continue;
        const auto t = ref.sample(u_body);
        st.x.push_back(u);
        st.y.push_back(t.x);
        sd.x.push_back(u);
        sd.y.push_back(std::max(std::abs(xw - t.x), 1e-30));
        stol.x.push_back(u);
        stol.y.push_back(ref.x_tolerance(t.offset, u_body));
    }
    inverse.series = {std::move(sw), std::move(st)};
    diff.series = {std::move(sd), std::move(stol)};
    return {std::move(inverse), std::move(diff)};
}

/// The analytic and the tabulated density, at every 128th bucket centre.
Plot density_plot(const ViewFunctions& f, const TabulatedReference& ref) {
    const MonotoneMarginal& m = f.view.m;
    Plot dens{Plot::Kind::Lines, "Density: analytic and tabulated", m.label, "density", false, false, {}, {}};
    Series sa{"analytic", {}, {}}, sb{"table", {}, {}}, sdd{"difference", {}, {}};
    const int stride = TabulatedReference::kBuckets / 512;
    for (int b = 0; b < TabulatedReference::kBuckets; b += stride) {
        const double xc = m.lo + (b + 0.5) * ref.bucket_width();
        const double analytic = f.density(xc);
        const double tab = ref.table_pdf(xc);
        sa.x.push_back(xc);
        sa.y.push_back(analytic);
        sb.x.push_back(xc);
        sb.y.push_back(tab);
        sdd.x.push_back(xc);
        sdd.y.push_back(analytic - tab);
    }
    dens.series = {std::move(sa), std::move(sb), std::move(sdd)};
    return dens;
}

Table worst_points(const Stats& s, const MonotoneMarginal& m, InputKind kind) {
    Table worst{"Worst points (largest error relative to tolerance)",
                {"input u", m.label + " warp", m.label + " table", "|dx|", "x tol", "pdf warp", "pdf table",
                 "pdf rel err (of larger)", "pdf tol"},
                {}};
    for (const auto& e : s.worst.entries()) {
        const Point& p = e.item;
        if (std::isnan(p.x_warp)) {
            worst.rows.push_back({format_input(p.input, kind), "NaN", "", "", "", "", "", "", ""});
            continue;
        }
        if (p.tail) {
            worst.rows.push_back({format_input(p.input, kind), fmt::format("{:.9g}", p.x_warp),
                                  fmt::format("{} {:.9g}", p.x_table == m.hi ? ">=" : "<=", p.x_table), "tail", "",
                                  "", "", "", ""});
            continue;
        }
        worst.rows.push_back({format_input(p.input, kind), fmt::format("{:.9g}", p.x_warp),
                              fmt::format("{:.9g}", p.x_table), fmt::format("{:.3e}", std::abs(p.x_warp - p.x_table)),
                              fmt::format("{:.3e}", p.x_tol), fmt::format("{:.6g}", p.pdf_warp),
                              fmt::format("{:.6g}", p.pdf_table),
                              fmt::format("{:.3e}", std::abs(p.pdf_warp - p.pdf_table) / std::max(p.pdf_warp, p.pdf_table)),
                              fmt::format("{:.3e}", p.pdf_tol)});
    }
    return worst;
}

/// "cos theta" -> "cos_theta": a view's label as part of a figure name.
std::string figure_label(const std::string& label) {
    std::string out;
    for (char ch : label) out += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
    return out;
}

CheckResult merge_views(const std::vector<View>& views, std::vector<CheckResult>& parts) {
    CheckResult r;
    r.verdict = Verdict::Pass;
    std::vector<std::string> summaries, messages;
    for (std::size_t k = 0; k < views.size(); ++k) {
        CheckResult& p = parts[k];
        const std::string& label = views[k].m.label;
        if (p.verdict == Verdict::Fail) r.verdict = Verdict::Fail;
        summaries.push_back(fmt::format("{}: {}", label, p.summary));
        if (!p.message.empty()) messages.push_back(fmt::format("view {}: {}", label, p.message));
        for (const Figure& f : p.figures) r.figures.push_back({figure_label(label) + "_" + f.name, f.value});
        for (Plot& plot : p.plots) r.plots.push_back(std::move(plot));
        for (Table& t : p.tables) r.tables.push_back(std::move(t));
        r.samples += p.samples;
    }
    r.figures.push_back({"views", static_cast<double>(views.size())});
    r.summary = join_reasons(summaries);
    r.message = join_reasons(messages);
    return r;
}

/// A claimed view whose samples are off the table: says so when the grid of
/// inputs shows it is not monotone in the claimed direction.
void explain_claim(CheckResult& r, const MonotonicityProbe& p, const std::string& label) {
    if (p.monotone) return;
    r.message += fmt::format("; the view claims {} is {} in u, but on a grid of inputs {}", label,
                             p.increasing ? "increasing" : "decreasing", step_back_text(p, label));
}

class TabulatedCheck final : public Check {
public:
    std::string name() const override { return "tabulated"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"density_nan_values", "points where the density is NaN", FigureRule::Zero},
                 {"x_failures", "samples beyond the x tolerance", FigureRule::Zero},
                 {"pdf_failures", "pdfs beyond the pdf tolerance", FigureRule::Zero},
                 {"tail_failures", "tail samples beyond the table's reach", FigureRule::Zero},
                 {"nan_samples", "NaN samples", FigureRule::Zero},
                 {"nan_pdfs", "NaN pdfs", FigureRule::Zero},
                 {"mass_outside_reach", "mass outside the warp's reach", FigureRule::AtMost, "mass_outside_reach_tolerance"}}};
    }
    CheckLegend legend() const override {
        return {name(), "sample(u) and pdf against the inversion method on a 65536-bucket table of the density: each "
                "error over its tolerance.",
                ""};
    }
    std::string description() const override {
        return "sample(u) and pdf against the inversion method on a 65536-bucket table of the density "
               "(1D warps and monotone 1D marginals)";
    }
    Applicability applicability(const WarpCase& warp) const override {
        if (!would_apply(warp)) return Applicability::not_about_such_cases();
        if (warp.info().inversion == Inversion::NotInversion)
            return Applicability::lacks(
                "the case declares that sample is not the inversion method (chi2 and unbinned test its distribution)");
        return Applicability::runs();
    }

    /// One result per view, merged: a single view's result as it is; several
    /// views' results with each view's figures, plots and tables named by its
    /// label, the verdict failing if any view fails, and the messages prefixed
    /// with the view.
    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const std::vector<View> views = resolve(warp);
        if (views.empty()) throw std::runtime_error("the tabulated check does not apply to this case");
        if (warp.info().inversion == Inversion::NotInversion) {
            CheckResult r;
            r.verdict = Verdict::NotApplicable;
            r.summary = "not applicable: " + not_applicable_because(warp);
            return r;
        }
        if (views.size() == 1) return run_view(warp, views[0], ctx);
        std::vector<CheckResult> parts;
        for (const View& view : views) parts.push_back(run_view(warp, view, ctx));
        return merge_views(views, parts);
    }

private:
    static bool would_apply(const WarpCase& warp) {
        return !takes_bits(warp.input_kind()) && warp.has_pdf() && !warp.is_discrete() && !resolve(warp).empty();
    }

    /// The view's grid of inputs (tabulated_monotonicity.h), in the view's
    /// declared direction or, when measured, the direction its ends show.
    static MonotonicityProbe probe(const WarpCase& warp, const View& view, bool declared_direction) {
        const ViewFunctions f{warp, view};
        return probe_monotonicity(
            warp, view.m.input_coordinate, [&f](const WarpOutput& o) { return f.coordinate(o); },
            TabulatedReference::float_slack(view.m.lo, view.m.hi),
            declared_direction ? std::optional<bool>(view.m.increasing) : std::nullopt);
    }

    static CheckResult run_view(const WarpCase& warp, View view, const CheckContext& ctx) {
        validate_view(view, warp);
        std::optional<MonotonicityProbe> grid;
        if (view.measure_monotonicity) {
            grid = probe(warp, view, false);
            const double noise = TabulatedReference::float_slack(view.m.lo, view.m.hi);
            if (!grid->monotone) return not_monotone_result(*grid, view.m.label, noise);
            view.m.increasing = grid->increasing;
        }
        const MonotoneMarginal& m = view.m;
        const ViewFunctions f{warp, view};
        const TabulatedReference ref([&f](double x) { return f.density(x); }, m.lo, m.hi, body_mass(m));
        if (ref.nan_values() > 0) return nan_density_result(m, ref, grid);
        const Stats stats = compute(warp, ctx, Comparison{f, ref, body_mass(m)});

        CheckResult r;
        judge(r, stats, m, ref, ctx.options().strict);
        add_figures(r, stats, m, ref, ctx.options().strict);
        if (grid) add_monotonicity_figures(r, *grid, ref.x_slack());
        if (!grid && stats.x_failures > 0) explain_claim(r, probe(warp, view, true), m.label);
        r.plots = inverse_cdf_plots(f, ref);
        r.plots.push_back(density_plot(f, ref));
        r.tables.push_back(worst_points(stats, m, warp.input_kind()));
        for (Plot& plot : r.plots) plot.title += " (view " + m.label + ")";
        for (Table& t : r.tables) t.title += " (view " + m.label + ")";
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_tabulated_check() { return std::make_unique<TabulatedCheck>(); }

}  // namespace warpcheck

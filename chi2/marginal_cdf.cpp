#include "chi2/marginal_cdf.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>

namespace warpcheck::chi2 {

namespace {

/// Buckets per strip of the lookup index: a bucket then holds about one edge
/// where the strips are uniform, and a refined peak's strips are searched
/// within the bucket only.
constexpr std::size_t kBucketsPerStrip = 2;

}  // namespace

void MarginalCdf::index_strips() {
    bucket_strip_.clear();
    const std::size_t n = edges.size() < 2 ? 0 : edges.size() - 1;  // strips
    for (std::size_t j = 0; j < edges.size(); ++j)
        if (!std::isfinite(edges[j]) || (j > 0 && !(edges[j] >= edges[j - 1]))) return;
    if (n == 0 || n > (std::size_t{1} << 28) || !(edges.back() > edges.front())) return;
    const std::size_t buckets = kBucketsPerStrip * n;
    bucket_scale_ = static_cast<double>(buckets) / (edges.back() - edges.front());
    bucket_strip_.resize(buckets + 1);
    std::size_t j = 0;
    for (std::size_t b = 0; b <= buckets; ++b) {
        const double start = edges.front() + static_cast<double>(b) / bucket_scale_;
        while (j + 1 < n && edges[j + 1] <= start) ++j;
        bucket_strip_[b] = static_cast<uint32_t>(j);
    }
}

std::size_t MarginalCdf::strip_by_grid(double t) const {
    // The uniform grid's strips are uniform in the parameter up to float
    // rounding of their edges: guess the strip arithmetically, step to the
    // exact one, then search its refined strips (usually just itself).
    const std::size_t last = first_edge.size() - 2;
    const double guess = (t - edges.front()) / (edges.back() - edges.front()) * static_cast<double>(last + 1);
    std::size_t k = std::min(last, static_cast<std::size_t>(std::max(0.0, guess)));
    while (k > 0 && t < edges[first_edge[k]]) --k;
    while (k < last && t >= edges[first_edge[k + 1]]) ++k;
    const auto begin = edges.begin() + static_cast<std::ptrdiff_t>(first_edge[k]);
    const auto end = edges.begin() + static_cast<std::ptrdiff_t>(first_edge[k + 1]);
    return static_cast<std::size_t>(std::upper_bound(begin + 1, end, t) - edges.begin()) - 1;
}

MarginalCdf::AtBand MarginalCdf::at_band(double lo, double t, double hi) const {
    if (!(t > edges.front() && t < edges.back())) return {(*this)(lo), (*this)(t), (*this)(hi)};
    const std::size_t j = strip_of(t);
    return {lo >= edges[j] ? interpolate(j, lo) : (*this)(lo), interpolate(j, t),
            hi < edges[j + 1] ? interpolate(j, hi) : (*this)(hi)};
}

Binning strip_binning(const Domain& domain, int axis, int strips, const BinResolution& line) {
    BinResolution r = line;
    r.first = axis == 0 ? strips : 1;
    r.second = axis == 0 ? 1 : strips;
    const Binning b(domain, r);
    if (axis == 1 && b.parameter_dimension() != 2) throw std::invalid_argument("a 1D domain has one parameter");
    return b;
}

Binning pilot_strip_binning(const Domain& domain, int axis, int strips, std::span<const double> values,
                            const BinResolution& line) {
    const Binning uniform = strip_binning(domain, axis, strips, line);
    std::vector<double> v;
    for (double x : values)
        if (std::isfinite(x)) v.push_back(x);
    if (static_cast<int>(v.size()) < strips || strips < 8) return uniform;
    std::sort(v.begin(), v.end());
    const ParamRect b = uniform.parameter_bounds();
    const double lo = axis == 0 ? b.u0 : b.v0, hi = axis == 0 ? b.u1 : b.v1;
    std::vector<double> coarse;
    const int parts = strips / 4;
    for (int k = 1; k < parts; ++k) {
        coarse.push_back(lo + (hi - lo) * k / parts);
        const std::size_t i = v.size() * static_cast<std::size_t>(k) / static_cast<std::size_t>(parts);
        coarse.push_back(v[i - 1] + 0.5 * (v[i] - v[i - 1]));
    }
    // And cuts graded out from the pilot's range to the ends (a quarter of its
    // spread, doubling): the strips next to where the samples are stay on
    // their scale, so that mass the density has just beyond them (a cap the
    // pdf claims 2% larger than the sampler draws) lies within the
    // cubature's reach instead of between its nodes.
    const double spread = std::max(v.back() - v.front(), (hi - lo) * 0x1p-40);
    for (double step = 0.25 * spread, below = v.front() - step, above = v.back() + step;
         below > lo || above < hi; step *= 2.0, below -= step, above += step) {
        if (below > lo) coarse.push_back(below);
        if (above < hi) coarse.push_back(above);
    }
    std::sort(coarse.begin(), coarse.end());
    // An interval's cuts become floats (Binning rounds them up): siblings
    // must stay apart by a few float steps.
    const bool floats = domain.is<Interval>();
    const auto apart = [&](double a, double c) {
        const double step = floats ? 4.0 * 0x1p-23 * std::max(std::abs(a), std::abs(c)) : 0.0;
        return c - a > step;
    };
    std::vector<double> edges{lo};
    for (double c : coarse) {
        if (!(c > lo && c < hi)) continue;
        const double mid = edges.back() + 0.5 * (c - edges.back());
        if (!(apart(edges.back(), mid) && apart(mid, c))) continue;  // too close to the last cut to halve
        edges.push_back(mid);
        edges.push_back(c);
    }
    const double mid = edges.back() + 0.5 * (hi - edges.back());
    if (apart(edges.back(), mid) && apart(mid, hi)) edges.push_back(mid);
    else edges.pop_back();  // the last strip's sibling joins it
    edges.push_back(hi);
    if (edges.size() % 2 == 0 || edges.size() < 3) return uniform;  // an odd number of edges: an even number of strips
    CellEdges cells;
    if (axis == 0) {
        cells.rows = {uniform.parameter_dimension() == 1 ? 0.0 : b.v0, uniform.parameter_dimension() == 1 ? 1.0 : b.v1};
        cells.cols = {edges};
    } else {
        cells.rows = edges;
        cells.cols.assign(edges.size() - 1, {b.u0, b.u1});
    }
    return Binning(domain, uniform.resolution(), std::move(cells));
}

namespace {

struct Strip {
    double lo = 0.0, hi = 0.0;
    std::size_t coarse = 0;  ///< the uniform grid's strip it lies in
    double p = 0.0, err = 0.0;
};

struct Tally {
    uint64_t evaluations = 0, bad_values = 0;
    std::size_t unconverged = 0;
};

/// The strips' integrals: each strip as the rows between `rows` (the cross
/// parameter's bounds and the cuts), integrated apart and summed.
struct StripIntegrator {
    const Binning& binning;
    int axis;
    std::vector<double> rows;
    const BatchPdf& pdf;
    const QuadratureOptions& options;
    const ParallelFor& parallel_for;
    Tally tally;

    void operator()(std::span<Strip> strips) {
        const std::size_t per_strip = rows.size() - 1;
        std::vector<ParamRect> rects;
        rects.reserve(strips.size() * per_strip);
        for (const Strip& s : strips)
            for (std::size_t r = 0; r < per_strip; ++r)
                rects.push_back(axis == 0 ? ParamRect{s.lo, s.hi, rows[r], rows[r + 1]}
                                          : ParamRect{rows[r], rows[r + 1], s.lo, s.hi});
        const CellIntegrals in = integrate_rects(binning, rects, pdf, options, parallel_for);
        for (std::size_t s = 0; s < strips.size(); ++s) {
            strips[s].p = strips[s].err = 0.0;
            for (std::size_t r = 0; r < per_strip; ++r) {
                strips[s].p += in.probability[s * per_strip + r];
                strips[s].err += in.error[s * per_strip + r];
            }
        }
        tally.evaluations += in.evaluations;
        tally.bad_values += in.negative_values + in.nonfinite_values;
        tally.unconverged += in.unconverged_cells;
    }
};

double total_of(const std::vector<Strip>& strips) {
    double sum = 0.0;
    for (const Strip& s : strips) sum += s.p;
    return sum;
}

/// Linear interpolation on strips of width h errs by ~h^2 |F''| / 8; on the
/// pair of sibling strips k, k + 1 (width 2h) the error at their shared edge is
/// measured exactly, |F(mid) - (F(a) + F(b)) / 2| = |p_k - p_k+1| / 2, and a
/// quarter of it estimates the error on the strips used (the h^2 law). Where
/// F'' changes within the pair (the flank of a peak) that falls a few percent
/// short (tests/chi2/test_marginal_cdf.cpp), so half of it is stated. Where F
/// is linear within the pair (a piecewise-constant density with edges on the
/// strips' edges) it is 0, as the true error is.
double pair_error(const std::vector<Strip>& strips, std::size_t k, double total) {
    return std::abs(strips[k].p - strips[k + 1].p) / 4.0 / total;
}

/// Splits the pairs whose error exceeds the target, worst first within the
/// budget, until none does (or the budget or the float resolution stops it).
void refine(std::vector<Strip>& strips, StripIntegrator& integrate, const CdfRefinement& r) {
    while (r.interpolation_target > 0.0) {
        const double total = total_of(strips);
        if (!(std::isfinite(total) && total > 0.0)) return;
        std::vector<std::pair<double, std::size_t>> over;
        for (std::size_t k = 0; k + 1 < strips.size(); k += 2) {
            const double e = pair_error(strips, k, total);
            const double mid_lo = 0.5 * (strips[k].lo + strips[k].hi);
            if (e > r.interpolation_target && mid_lo > strips[k].lo && mid_lo < strips[k].hi) over.push_back({e, k});
        }
        const std::size_t budget = r.max_strips > strips.size() ? (r.max_strips - strips.size()) / 2 : 0;
        if (over.empty() || budget == 0) return;
        std::sort(over.begin(), over.end(), [](const auto& a, const auto& b) {
            return a.first != b.first ? a.first > b.first : a.second < b.second;
        });
        over.resize(std::min(over.size(), budget));
        std::vector<char> split(strips.size(), 0);
        for (const auto& o : over) split[o.second] = split[o.second + 1] = 1;
        std::vector<Strip> halves;
        for (std::size_t k = 0; k < strips.size(); ++k) {
            if (!split[k]) continue;
            const double mid = 0.5 * (strips[k].lo + strips[k].hi);
            halves.push_back({strips[k].lo, mid, strips[k].coarse});
            halves.push_back({mid, strips[k].hi, strips[k].coarse});
        }
        integrate(halves);
        std::vector<Strip> next;
        next.reserve(strips.size() + halves.size() / 2);
        for (std::size_t k = 0, h = 0; k < strips.size(); ++k) {
            if (!split[k]) next.push_back(strips[k]);
            else {
                next.push_back(halves[h++]);
                next.push_back(halves[h++]);
            }
        }
        strips = std::move(next);
    }
}

/// Every kProbeStride-th strip is probed inside (probe_interpolation).
constexpr std::size_t kProbeStride = 16;
/// Where in its strip a probe looks, in turn: 0.2, 1 / phi^2, 1 / 2, 1 / phi,
/// 0.8 (phi the golden ratio): structure with 2 to 8 periods per strip puts
/// its largest error near one of them.
constexpr double kProbeFractions[] = {0.2, 0.3819660112501051, 0.5, 0.6180339887498949, 0.8};

/// The largest interpolation error seen inside the probed strips: each probe
/// integrates its strip from the start to a fraction f of it, and the linear
/// interpolation's error there is |that - f p| exactly, less the two
/// integrals' own error estimates (the probe measures interpolation, not
/// quadrature). Sees what the pair estimate cannot: structure within a strip
/// that leaves neighbouring strips equal (a density alternating at twice the
/// strips' frequency: 0 stated, 4.4e-4 true; tests/chi2/test_marginal_cdf.cpp).
double probe_interpolation(const std::vector<Strip>& strips, StripIntegrator& integrate, double total) {
    std::vector<Strip> probes;
    std::vector<std::size_t> probed;
    std::vector<double> fractions;
    for (std::size_t k = kProbeStride / 2; k < strips.size(); k += kProbeStride) {
        const double f = kProbeFractions[(k / kProbeStride) % std::size(kProbeFractions)];
        const double cut = strips[k].lo + f * (strips[k].hi - strips[k].lo);
        if (!(cut > strips[k].lo && cut < strips[k].hi)) continue;
        probes.push_back({strips[k].lo, cut, strips[k].coarse});
        probed.push_back(k);
        fractions.push_back(f);
    }
    if (probes.empty() || !(std::isfinite(total) && total > 0.0)) return 0.0;
    integrate(probes);
    double worst = 0.0;
    for (std::size_t i = 0; i < probes.size(); ++i) {
        const Strip& s = strips[probed[i]];
        const double seen = std::abs(probes[i].p - fractions[i] * s.p) - (probes[i].err + fractions[i] * s.err);
        worst = std::max(worst, seen / total);
    }
    return worst;
}

/// The rows of every strip: the cross parameter's range cut at the cuts inside it.
std::vector<double> row_edges(const Binning& b, int axis, const std::vector<double>& cuts) {
    const ParamRect whole = b.cell_rect(0);
    const double lo = axis == 0 ? whole.v0 : whole.u0, hi = axis == 0 ? whole.v1 : whole.u1;
    std::vector<double> rows = {lo};
    for (double c : cuts)
        if (c > rows.back() && c < hi) rows.push_back(c);
    rows.push_back(hi);
    return rows;
}

MarginalCdf assemble(const std::vector<Strip>& strips, std::size_t coarse_count, int axis) {
    MarginalCdf m;
    m.axis = axis;
    m.total = total_of(strips);
    const std::size_t n = strips.size();
    m.edges.resize(n + 1);
    m.cdf.resize(n + 1);
    m.first_edge.assign(coarse_count + 1, n);
    double sum = 0.0, err = 0.0;
    for (std::size_t k = n; k-- > 0;) m.first_edge[strips[k].coarse] = k;
    for (std::size_t k = 0; k < n; ++k) {
        m.edges[k] = strips[k].lo;
        m.cdf[k] = sum / m.total;
        sum += strips[k].p;
        err += strips[k].err;
    }
    m.edges[n] = strips.back().hi;
    m.cdf[n] = 1.0;
    m.quadrature_error = err / m.total;
    for (std::size_t k = 0; k + 1 < n; k += 2)
        m.interpolation_error = std::max(m.interpolation_error, pair_error(strips, k, m.total));
    if (!std::isfinite(m.total) || !(m.total > 0.0)) m.interpolation_error = std::nan("");
    m.refined_strips = n - coarse_count;
    m.index_strips();
    return m;
}

}  // namespace

MarginalCdf tabulate_marginal_cdf(const Binning& strips, int axis, const BatchPdf& pdf,
                                  const QuadratureOptions& options, const ParallelFor& parallel_for,
                                  const CdfRefinement& refinement) {
    const std::size_t n = strips.cell_count();
    if (n < 2 || n % 2 != 0) throw std::invalid_argument("tabulate_marginal_cdf: an even number of strips is needed");
    const ParallelFor& run = parallel_for ? parallel_for : ParallelFor(serial_for);
    StripIntegrator integrate{strips, axis, row_edges(strips, axis, refinement.cross_cuts), pdf, options, run, {}};
    std::vector<Strip> s(n);
    for (std::size_t c = 0; c < n; ++c) {
        const ParamRect r = strips.cell_rect(c);
        s[c] = {axis == 0 ? r.u0 : r.v0, axis == 0 ? r.u1 : r.v1, c};
    }
    integrate(s);
    refine(s, integrate, refinement);
    const double probed = probe_interpolation(s, integrate, total_of(s));
    MarginalCdf m = assemble(s, n, axis);
    m.probed_interpolation_error = probed;
    m.interpolation_error = std::max(m.interpolation_error, kProbeMargin * probed);
    m.evaluations = integrate.tally.evaluations;
    m.bad_values = integrate.tally.bad_values;
    m.unconverged_strips = integrate.tally.unconverged;
    return m;
}

std::vector<double> quantile_cuts(const MarginalCdf& cdf, int parts) {
    std::vector<double> tails, levels;
    for (double tail = 1e-6; tail < 0.5 / parts; tail *= 10.0) tails.push_back(tail);
    levels.insert(levels.end(), tails.begin(), tails.end());
    for (int k = 1; k < parts; ++k) levels.push_back(static_cast<double>(k) / parts);
    for (auto t = tails.rbegin(); t != tails.rend(); ++t) levels.push_back(1.0 - *t);
    std::vector<double> cuts;
    for (double q : levels) {
        const auto it = std::upper_bound(cdf.cdf.begin(), cdf.cdf.end(), q);
        if (it == cdf.cdf.begin() || it == cdf.cdf.end()) continue;
        const std::size_t j = static_cast<std::size_t>(it - cdf.cdf.begin()) - 1;
        const double w = (q - cdf.cdf[j]) / (cdf.cdf[j + 1] - cdf.cdf[j]);
        const double t = cdf.edges[j] + w * (cdf.edges[j + 1] - cdf.edges[j]);
        if (std::isfinite(t) && (cuts.empty() || t > cuts.back())) cuts.push_back(t);
    }
    return cuts;
}

}  // namespace warpcheck::chi2

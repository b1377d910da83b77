#include "chi2/equal_probability.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

namespace warpcheck::chi2 {
namespace {

/// A row or column must span at least this many times sqrt(E) float steps
/// (E: its cells' expected count), as float_aware_resolution asks of uniform
/// cells: the bands of kEdgeFloatSteps float steps at its two edges then hold
/// at most 2 1.5 / 3 = 1 sqrt(E) of its cells' counts all told.
constexpr double kFloatStepsPerDeviation = 3.0;

/// Edges between `parts` parts of sorted `x` of about equal count, strictly
/// inside (lo, hi): each the midpoint of the two order statistics on either
/// side of k / parts. Ties, and edges at or beyond the ends, are left out
/// (fewer parts).
std::vector<double> quantile_edges(std::span<const double> x, int parts, double lo, double hi) {
    std::vector<double> e{lo};
    const std::size_t n = x.size();
    for (int k = 1; k < parts; ++k) {
        const auto i = static_cast<std::size_t>(std::llround(static_cast<double>(k) * static_cast<double>(n) / parts));
        if (i == 0 || i >= n) continue;
        const double edge = x[i - 1] + 0.5 * (x[i] - x[i - 1]);
        if (edge > e.back() && edge < hi) e.push_back(edge);
    }
    e.push_back(hi);
    return e;
}

/// An interval's interior edges rounded up to floats, as Binning rounds
/// them (a float x >= e exactly when x >= e rounded up), ties merged: the
/// integration pieces then tile the cells Binning makes.
void round_up_to_floats(std::vector<double>& e) {
    for (std::size_t j = 1; j + 1 < e.size(); ++j) {
        float f = static_cast<float>(e[j]);
        if (static_cast<double>(f) < e[j]) f = std::nextafter(f, INFINITY);
        e[j] = static_cast<double>(f);
    }
    std::vector<double> kept{e.front()};
    for (std::size_t j = 1; j + 1 < e.size(); ++j)
        if (e[j] > kept.back() && e[j] < e.back()) kept.push_back(e[j]);
    kept.push_back(e.back());
    e = std::move(kept);
}

/// How many of sorted `x` lie in [e[j], e[j + 1]) for each part j (the last
/// part closed at its top).
std::vector<std::size_t> counts_between(std::span<const double> x, const std::vector<double>& e) {
    std::vector<std::size_t> n(e.size() - 1, 0);
    for (double t : x) {
        const auto it = std::upper_bound(e.begin() + 1, e.end() - 1, t);
        ++n[static_cast<std::size_t>(it - (e.begin() + 1))];
    }
    return n;
}

/// Merges neighbouring parts of `e` (whose pilot counts are `count` of
/// `used`) until each spans kFloatStepsPerDeviation sqrt(E) float steps,
/// E = samples * (its share of the pilot) / cells_per_part, the resolution at
/// its middle given by `resolution`. A last part that falls short joins the
/// one before it. Returns how many parts were merged away.
template <class Resolution>
std::size_t merge_narrow(std::vector<double>& e, const std::vector<std::size_t>& count, std::size_t used,
                         uint64_t samples, double cells_per_part, const Resolution& resolution) {
    std::vector<double> merged{e.front()};
    std::size_t open = 0;  // pilot points in the part being gathered
    const auto wide_enough = [&](double lo, double hi, std::size_t points) {
        const double expected = static_cast<double>(samples) * static_cast<double>(points) /
                                static_cast<double>(used) / cells_per_part;
        const double step = resolution(0.5 * (lo + hi));
        return !(step > 0.0) || hi - lo >= kFloatStepsPerDeviation * std::sqrt(expected) * step;
    };
    for (std::size_t j = 0; j + 1 < e.size(); ++j) {
        open += count[j];
        if (j + 2 == e.size()) break;  // the last part closes at the end below
        if (wide_enough(merged.back(), e[j + 1], open)) {
            merged.push_back(e[j + 1]);
            open = 0;
        }
    }
    // The last part: from the last closed edge to the end; if it is too
    // narrow, it joins the part before it.
    if (merged.size() > 1 && !wide_enough(merged.back(), e.back(), open)) merged.pop_back();
    merged.push_back(e.back());
    const std::size_t dropped = e.size() - merged.size();
    e = std::move(merged);
    return dropped;
}

/// Pilot points as parameters: (u, v), u NaN at a pole (no azimuth).
struct PilotParameters {
    std::vector<std::array<double, 2>> uv;  ///< sorted by v
};

PilotParameters parameters(const Binning& grid, std::span<const SamplePoint> pilot) {
    PilotParameters out;
    const Domain& d = grid.domain();
    const int n = d.point_dimension();
    for (const SamplePoint& s : pilot) {
        const DomainPoint p{s[0], n > 1 ? s[1] : 0.0, n > 2 ? s[2] : 0.0};
        if (std::isnan(p[0]) || std::isnan(p[1]) || std::isnan(p[2]) || !d.contains(p)) continue;
        std::array<double, 2> uv = grid.parameters_of(p);
        if (d.azimuthal() && p[0] == 0.0 && p[1] == 0.0) uv[0] = std::nan("");
        if (grid.parameter_dimension() == 1) uv[1] = 0.5;
        if (!std::isfinite(uv[1]) || std::isinf(uv[0])) continue;
        out.uv.push_back(uv);
    }
    std::sort(out.uv.begin(), out.uv.end(), [](const auto& a, const auto& b) { return a[1] < b[1]; });
    return out;
}

/// The column edges of one row from its pilot points' u (sorted), `cols`
/// parts; uniform where the points are too few or tie.
std::vector<double> row_columns(std::vector<double> u, int cols, const ParamRect& bounds) {
    std::vector<double> e;
    if (u.size() >= 2 * static_cast<std::size_t>(cols)) {
        std::sort(u.begin(), u.end());
        e = quantile_edges(u, cols, bounds.u0, bounds.u1);
    }
    if (static_cast<int>(e.size()) != cols + 1) {
        e.assign(static_cast<std::size_t>(cols) + 1, 0.0);
        for (int k = 0; k <= cols; ++k)
            e[static_cast<std::size_t>(k)] = k == cols ? bounds.u1 : bounds.u0 + (bounds.u1 - bounds.u0) * k / cols;
    }
    return e;
}

/// Cuts of [a, b] graded from the span [s0, s1] out to its ends: the span
/// widened by a quarter of its width each way, then pieces that double in
/// width away from it (growing faster where more than kMaxGradedPieces would
/// be needed), so that a density falling off from the span meets pieces on
/// its own scale. No cut when the interval is within 8 times the span.
std::vector<double> graded_cuts(double a, double b, double s0, double s1) {
    constexpr int kMaxGradedPieces = 16;
    const double w = std::max(s1 - s0, (b - a) * 0x1p-40);
    if (!(b - a > 8.0 * w) || !(s0 >= a) || !(s1 <= b)) return {a, b};
    const double lo = std::max(a, s0 - 0.25 * w), hi = std::min(b, s1 + 0.25 * w);
    const auto side = [&](double from, double to) {  // cuts from `from` towards `to`, both excluded
        std::vector<double> cuts;
        const double length = std::abs(to - from);
        if (!(length > w)) return cuts;
        const double factor =
            std::log2(length / w) > kMaxGradedPieces ? std::pow(length / w, 1.0 / kMaxGradedPieces) : 2.0;
        const double direction = to > from ? 1.0 : -1.0;
        for (double step = w, at = from + direction * w; direction * (to - at) > 0.0;
             step *= factor, at += direction * step)
            cuts.push_back(at);
        return cuts;
    };
    const std::vector<double> below = side(lo, a), above = side(hi, b);
    std::vector<double> cuts{a};
    for (auto it = below.rbegin(); it != below.rend(); ++it) cuts.push_back(*it);
    cuts.push_back(lo);
    cuts.push_back(hi);
    cuts.insert(cuts.end(), above.begin(), above.end());
    cuts.push_back(b);
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    return cuts;
}

/// The integration pieces of cell r from the pilot points in it: where the
/// points leave a gap of more than half the cell's extent along an axis (a
/// cell whose mass lies at both of its ends, across the azimuth's cut or a
/// lobe's two flanks), the cell is cut in the gap's middle and each part
/// treated alone (three levels at most); then each part is cut into pieces
/// graded from its points' span (graded_cuts). A pole's point, without an
/// azimuth, spans the whole u range. No points: the part whole.
void cut_pieces(const ParamRect& r, std::vector<std::array<double, 2>> points, bool two_d, int depth,
                std::vector<ParamRect>& out) {
    if (points.empty()) {
        out.push_back(r);
        return;
    }
    for (int axis = 0; axis < (two_d ? 2 : 1) && depth < 3; ++axis) {
        std::vector<double> c;
        for (const auto& p : points)
            if (!std::isnan(p[static_cast<std::size_t>(axis)])) c.push_back(p[static_cast<std::size_t>(axis)]);
        if (c.size() < 2 || c.size() < points.size()) continue;  // a pole spans the u range: no gap
        std::sort(c.begin(), c.end());
        double gap = 0.0, middle = 0.0;
        for (std::size_t i = 1; i < c.size(); ++i)
            if (c[i] - c[i - 1] > gap) gap = c[i] - c[i - 1], middle = c[i - 1] + 0.5 * (c[i] - c[i - 1]);
        const double extent = axis == 0 ? r.u1 - r.u0 : r.v1 - r.v0;
        if (!(gap > 0.5 * extent)) continue;
        ParamRect lo = r, hi = r;
        (axis == 0 ? lo.u1 : lo.v1) = middle;
        (axis == 0 ? hi.u0 : hi.v0) = middle;
        std::vector<std::array<double, 2>> below, above;
        for (const auto& p : points) (p[static_cast<std::size_t>(axis)] < middle ? below : above).push_back(p);
        cut_pieces(lo, std::move(below), two_d, depth + 1, out);
        cut_pieces(hi, std::move(above), two_d, depth + 1, out);
        return;
    }
    double u0 = INFINITY, u1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;
    for (const auto& p : points) {
        if (std::isnan(p[0])) u0 = r.u0, u1 = r.u1;
        else u0 = std::min(u0, p[0]), u1 = std::max(u1, p[0]);
        v0 = std::min(v0, p[1]), v1 = std::max(v1, p[1]);
    }
    const std::vector<double> us = graded_cuts(r.u0, r.u1, std::max(u0, r.u0), std::min(u1, r.u1));
    const std::vector<double> vs =
        two_d ? graded_cuts(r.v0, r.v1, std::max(v0, r.v0), std::min(v1, r.v1)) : std::vector<double>{r.v0, r.v1};
    for (std::size_t j = 0; j + 1 < vs.size(); ++j)
        for (std::size_t i = 0; i + 1 < us.size(); ++i) out.push_back({us[i], us[i + 1], vs[j], vs[j + 1]});
}

/// Every cell's integration pieces (CellEdges::pieces), from the pilot points in it.
std::vector<std::vector<ParamRect>> integration_pieces(const CellEdges& e, const PilotParameters& pp, bool two_d) {
    const std::size_t rows = e.rows.size() - 1, cols = e.cols.front().size() - 1;
    std::vector<std::vector<std::array<double, 2>>> in(rows * cols);
    for (const auto& p : pp.uv) {
        const std::size_t j = !two_d ? 0
                                     : static_cast<std::size_t>(std::upper_bound(e.rows.begin() + 1, e.rows.end() - 1,
                                                                                 p[1]) -
                                                                (e.rows.begin() + 1));
        const std::vector<double>& c = e.cols[j];
        // A pole's point (no azimuth) belongs to every column of its row.
        if (std::isnan(p[0])) {
            for (std::size_t k = 0; k < cols; ++k) in[j * cols + k].push_back(p);
            continue;
        }
        const auto k = static_cast<std::size_t>(std::upper_bound(c.begin() + 1, c.end() - 1, p[0]) - (c.begin() + 1));
        in[j * cols + k].push_back(p);
    }
    std::vector<std::vector<ParamRect>> pieces(rows * cols);
    for (std::size_t j = 0; j < rows; ++j)
        for (std::size_t k = 0; k < cols; ++k) {
            const ParamRect r{e.cols[j][k], e.cols[j][k + 1], e.rows[j], e.rows[j + 1]};
            std::vector<ParamRect> p;
            cut_pieces(r, std::move(in[j * cols + k]), two_d, 0, p);
            if (p.size() > 1) pieces[j * cols + k] = std::move(p);
        }
    return pieces;
}

}  // namespace

double effective_cells(const Binning& grid, std::span<const SamplePoint> pilot) {
    Histogram h;
    h.counts.assign(grid.cell_count(), 0);
    grid.bin(pilot, h);
    grid.spread_poles(h);
    double total = 0.0, squares = 0.0;
    for (uint64_t c : h.counts) total += static_cast<double>(c);
    for (uint64_t c : h.counts) squares += static_cast<double>(c) * static_cast<double>(c);
    return squares > 0.0 ? total * total / squares : 0.0;
}

EqualProbabilityCells equal_probability_cells(const Binning& grid, std::span<const SamplePoint> pilot,
                                              uint64_t samples) {
    EqualProbabilityCells out;
    const PilotParameters pp = parameters(grid, pilot);
    out.pilot_used = pp.uv.size();
    if (out.pilot_used < 2 * grid.cell_count()) return out;
    const ParamRect bounds = grid.parameter_bounds();
    const std::size_t used = out.pilot_used;

    if (grid.parameter_dimension() == 1) {
        std::vector<double> u;
        for (const auto& p : pp.uv) u.push_back(p[0]);
        std::sort(u.begin(), u.end());
        std::vector<double> e = quantile_edges(u, grid.cols(), bounds.u0, bounds.u1);
        if (grid.domain().is<Interval>()) round_up_to_floats(e);
        out.rows_merged = static_cast<std::size_t>(grid.cols()) + 1 - e.size();
        out.rows_merged += merge_narrow(e, counts_between(u, e), used, samples, 1.0,
                                        [&](double t) { return grid.float_resolution(0, t, 0.5); });
        if (e.size() < 3) return {};
        out.edges.rows = {0.0, 1.0};
        out.edges.cols = {std::move(e)};
        out.edges.pieces = integration_pieces(out.edges, pp, false);
        return out;
    }

    // Rows at the quantiles of v.
    std::vector<double> v(used);
    for (std::size_t i = 0; i < used; ++i) v[i] = pp.uv[i][1];
    std::vector<double> rows = quantile_edges(v, grid.rows(), bounds.v0, bounds.v1);
    out.rows_merged = static_cast<std::size_t>(grid.rows()) + 1 - rows.size();
    const double u_mid = 0.5 * (bounds.u0 + bounds.u1);
    out.rows_merged += merge_narrow(rows, counts_between(v, rows), used, samples, grid.cols(),
                                    [&](double t) { return grid.float_resolution(1, u_mid, t); });
    if (rows.size() < 2) return {};

    // Each row's pilot u values (the pole's, without an azimuth, left out).
    std::vector<std::vector<double>> row_u(rows.size() - 1);
    std::vector<std::size_t> row_points(rows.size() - 1, 0);
    for (const auto& p : pp.uv) {
        const auto it = std::upper_bound(rows.begin() + 1, rows.end() - 1, p[1]);
        const auto j = static_cast<std::size_t>(it - (rows.begin() + 1));
        ++row_points[j];
        if (!std::isnan(p[0])) row_u[j].push_back(p[0]);
    }
    // Columns at the quantiles of u in each row, halved in number while any
    // is narrower than its float resolution allows.
    const int floor = grid.domain().azimuthal() ? 8 : 1;
    for (int cols = grid.cols();; cols /= 2) {
        std::vector<std::vector<double>> all;
        bool narrow = false;
        for (std::size_t j = 0; j + 1 < rows.size(); ++j) {
            std::vector<double> e = row_columns(row_u[j], cols, bounds);
            const double v_mid = 0.5 * (rows[j] + rows[j + 1]);
            const double expected = static_cast<double>(samples) * static_cast<double>(row_points[j]) /
                                    static_cast<double>(used) / cols;
            for (std::size_t k = 0; k + 1 < e.size() && !narrow; ++k) {
                const double step = grid.float_resolution(0, 0.5 * (e[k] + e[k + 1]), v_mid);
                narrow = step > 0.0 && e[k + 1] - e[k] < kFloatStepsPerDeviation * std::sqrt(expected) * step;
            }
            all.push_back(std::move(e));
        }
        if (!narrow || cols / 2 < floor) {
            out.edges.rows = std::move(rows);
            out.edges.cols = std::move(all);
            break;
        }
        ++out.column_halvings;
    }
    if (out.edges.cols.front().size() * (out.edges.rows.size() - 1) < 2) return {};
    out.edges.pieces = integration_pieces(out.edges, pp, true);
    return out;
}

}  // namespace warpcheck::chi2

#include "chi2/binning.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <type_traits>
#include <variant>

namespace warpcheck::chi2 {

namespace {

int clamp_index(double f, int n) {
    // f may be slightly negative or reach n for points within the tolerance.
    if (!(f >= 0.0)) return 0;
    const auto i = static_cast<long long>(f);
    return i >= n ? n - 1 : static_cast<int>(i);
}

}  // namespace

double fast_phi(double x, double y) {
    const double ax = std::abs(x), ay = std::abs(y);
    const double hi = std::max(ax, ay), lo = std::min(ax, ay);
    if (hi == 0.0) return 0.0;
    const double t = lo / hi, t2 = t * t;
    // Abramowitz & Stegun 4.4.49: atan t = t (1 + a2 t^2 + ... + a16 t^16), |error| <= 2e-8 on [0, 1].
    double p = 0.0028662257;
    p = p * t2 - 0.0161657367;
    p = p * t2 + 0.0429096138;
    p = p * t2 - 0.0752896400;
    p = p * t2 + 0.1065626393;
    p = p * t2 - 0.1420889944;
    p = p * t2 + 0.1999355085;
    p = p * t2 - 0.3333314528;
    p = p * t2 + 1.0;
    double a = t * p;
    if (ay > ax) a = 0.5 * std::numbers::pi - a;
    if (x < 0.0) a = std::numbers::pi - a;
    if (y < 0.0) a = kTwoPi - a;
    return a;
}

uint64_t Histogram::total() const {
    uint64_t n = outside + nan + on_boundary;
    for (uint64_t c : poles) n += c;
    for (uint64_t c : counts) n += c;
    return n;
}

namespace {

/// Keeps, per cell, the points of `points` plus `more` that are extreme in a
/// coordinate (the smallest and the largest x, y and z, ties broken by the
/// whole point): they span the support the samples found in the cell, and
/// which they are does not depend on the order of binning.
void keep_extreme_points(std::vector<Histogram::CellPoint>& points, std::span<const Histogram::CellPoint> more) {
    points.insert(points.end(), more.begin(), more.end());
    std::sort(points.begin(), points.end());
    points.erase(std::unique(points.begin(), points.end()), points.end());
    std::vector<Histogram::CellPoint> kept;
    for (std::size_t begin = 0; begin < points.size();) {
        std::size_t end = begin;
        while (end < points.size() && points[end].cell == points[begin].cell) ++end;
        std::vector<std::size_t> pick;
        for (std::size_t k = 0; k < 3; ++k) {
            std::size_t lo = begin, hi = begin;
            for (std::size_t i = begin; i < end; ++i) {
                if (points[i].point[k] < points[lo].point[k]) lo = i;
                if (points[i].point[k] > points[hi].point[k]) hi = i;
            }
            pick.push_back(lo);
            pick.push_back(hi);
        }
        std::sort(pick.begin(), pick.end());
        pick.erase(std::unique(pick.begin(), pick.end()), pick.end());
        for (std::size_t i : pick) kept.push_back(points[i]);
        begin = end;
    }
    points = std::move(kept);
}

}  // namespace

void Histogram::merge(const Histogram& other) {
    if (counts.size() != other.counts.size()) throw std::invalid_argument("Histogram::merge: different binnings");
    for (std::size_t i = 0; i < counts.size(); ++i) counts[i] += other.counts[i];
    outside += other.outside;
    nan += other.nan;
    snapped += other.snapped;
    on_boundary += other.on_boundary;
    if (!other.zero_cell_points.empty()) keep_extreme_points(zero_cell_points, other.zero_cell_points);
    if (poles.size() < other.poles.size()) poles.resize(other.poles.size(), 0);
    for (std::size_t r = 0; r < other.poles.size(); ++r) poles[r] += other.poles[r];
}

void Histogram::spread_poles(int cols, std::span<const double> shares) {
    const auto n_cols = static_cast<std::size_t>(cols);
    if (shares.size() < poles.size() * n_cols) throw std::invalid_argument("Histogram::spread_poles: too few shares");
    for (std::size_t r = 0; r < poles.size(); ++r) {
        if (poles[r] == 0) continue;
        const std::span<const double> w = shares.subspan(r * n_cols, n_cols);
        double sum = 0.0;
        for (double x : w) sum += std::max(x, 0.0);
        if (!(sum > 0.0)) throw std::invalid_argument("Histogram::spread_poles: shares must be positive");
        // Largest remainders: each column its whole share, then the rest one
        // at a time to the largest fractions.
        std::vector<std::pair<double, std::size_t>> fraction;
        uint64_t dealt = 0;
        for (std::size_t c = 0; c < n_cols; ++c) {
            const double exact = static_cast<double>(poles[r]) * std::max(w[c], 0.0) / sum;
            const auto whole = static_cast<uint64_t>(std::floor(exact));
            counts[r * n_cols + c] += whole;
            dealt += whole;
            fraction.emplace_back(-(exact - static_cast<double>(whole)), c);
        }
        std::sort(fraction.begin(), fraction.end());
        for (std::size_t k = 0; dealt < poles[r]; ++k, ++dealt) ++counts[r * n_cols + fraction[k % n_cols].second];
    }
    poles.clear();
}

void Histogram::spread_poles(int cols) {
    const auto n_cols = static_cast<uint64_t>(cols);
    for (std::size_t r = 0; r < poles.size(); ++r)
        for (uint64_t c = 0; c < n_cols; ++c)
            counts[r * n_cols + c] += poles[r] / n_cols + (c < poles[r] % n_cols ? 1 : 0);
    poles.clear();
}

double Binning::float_resolution(int axis, double u, double v) const {
    const DomainPoint p = point_at(u, v);
    const DomainPoint f{static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])};
    const double at = parameters_of(f)[static_cast<std::size_t>(axis)];
    double step = 0.0;
    for (int c = 0; c < domain_.point_dimension(); ++c) {
        for (const float toward : {INFINITY, -INFINITY}) {
            DomainPoint n = f;
            n[static_cast<std::size_t>(c)] = std::nextafter(static_cast<float>(f[static_cast<std::size_t>(c)]), toward);
            double d = std::abs(parameters_of(n)[static_cast<std::size_t>(axis)] - at);
            if (domain_.azimuthal() && axis == 0) d = std::min(d, kTwoPi - d);  // phi wraps
            if (std::isfinite(d)) step = std::max(step, d);
        }
    }
    return step;
}

double Binning::reading_resolution(int axis, double u, double v) const {
    double r = float_resolution(axis, u, v);
    if (axis == 1 && domain_.is<SphericalCap>()) {
        const auto z = static_cast<float>(ring(v)[1]);
        r = std::max({r, static_cast<double>(std::nextafter(z, INFINITY)) - z,
                      z - static_cast<double>(std::nextafter(z, -INFINITY))});
    }
    return r;
}

Binning::Binning(const Domain& domain, BinResolution resolution) : domain_(domain), resolution_(resolution) {
    if (resolution_.first < 0 || resolution_.second < 0) throw std::invalid_argument("bin resolution must be >= 0");
    if (resolution_.half_line_scale == 0.0) resolution_.half_line_scale = 1.0;
    if (!(resolution_.half_line_scale > 0.0) || !std::isfinite(resolution_.half_line_scale))
        throw std::invalid_argument("half-line scale must be positive and finite");
    if (!std::isfinite(resolution_.line_center)) throw std::invalid_argument("line centre must be finite");
    const BinResolution defaults = std::visit([](const auto& k) { return k.default_resolution(); }, domain_.shape());
    auto pick = [](int requested, int fallback) { return requested > 0 ? requested : fallback; };
    dims_ = domain_.point_dimension() == 1 ? 1 : 2;
    cols_ = pick(resolution_.first, defaults.first);
    rows_ = dims_ == 1 ? 1 : pick(resolution_.second, defaults.second);
    bounds_ = std::visit([](const auto& k) { return k.parameter_bounds(); }, domain_.shape());
    const Domain::Slack slack = domain_.slack();  // the one membership tolerance
    tol_x_ = slack.x;
    tol_y_ = slack.y;
    if (dims_ == 1 && resolution_.second > 1) throw std::invalid_argument("1D domains take one resolution value");
    if (cell_count() > (std::size_t{1} << 26)) throw std::invalid_argument("bin resolution too large");
    du_ = (bounds_.u1 - bounds_.u0) / cols_;
    if (domain_.is<Interval>()) build_interval_edges();
    dv_ = (bounds_.v1 - bounds_.v0) / rows_;
    if (domain_.azimuthal() && cols_ % 8 == 0) build_phi_table();
}

Binning::Binning(const Domain& domain, BinResolution resolution, CellEdges edges) : Binning(domain, resolution) {
    edges_ = std::move(edges);
    check_edges();
    rows_ = static_cast<int>(edges_.rows.size()) - 1;
    cols_ = static_cast<int>(edges_.cols.front().size()) - 1;
    resolution_.first = cols_;
    resolution_.second = dims_ == 1 ? 0 : rows_;
    du_ = (bounds_.u1 - bounds_.u0) / cols_;
    dv_ = (bounds_.v1 - bounds_.v0) / rows_;
    if (domain_.is<Interval>()) {
        // As the uniform cells' (interval_edges_): a float x >= e exactly when
        // x >= e rounded up to a float, so the cells hold the same samples and
        // are integrated over the span those samples cover.
        std::vector<double>& e = edges_.cols.front();
        for (std::size_t j = 1; j + 1 < e.size(); ++j) {
            float f = static_cast<float>(e[j]);
            if (static_cast<double>(f) < e[j]) f = std::nextafter(f, std::numeric_limits<float>::infinity());
            e[j] = static_cast<double>(f);
        }
        check_edges();
    }
    interval_edges_.clear();
    octant_cols_ = 0;
    // Sixteen buckets per part: most hold no edge.
    row_lookup_.build(edges_.rows, 16);
    column_lookup_.resize(edges_.cols.size());
    for (std::size_t r = 0; r < edges_.cols.size(); ++r) column_lookup_[r].build(edges_.cols[r], 16);
}

void Binning::check_edges() {
    const auto ascending = [](const std::vector<double>& e, double lo, double hi) {
        if (e.size() < 2 || e.front() != lo || e.back() != hi) return false;
        for (std::size_t i = 0; i + 1 < e.size(); ++i)
            if (!(e[i] < e[i + 1])) return false;
        return true;
    };
    const double v0 = dims_ == 1 ? 0.0 : bounds_.v0, v1 = dims_ == 1 ? 1.0 : bounds_.v1;
    if (!ascending(edges_.rows, v0, v1) || (dims_ == 1 && edges_.rows.size() != 2))
        throw std::invalid_argument("cell edges: rows must ascend strictly from the parameter range's start to its end");
    if (edges_.cols.size() + 1 != edges_.rows.size())
        throw std::invalid_argument("cell edges: one list of column edges per row");
    for (const std::vector<double>& c : edges_.cols)
        if (!ascending(c, bounds_.u0, bounds_.u1) || c.size() != edges_.cols.front().size())
            throw std::invalid_argument(
                "cell edges: every row's columns must ascend strictly across the parameter range, as many in each row");
    const std::size_t cells = (edges_.cols.front().size() - 1) * (edges_.rows.size() - 1);
    if (cells > (std::size_t{1} << 26)) throw std::invalid_argument("cell edges: too many cells");
    if (!edges_.pieces.empty() && edges_.pieces.size() != cells)
        throw std::invalid_argument("cell edges: integration pieces for every cell or none");
}

void Binning::EdgeLookup::build(const std::vector<double>& e, std::size_t buckets_per_part) {
    const std::size_t parts = e.size() - 1, buckets = buckets_per_part * parts;
    lo = e.front();
    scale = static_cast<double>(buckets) / (e.back() - e.front());
    first.assign(buckets + 1, 0);
    std::size_t i = 0;
    for (std::size_t b = 0; b <= buckets; ++b) {
        const double start = lo + static_cast<double>(b) / scale;
        while (i + 1 < parts && e[i + 1] <= start) ++i;
        first[b] = static_cast<uint32_t>(i);
    }
}

int Binning::EdgeLookup::find(const std::vector<double>& e, double x) const {
    const std::size_t parts = e.size() - 1, buckets = first.size() - 1;
    const double f = (x - lo) * scale;
    const std::size_t b = f >= 0.0 ? std::min(buckets - 1, static_cast<std::size_t>(f)) : 0;  // NaN: bucket 0
    std::size_t i = first[b];
    const std::size_t j = first[b + 1];
    // The bucket's parts run from i to j; rounding of f may put x in a
    // neighbouring bucket, so the answer is checked and searched for whole if
    // it does not hold x.
    if (j > i) {
        if (j - i <= 4) {
            while (i < j && e[i + 1] <= x) ++i;
        } else {
            i = static_cast<std::size_t>(std::upper_bound(e.begin() + 1 + i, e.begin() + 1 + j, x) - e.begin()) - 1;
        }
    }
    const bool holds = (i == 0 || e[i] <= x) && (i + 1 == parts || x < e[i + 1]);
    if (holds || !(x == x)) return static_cast<int>(i);
    return static_cast<int>(std::upper_bound(e.begin() + 1, e.end() - 1, x) - (e.begin() + 1));
}

int Binning::uniform_phi_column(double x, double y) const {
    // By the octant table, or else by the fast atan2, with the exact one within
    // a safety margin of a cell edge (the fast one is within 3e-8 rad; the
    // margin is 1e-6 rad).
    if (octant_cols_ > 0) return phi_column_by_table(x, y);
    const double inv_du = 1.0 / du_, edge_margin = 1e-6 * inv_du;
    const double f = fast_phi(x, y) * inv_du;
    const double fl = std::floor(f);
    if (f - fl < edge_margin || fl + 1.0 - f < edge_margin) return clamp_index(exact_phi(x, y) * inv_du, cols_);
    return clamp_index(fl, cols_);
}

int Binning::own_phi_column(int row, double x, double y, double& phi) const {
    // The fast atan2 (within 3e-8 rad), and the exact one within 1e-6 rad of
    // the column's edges.
    phi = fast_phi(x, y);
    int col = column_of(row, phi);
    const std::vector<double>& e = edges_.cols[static_cast<std::size_t>(row)];
    const auto c = static_cast<std::size_t>(col);
    if (phi - e[c] < 1e-6 || e[c + 1] - phi < 1e-6) {
        phi = exact_phi(x, y);
        col = column_of(row, phi);
    }
    return col;
}

int Binning::row_of(double v) const {
    // The last row whose lower edge is at or below v (clamped: points within
    // the tolerance outside go to the nearest row).
    return row_lookup_.find(edges_.rows, v);
}

int Binning::column_of(int row, double u) const {
    const auto r = static_cast<std::size_t>(row);
    return column_lookup_[r].find(edges_.cols[r], u);
}

void Binning::build_interval_edges() {
    interval_edges_.resize(static_cast<std::size_t>(cols_) + 1);
    interval_edges_.front() = bounds_.u0;
    interval_edges_.back() = bounds_.u1;
    for (int j = 1; j < cols_; ++j) {
        const double e = bounds_.u0 + (bounds_.u1 - bounds_.u0) * j / cols_;
        float f = static_cast<float>(e);
        if (static_cast<double>(f) < e) f = std::nextafter(f, std::numeric_limits<float>::infinity());
        interval_edges_[static_cast<std::size_t>(j)] = static_cast<double>(f);
    }
}

void Binning::build_phi_table() {
    octant_cols_ = cols_ / 8;
    tan_edges_.resize(static_cast<std::size_t>(octant_cols_) + 1);
    for (int k = 0; k < octant_cols_; ++k) tan_edges_[static_cast<std::size_t>(k)] = std::tan(k * du_);
    tan_edges_.back() = std::numeric_limits<double>::infinity();
    // Edges are at least du apart in t (tan' >= 1): with a lookup cell of
    // du / 2 or less, the comparison loop below runs at most twice.
    const int cells = std::max(256, 4 * octant_cols_);
    lookup_scale_ = cells;
    edge_lookup_.resize(static_cast<std::size_t>(cells) + 1);
    int j = 0;
    for (int m = 0; m <= cells; ++m) {
        while (j + 1 < octant_cols_ && tan_edges_[static_cast<std::size_t>(j) + 1] <= m / lookup_scale_) ++j;
        edge_lookup_[static_cast<std::size_t>(m)] = j;
    }
}

// Branch-free apart from the rare extra edge comparison: the octant and the
// quadrant are random per sample, so branches on them would mispredict half
// the time.
[[gnu::always_inline]] inline int Binning::phi_column_by_table(double x, double y) const {
    const double ax = std::abs(x), ay = std::abs(y);
    const double hi = std::max(ax, ay), lo = std::min(ax, ay);
    // t = lo / hi in [0, 1]; (0, 0) maps to t = 0, column 0.
    const double t = hi > 0.0 ? lo / hi : 0.0;
    // The lookup lands on or next to the last edge <= t (its own rounding of
    // t * scale may put it one too high); the comparisons settle it.
    int j = edge_lookup_[static_cast<std::size_t>(t * lookup_scale_)];
    while (j > 0 && t < tan_edges_[static_cast<std::size_t>(j)]) --j;
    while (t >= tan_edges_[static_cast<std::size_t>(j) + 1]) ++j;
    const int quadrant_cols = 2 * octant_cols_;
    const int steep = ay > ax;  // above the diagonal: phi = pi/2 - atan(t) within the quadrant
    const int q = j + steep * (quadrant_cols - 1 - 2 * j);
    // Quadrants by the signs: (+,+) q, (-,+) 2Q-1-q, (-,-) 2Q+q, (+,-) 4Q-1-q.
    const int sx = x < 0.0, sy = y < 0.0;
    const int mirrored = sx ^ sy;
    return q + mirrored * (2 * quadrant_cols - 1 - 2 * q) + sy * 2 * quadrant_cols;
}

int Binning::interval_column(double x) const {
    // The uniform guess is off by at most one cell near an edge; the snapped
    // edges decide.
    int col = clamp_index((x - bounds_.u0) * (1.0 / du_), cols_);
    while (col > 0 && x < interval_edges_[static_cast<std::size_t>(col)]) --col;
    while (col + 1 < cols_ && x >= interval_edges_[static_cast<std::size_t>(col) + 1]) ++col;
    return col;
}

ParamRect Binning::cell_rect(std::size_t cell) const {
    const auto col = static_cast<int>(cell % static_cast<std::size_t>(cols_));
    const auto row = static_cast<int>(cell / static_cast<std::size_t>(cols_));
    if (!edges_.empty()) {
        const std::vector<double>& c = edges_.cols[static_cast<std::size_t>(row)];
        const auto i = static_cast<std::size_t>(col), j = static_cast<std::size_t>(row);
        return {c[i], c[i + 1], edges_.rows[j], edges_.rows[j + 1]};
    }
    if (!interval_edges_.empty())
        return {interval_edges_[static_cast<std::size_t>(col)], interval_edges_[static_cast<std::size_t>(col) + 1],
                0.0, 1.0};
    // Edges from the index (not by accumulation), and exact at the domain's ends.
    auto edge = [](double lo, double hi, int i, int n) { return i == n ? hi : lo + (hi - lo) * i / n; };
    return {edge(bounds_.u0, bounds_.u1, col, cols_), edge(bounds_.u0, bounds_.u1, col + 1, cols_),
            edge(bounds_.v0, bounds_.v1, row, rows_), edge(bounds_.v0, bounds_.v1, row + 1, rows_)};
}

std::vector<ParamRect> Binning::integration_pieces(std::size_t cell) const {
    if (cell < edges_.pieces.size() && !edges_.pieces[cell].empty()) return edges_.pieces[cell];
    return {cell_rect(cell)};
}

double Binning::cell_measure(std::size_t cell) const {
    const ParamRect r = cell_rect(cell);
    return std::visit([&](const auto& k) { return k.cell_measure(r, resolution_); }, domain_.shape());
}

DomainPoint Binning::point_at(double u, double v) const {
    return std::visit(
        [&](const auto& k) -> DomainPoint {
            if constexpr (std::decay_t<decltype(k)>::kAzimuthal) {
                const auto [radius, height] = k.ring(v);  // as the quadrature's grids compute it
                return {radius * std::cos(u), radius * std::sin(u), height};
            } else {
                return k.point_at(u, v, resolution_);
            }
        },
        domain_.shape());
}

std::array<double, 2> Binning::ring(double v) const {
    return std::visit(
        [&](const auto& k) -> std::array<double, 2> {
            if constexpr (std::decay_t<decltype(k)>::kAzimuthal) return k.ring(v);
            else throw std::logic_error("Binning::ring: " + k.describe() + " is not azimuthal");
        },
        domain_.shape());
}

double Binning::jacobian(double u, double v) const {
    return std::visit([&](const auto& k) { return k.jacobian(u, v, resolution_); }, domain_.shape());
}

std::array<double, 2> Binning::parameters_of(const DomainPoint& p) const {
    return std::visit(
        [&](const auto& k) -> std::array<double, 2> {
            if constexpr (std::decay_t<decltype(k)>::kAzimuthal) return {exact_phi(p[0], p[1]), k.v_of(p)};
            else return k.parameters_of(p, resolution_);
        },
        domain_.shape());
}

std::size_t Binning::cell_at_parameters(double u, double v) const {
    if (domain_.azimuthal()) {
        u = std::fmod(u, kTwoPi);
        if (u < 0.0) u += kTwoPi;
    }
    // The same arithmetic as bin_impl, so both put a point in the same cell.
    if (!edges_.empty()) {
        const int row = dims_ == 1 ? 0 : row_of(v);
        return static_cast<std::size_t>(row) * static_cast<std::size_t>(cols_) +
               static_cast<std::size_t>(column_of(row, u));
    }
    const int col = !interval_edges_.empty() ? interval_column(u) : clamp_index((u - bounds_.u0) * (1.0 / du_), cols_);
    const int row = clamp_index((v - bounds_.v0) * (1.0 / dv_), rows_);
    return static_cast<std::size_t>(row) * static_cast<std::size_t>(cols_) + static_cast<std::size_t>(col);
}

std::ptrdiff_t Binning::cell_of(const DomainPoint& p) const {
    const int n = domain_.point_dimension();
    for (int k = 0; k < n; ++k)
        if (std::isnan(p[static_cast<std::size_t>(k)])) return kNaN;
    if (!domain_.contains(p)) return kOutside;
    const auto uv = parameters_of(p);
    return static_cast<std::ptrdiff_t>(cell_at_parameters(uv[0], uv[1]));
}

std::array<double, 2> Binning::rounding_reach(double u, double v) const {
    // Each coordinate moved kSnapFloatSteps float spacings of the domain's
    // extent (the slack's scale, as the consistency check probes), both ways.
    const DomainPoint p = point_at(u, v);
    const double extent[3] = {tol_x_ / kDomainTolerance, tol_y_ / kDomainTolerance, tol_x_ / kDomainTolerance};
    const std::array<double, 2> at = parameters_of(p);
    std::array<double, 2> reach{0.0, 0.0};
    for (int c = 0; c < domain_.point_dimension(); ++c)
        for (const double sign : {1.0, -1.0}) {
            DomainPoint q = p;
            const auto k = static_cast<std::size_t>(c);
            q[k] += sign * kSnapFloatSteps * 0x1p-24 * std::max(extent[k], std::abs(p[k]));
            const std::array<double, 2> moved = parameters_of(q);
            for (std::size_t a = 0; a < 2; ++a) {
                double d = std::abs(moved[a] - at[a]);
                if (a == 0 && domain_.azimuthal()) d = std::min(d, kTwoPi - d);
                if (std::isfinite(d)) reach[a] = std::max(reach[a], d);
            }
        }
    return reach;
}

std::size_t Binning::snap_from_zero_cell(double u, double v, std::size_t cell, std::span<const unsigned char> zero_cells,
                                         uint64_t& snapped) const {
    // How far rounding may have moved the sample, in parameter units: a few
    // float spacings of the coordinates (rounding_reach), at most the
    // membership slack (2 pi times it for phi). Not the slack alone: cells of
    // equal probability can be far narrower than it (a lobe of 1e-6 sr has
    // rows 1e-7 apart in cos theta, the slack is 1e-5).
    auto [tu, tv_kind] = std::visit([&](const auto& k) { return k.parameter_slack({tol_x_, tol_y_}); },
                                    domain_.shape());
    const std::array<double, 2> reach = rounding_reach(u, v);
    tu = std::min(tu, reach[0]);
    tv_kind = std::min(tv_kind, reach[1]);
    const double tv = dims_ == 1 ? 0.0 : tv_kind;
    static constexpr int kSteps[8][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}, {-1, -1}, {1, -1}, {-1, 1}, {1, 1}};
    for (const auto& s : kSteps) {
        if (dims_ == 1 && s[1] != 0) continue;
        const std::size_t other = cell_at_parameters(u + s[0] * tu, v + s[1] * tv);
        if (!zero_cells[other]) {
            ++snapped;
            return other;
        }
    }
    return cell;
}

// Whether parameters (u, v) lie exactly on the domain's boundary (Domain::on_boundary).
bool Binning::on_parameter_boundary(double u, double v) const {
    return std::visit([&](const auto& k) { return k.on_parameter_boundary(u, v); }, domain_.shape());
}

void Binning::count_pole(Histogram& hist, std::size_t row) const {
    if (hist.poles.empty()) hist.poles.assign(static_cast<std::size_t>(rows_), 0);
    ++hist.poles[row];
}

namespace {

/// A sample left in a zero cell, kept; the list is compacted when it doubles
/// (at least 4096): with hundreds of zero cells, what compaction keeps (six
/// points a cell) is itself thousands, and compacting at a fixed size would
/// sort them again at every sample.
void keep_zero_point(std::vector<Histogram::CellPoint>& points, std::size_t& compact_at, Histogram::CellPoint p) {
    points.push_back(p);
    if (points.size() < compact_at) return;
    keep_extreme_points(points, {});
    compact_at = std::max<std::size_t>(4096, 2 * points.size());
}

}  // namespace

template <typename Point>
void Binning::bin_impl(std::span<const Point> points, Histogram& hist, std::span<const unsigned char> zero_cells) const {
    if (hist.counts.size() != cell_count()) throw std::invalid_argument("Binning::bin: histogram of another binning");
    if (!zero_cells.empty() && zero_cells.size() != cell_count())
        throw std::invalid_argument("Binning::bin: zero-cell mask of another binning");
    uint64_t* const counts = hist.counts.data();
    const double inv_dv = 1.0 / dv_;
    const bool check_zero = !zero_cells.empty();
    // A sample in a zero-expected cell moves to a neighbour within the domain
    // tolerance if it can; otherwise, if it lies exactly on the domain's
    // boundary, it is set aside: a float warp reaches the boundary from input
    // edges such as u = 0 (probability ~2^-24 per sample), where a density like
    // cos^n(theta) vanishes. The test caps how many it accepts (chi2_test.cpp).
    std::vector<Histogram::CellPoint> zero_points;  // samples left in zero cells (rare)
    std::size_t compact_at = 4096;
    auto add = [&](std::size_t cell, double u, double v, const DomainPoint& q) {
        if (check_zero && zero_cells[cell]) {
            cell = snap_from_zero_cell(u, v, cell, zero_cells, hist.snapped);
            if (zero_cells[cell] && on_parameter_boundary(u, v)) {
                ++hist.on_boundary;
                return;
            }
            if (zero_cells[cell]) keep_zero_point(zero_points, compact_at, {cell, q});
        }
        ++counts[cell];
    };
    // Spherical and disk samples: phi is computed exactly only to snap out of a zero cell (rare).
    auto add_phi = [&](std::size_t cell, double x, double y, double v, const DomainPoint& q) {
        if (check_zero && zero_cells[cell]) add(cell, exact_phi(x, y), v, q);
        else ++counts[cell];
    };
    const std::size_t cols = static_cast<std::size_t>(cols_);
    const bool own_edges = !edges_.empty();

    // One loop per kind (std::visit outside it): NaN first, then membership,
    // then the cell. Azimuthal kinds get phi's column from the table or the
    // fast atan2 and their row from v; the others map the point to (u, v).
    const Domain::Slack slack{tol_x_, tol_y_};
    std::visit(
        [&](const auto& kind) {
            using Kind = std::decay_t<decltype(kind)>;
            for (const auto& p : points) {
                constexpr int n = Kind::kPointDimension;
                const DomainPoint q{p[0], n > 1 ? p[1] : 0.0, n > 2 ? p[2] : 0.0};
                if (q[0] != q[0] || q[1] != q[1] || q[2] != q[2]) { ++hist.nan; continue; }
                bool inside = false;
                if constexpr (requires { kind.bin_contains(q, slack); }) inside = kind.bin_contains(q, slack);
                else inside = kind.contains(q, slack);
                if (!inside) { ++hist.outside; continue; }
                if constexpr (Kind::kAzimuthal) {
                    const double v = kind.v_of(q);
                    const auto row = static_cast<std::size_t>(own_edges ? row_of(v)
                                                                        : clamp_index((v - bounds_.v0) * inv_dv, rows_));
                    if (q[0] == 0.0 && q[1] == 0.0) {  // a pole: no azimuth (Histogram::poles)
                        count_pole(hist, row);
                        continue;
                    }
                    if (own_edges) {
                        double phi = 0.0;
                        const int col = own_phi_column(static_cast<int>(row), q[0], q[1], phi);
                        add(row * cols + static_cast<std::size_t>(col), phi, v, q);
                    } else {
                        add_phi(row * cols + static_cast<std::size_t>(uniform_phi_column(q[0], q[1])), q[0], q[1], v, q);
                    }
                } else {
                    // The same arithmetic as cell_at_parameters.
                    const auto [u, v] = kind.parameters_of(q, resolution_);
                    add(cell_at_parameters(u, v), u, v, q);
                }
            }
        },
        domain_.shape());
    if (!zero_points.empty()) keep_extreme_points(hist.zero_cell_points, zero_points);
}

void Binning::bin(std::span<const std::array<float, 3>> points, Histogram& hist,
                  std::span<const unsigned char> zero_cells) const {
    bin_impl(points, hist, zero_cells);
}

void Binning::bin(std::span<const DomainPoint> points, Histogram& hist, std::span<const unsigned char> zero_cells) const {
    bin_impl(points, hist, zero_cells);
}

std::optional<LanePlan> Binning::lane_plan() const {
    if (!edges_.empty() || octant_cols_ == 0 || octant_cols_ > LanePlan::kMaxOctantCols) return std::nullopt;
    LanePlan plan;
    if (domain_.is<SphericalCap>()) {
        plan.sphere = true;
        plan.len2_lo = (1.0 - tol_x_) * (1.0 - tol_x_);
        plan.z_floor = domain_.as<SphericalCap>().z_min - tol_x_;
    } else if (!domain_.is<Disk>()) {
        return std::nullopt;
    }
    plan.len2_hi = (1.0 + tol_x_) * (1.0 + tol_x_);
    plan.v0 = bounds_.v0;
    plan.inv_dv = 1.0 / dv_;
    plan.rows = rows_;
    plan.cols = cols_;
    plan.octant_cols = octant_cols_;
    for (int k = 1; k < octant_cols_; ++k) plan.tan_edges[k - 1] = tan_edges_[static_cast<std::size_t>(k)];
    return plan;
}

namespace {

/// The fewest float steps across a cell along `axis`, over the cells along
/// that axis (at the middle of the other axis).
double narrowest_in_floats(const Binning& b, int axis) {
    const int n = axis == 0 ? b.cols() : b.rows();
    const int other = axis == 0 ? b.rows() / 2 : b.cols() / 2;
    double worst = std::numeric_limits<double>::infinity();
    for (int k = 0; k < n; ++k) {
        const std::size_t cell = axis == 0 ? static_cast<std::size_t>(other) * b.cols() + k
                                           : static_cast<std::size_t>(k) * b.cols() + other;
        const ParamRect r = b.cell_rect(cell);
        const double uc = 0.5 * (r.u0 + r.u1), vc = 0.5 * (r.v0 + r.v1);
        const double step = b.float_resolution(axis, uc, vc);
        const double width = axis == 0 ? r.u1 - r.u0 : r.v1 - r.v0;
        if (step > 0.0) worst = std::min(worst, width / step);
    }
    return worst;
}

}  // namespace

BinResolution float_aware_resolution(const Domain& domain, BinResolution requested, uint64_t samples) {
    Binning b(domain, requested);
    BinResolution r = b.resolution();
    r.first = b.cols();
    r.second = b.parameter_dimension() == 1 ? 0 : b.rows();
    for (int axis = 0; axis < b.parameter_dimension(); ++axis) {
        while (true) {
            const int n = axis == 0 ? b.cols() : b.rows();
            const int floor = axis == 0 && domain.azimuthal() ? 8 : 1;
            const double mean = static_cast<double>(samples) / static_cast<double>(b.cell_count());
            if (n / 2 < floor || narrowest_in_floats(b, axis) >= 3.0 * std::sqrt(mean)) break;
            (axis == 0 ? r.first : r.second) = n / 2;
            b = Binning(domain, r);
        }
    }
    return r;
}

void Binning::spread_poles(Histogram& hist) const {
    if (hist.poles.empty()) return;
    if (edges_.empty() || !domain_.azimuthal()) {
        hist.spread_poles(cols_);
        return;
    }
    std::vector<double> shares;
    shares.reserve(cell_count());
    for (const std::vector<double>& row : edges_.cols)
        for (std::size_t c = 0; c + 1 < row.size(); ++c) shares.push_back(row[c + 1] - row[c]);
    hist.spread_poles(cols_, shares);
}

std::string Binning::u_label() const {
    return std::visit([](const auto& k) { return k.u_label(); }, domain_.shape());
}

std::string Binning::v_label() const {
    return std::visit([](const auto& k) { return k.v_label(); }, domain_.shape());
}

double Binning::cell_position(std::size_t cell) const {
    const ParamRect r = cell_rect(cell);
    return std::visit(
        [&](const auto& k) {
            if constexpr (std::decay_t<decltype(k)>::kAzimuthal) return 0.5 * (r.u0 + r.u1);
            else return k.cell_position(r, resolution_);
        },
        domain_.shape());
}

}  // namespace warpcheck::chi2

#include "chi2/two_sample.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "chi2/unbinned.h"

namespace warpcheck::chi2 {

HomogeneityResult homogeneity_test(std::span<const uint64_t> a, std::span<const uint64_t> b, double min_expected) {
    if (a.size() != b.size()) throw std::invalid_argument("homogeneity_test: the histograms have different cells");
    HomogeneityResult r;
    double na = 0.0, nb = 0.0;
    for (std::size_t k = 0; k < a.size(); ++k) na += static_cast<double>(a[k]), nb += static_cast<double>(b[k]);
    const double n = na + nb;
    if (!(na > 0.0 && nb > 0.0)) {
        r.statistic = r.p_value = std::numeric_limits<double>::quiet_NaN();
        return r;
    }
    r.effective_samples = na * nb / n;
    const double smaller = std::min(na, nb);
    // Terms: runs of cells, each closed once the smaller sample expects enough in it.
    std::vector<std::array<double, 2>> terms;
    double run_a = 0.0, run_b = 0.0;
    std::size_t run_cells = 0;
    for (std::size_t k = 0; k < a.size(); ++k) {
        run_a += static_cast<double>(a[k]), run_b += static_cast<double>(b[k]), ++run_cells;
        if (smaller * (run_a + run_b) / n >= min_expected) {
            terms.push_back({run_a, run_b});
            r.merged_cells += run_cells - 1;
            run_a = run_b = 0.0, run_cells = 0;
        }
    }
    if (run_cells > 0) {  // the leftover joins the last term, or is the only one
        if (terms.empty()) terms.push_back({0.0, 0.0});
        else r.merged_cells += run_cells;
        terms.back()[0] += run_a, terms.back()[1] += run_b;
    }
    const double ratio = std::sqrt(nb / na);
    for (const auto& [ta, tb] : terms) {
        const double d = ratio * ta - tb / ratio;
        r.statistic += d * d / (ta + tb);
        const double expected_a = na * (ta + tb) / n;
        r.residual.push_back((ta - expected_a) / std::sqrt(expected_a));
    }
    r.terms = terms.size();
    r.dof = static_cast<int>(terms.size()) - 1;
    r.p_value = r.dof >= 1 ? chi_square_upper_tail(r.statistic, r.dof) : std::numeric_limits<double>::quiet_NaN();
    if (r.dof < 1) r.statistic = std::numeric_limits<double>::quiet_NaN();
    return r;
}

namespace {

/// Lower edges of `parts` cells at quantiles of the sorted values: -inf, then
/// the value at each k/parts of the way, each once (tied quantiles are one edge).
std::vector<double> quantile_edges(std::span<const double> sorted, int parts) {
    std::vector<double> edges{-std::numeric_limits<double>::infinity()};
    for (int k = 1; k < parts; ++k) {
        const std::size_t at = sorted.size() * static_cast<std::size_t>(k) / static_cast<std::size_t>(parts);
        if (at >= sorted.size()) break;
        if (sorted[at] > edges.back()) edges.push_back(sorted[at]);
    }
    return edges;
}

/// The index of the last edge <= x (edges[0] is -inf).
std::size_t part_of(const std::vector<double>& edges, double x) {
    return static_cast<std::size_t>(std::upper_bound(edges.begin(), edges.end(), x) - edges.begin()) - 1;
}

}  // namespace

AdaptiveCells::AdaptiveCells(std::span<const Point> a, std::span<const Point> b, int dims, int strips,
                             int cells_per_strip)
    : dims_(dims), cells_per_strip_(dims == 2 ? cells_per_strip : 1) {
    if (dims != 1 && dims != 2) throw std::invalid_argument("AdaptiveCells: dims must be 1 or 2");
    if (strips < 1 || cells_per_strip < 1) throw std::invalid_argument("AdaptiveCells: needs at least one cell");
    std::vector<double> u;
    u.reserve(a.size() + b.size());
    for (const Point& p : a) u.push_back(p[0]);
    for (const Point& p : b) u.push_back(p[0]);
    std::sort(u.begin(), u.end());
    u_edges_ = quantile_edges(u, strips);
    v_edges_.assign(u_edges_.size(), {-std::numeric_limits<double>::infinity()});
    if (dims_ == 1) return;
    std::vector<std::vector<double>> v(u_edges_.size());
    for (auto sample : {a, b})
        for (const Point& p : sample) v[part_of(u_edges_, p[0])].push_back(p[1]);
    for (std::size_t s = 0; s < v.size(); ++s) {
        std::sort(v[s].begin(), v[s].end());
        v_edges_[s] = quantile_edges(v[s], cells_per_strip_);
    }
}

std::size_t AdaptiveCells::cell_of(const Point& p) const {
    const std::size_t strip = part_of(u_edges_, p[0]);
    const std::size_t cell = dims_ == 2 ? part_of(v_edges_[strip], p[1]) : 0;
    return strip * static_cast<std::size_t>(cells_per_strip_) + cell;
}

std::vector<uint64_t> AdaptiveCells::counts(std::span<const Point> points) const {
    std::vector<uint64_t> c(cell_count(), 0);
    for (const Point& p : points) ++c[cell_of(p)];
    return c;
}

namespace {

/// Scholz and Stephens' variance of A^2_kN under the null (their section 3),
/// from N, k and H = sum of 1 / n_i; h and g are sums of reciprocals over N,
/// g's double sum taken in one pass: g = sum_{i=1}^{N-2} (h_{N-1} - h_i) / (N - i).
double ad_k_sample_variance(double n_total, double k, double h_inverse_sizes) {
    const auto big_n = static_cast<std::size_t>(n_total);
    double h = 0.0;  // h_{N-1} = sum_{j=1}^{N-1} 1/j
    for (std::size_t j = 1; j < big_n; ++j) h += 1.0 / static_cast<double>(j);
    double g = 0.0, h_i = 0.0;
    for (std::size_t i = 1; i + 2 <= big_n; ++i) {
        h_i += 1.0 / static_cast<double>(i);
        g += (h - h_i) / static_cast<double>(big_n - i);
    }
    const double H = h_inverse_sizes, N = n_total;
    const double a = (4 * g - 6) * (k - 1) + (10 - 6 * g) * H;
    const double b = (2 * g - 4) * k * k + 8 * h * k + (2 * g - 14 * h - 4) * H - 8 * h + 4 * g - 6;
    const double c = (6 * h + 2 * g - 2) * k * k + (4 * h - 4 * g + 6) * k + (2 * h - 6) * H + 4 * h;
    const double d = (2 * h + 6) * k * k - 4 * h * k;
    return (a * N * N * N + b * N * N + c * N + d) / ((N - 1) * (N - 2) * (N - 3));
}

}  // namespace

AndersonDarlingTwoSample anderson_darling_two_sample(std::span<const double> a, std::span<const double> b) {
    AndersonDarlingTwoSample r;
    const double na = static_cast<double>(a.size()), nb = static_cast<double>(b.size()), n = na + nb;
    const auto has_nan = [](std::span<const double> s) {
        return std::any_of(s.begin(), s.end(), [](double x) { return std::isnan(x); });
    };
    if (a.empty() || b.empty() || n < 4 || has_nan(a) || has_nan(b)) {
        r.a2 = r.standardized = r.p_value = std::numeric_limits<double>::quiet_NaN();
        return r;
    }
    std::vector<double> sa(a.begin(), a.end()), sb(b.begin(), b.end());
    std::sort(sa.begin(), sa.end());
    std::sort(sb.begin(), sb.end());
    // One merge over the distinct pooled values z_j: per value its count in
    // each sample (f_aj, f_bj), l_j = f_aj + f_bj, and the counts below it.
    double sum_a = 0.0, sum_b = 0.0, below_a = 0.0, below_b = 0.0;
    std::size_t i = 0, j = 0;
    while (i < sa.size() || j < sb.size()) {
        const double z = j == sb.size() || (i < sa.size() && sa[i] < sb[j]) ? sa[i] : sb[j];
        double fa = 0.0, fb = 0.0;
        for (; i < sa.size() && sa[i] == z; ++i) fa += 1.0;
        for (; j < sb.size() && sb[j] == z; ++j) fb += 1.0;
        const double l = fa + fb;
        const double bj = below_a + below_b + l / 2;  // B_aj: pooled midrank count
        const double denominator = bj * (n - bj) - n * l / 4;
        // Only a single distinct value over the whole pool makes it 0 (0/0): no evidence either way.
        if (denominator > 0.0) {
            const double ma = below_a + fa / 2, mb = below_b + fb / 2;  // M_aij: each sample's midrank count
            sum_a += l / n * (n * ma - na * bj) * (n * ma - na * bj) / denominator;
            sum_b += l / n * (n * mb - nb * bj) * (n * mb - nb * bj) / denominator;
        }
        below_a += fa, below_b += fb;
        ++r.distinct;
    }
    r.a2 = (n - 1) / n * (sum_a / na + sum_b / nb);
    const double sigma2 = ad_k_sample_variance(n, 2.0, 1.0 / na + 1.0 / nb);
    r.standardized = (r.a2 - 1.0) / std::sqrt(sigma2);
    r.p_value = 1.0 - anderson_darling_asymptotic_cdf(r.a2);
    return r;
}

}  // namespace warpcheck::chi2

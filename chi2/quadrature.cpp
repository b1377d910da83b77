#include "chi2/quadrature.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>

namespace warpcheck::chi2 {

namespace {

constexpr int kNodes = 15;

/// The 15 Kronrod nodes on [-1, 1] in increasing order, their weights, and the
/// weights of the embedded 7-point Gauss rule (zero on Kronrod-only nodes).
struct Rule {
    std::array<double, kNodes> x{}, wk{}, wg{};
    Rule() {
        using Kronrod = boost::math::quadrature::gauss_kronrod<double, kNodes>;
        using Gauss = boost::math::quadrature::gauss<double, (kNodes - 1) / 2>;
        const auto& a = Kronrod::abscissa();  // a[0] = 0, a[1..7] > 0
        const auto& w = Kronrod::weights();
        const auto& g = Gauss::weights();  // for the Gauss nodes a[0], a[2], a[4], a[6]
        constexpr int mid = kNodes / 2;
        for (int i = 0; i <= mid; ++i) {
            const auto k = static_cast<std::size_t>(i);
            const double gauss_weight = (i % 2 == 0) ? g[k / 2] : 0.0;
            x[static_cast<std::size_t>(mid + i)] = a[k];
            x[static_cast<std::size_t>(mid - i)] = -a[k];
            wk[static_cast<std::size_t>(mid + i)] = wk[static_cast<std::size_t>(mid - i)] = w[k];
            wg[static_cast<std::size_t>(mid + i)] = wg[static_cast<std::size_t>(mid - i)] = gauss_weight;
        }
    }
};

const Rule& rule() {
    static const Rule r;
    return r;
}

struct Region {
    ParamRect rect;
    double value = 0.0;
    double err_u = 0.0;  // change when the u rule drops to Gauss
    double err_v = 0.0;  // change when the v rule drops to Gauss
    double f_min = 0.0, f_max = 0.0;  // the density's range over the nodes
    double error() const { return err_u + err_v; }
};

bool less_error(const Region& a, const Region& b) { return a.error() < b.error(); }

/// Evaluates the tensor rule on rectangles of one binning, reusing its buffers.
class RegionRule {
public:
    RegionRule(const Binning& binning, const BatchPdf& pdf, bool probe_edges = false)
        : binning_(binning), pdf_(pdf), probe_edges_(probe_edges) {
        const std::size_t n = binning.parameter_dimension() == 1 ? kNodes : kNodes * kNodes;
        points_.resize(n);
        values_.resize(n);
    }

    uint64_t evaluations = 0, negative = 0, nonfinite = 0;

    Region evaluate(const ParamRect& r) {
        const Rule& q = rule();
        const double uc = 0.5 * (r.u0 + r.u1), hu = 0.5 * (r.u1 - r.u0);
        const double vc = 0.5 * (r.v0 + r.v1), hv = 0.5 * (r.v1 - r.v0);
        std::array<double, kNodes> us{}, vs{};
        for (int i = 0; i < kNodes; ++i) {
            us[static_cast<std::size_t>(i)] = uc + hu * q.x[static_cast<std::size_t>(i)];
            vs[static_cast<std::size_t>(i)] = vc + hv * q.x[static_cast<std::size_t>(i)];
        }
        const bool one_d = binning_.parameter_dimension() == 1;
        fill_points(us, vs, one_d);
        if (one_d) keep_inside(points_);
        pdf_(points_, values_);
        evaluations += values_.size();

        // Weight by the measure density, screening for values that make no density.
        // Every kind's Jacobian depends on u alone (chi2/domain.h): one per column.
        std::array<double, kNodes> jacobian{};
        for (std::size_t i = 0; i < kNodes; ++i) jacobian[i] = binning_.jacobian(us[i], vs[0]);
        bool finite = true;
        double f_min = std::numeric_limits<double>::infinity(), f_max = -f_min;
        for (std::size_t k = 0, i = 0; k < values_.size(); ++k, i = i + 1 == kNodes ? 0 : i + 1) {
            const double f = values_[k];
            if (!std::isfinite(f)) {
                ++nonfinite;
                finite = false;
            } else if (f < 0.0) {
                ++negative;
            }
            f_min = std::min(f_min, f);
            f_max = std::max(f_max, f);
            values_[k] = f * jacobian[i];
        }
        if (probe_edges_) widen_by_edge_probes(r, f_min, f_max);
        Region out{r, 0.0, 0.0, 0.0, f_min, f_max};
        if (!finite) {
            out.value = std::numeric_limits<double>::quiet_NaN();
            return out;
        }
        if (one_d) {
            double kr = 0.0, ga = 0.0;
            for (std::size_t i = 0; i < kNodes; ++i) {
                kr += q.wk[i] * values_[i];
                ga += q.wg[i] * values_[i];
            }
            out.value = hu * kr;
            out.err_u = hu * std::abs(kr - ga);
            return out;
        }
        double kk = 0.0, gk = 0.0, kg = 0.0;
        for (std::size_t j = 0; j < kNodes; ++j) {
            double row_k = 0.0, row_g = 0.0;
            for (std::size_t i = 0; i < kNodes; ++i) {
                const double f = values_[j * kNodes + i];
                row_k += q.wk[i] * f;
                row_g += q.wg[i] * f;
            }
            kk += q.wk[j] * row_k;
            gk += q.wk[j] * row_g;
            kg += q.wg[j] * row_k;
        }
        const double area = hu * hv;
        out.value = area * kk;
        out.err_u = area * std::abs(kk - gk);
        out.err_v = area * std::abs(kk - kg);
        return out;
    }

    /// The integral over r of the density's change over one float step of its
    /// arguments (the file comment of quadrature.h), by the 3-point
    /// Gauss-Legendre rule per parameter (a noise estimate needs no more): each
    /// coordinate of each node moved one float up and down.
    double noise(const ParamRect& r) {
        static constexpr double kX[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
        static constexpr double kW[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
        const bool one_d = binning_.parameter_dimension() == 1;
        const int dims = binning_.domain().point_dimension();
        noise_points_.clear();
        noise_weights_.clear();
        for (int j = 0; j < (one_d ? 1 : 3); ++j)
            for (int i = 0; i < 3; ++i) {
                const double u = 0.5 * (r.u0 + r.u1) + 0.5 * (r.u1 - r.u0) * kX[i];
                const double v = one_d ? 0.5 : 0.5 * (r.v0 + r.v1) + 0.5 * (r.v1 - r.v0) * kX[j];
                noise_weights_.push_back(kW[i] * (one_d ? 1.0 : kW[j]) * binning_.jacobian(u, v));
                const DomainPoint p = rounded(binning_.point_at(u, v));
                noise_points_.push_back(p);
                for (int c = 0; c < dims; ++c)
                    for (const float toward : {INFINITY, -INFINITY}) {
                        DomainPoint n = p;
                        const auto k = static_cast<std::size_t>(c);
                        n[k] = static_cast<double>(std::nextafter(static_cast<float>(p[k]), toward));
                        noise_points_.push_back(n);
                    }
            }
        if (one_d) keep_inside(noise_points_);
        noise_values_.resize(noise_points_.size());
        pdf_(noise_points_, noise_values_);
        evaluations += noise_values_.size();
        const std::size_t stride = 1 + 2 * static_cast<std::size_t>(dims);
        double sum = 0.0;
        for (std::size_t node = 0; node < noise_weights_.size(); ++node) {
            const double* f = &noise_values_[node * stride];
            double change = 0.0;
            for (int c = 0; c < dims; ++c) {
                // A change of more than half the density over one float step is
                // a jump of the density (a node on a support's edge), not its
                // rounding: it is not counted.
                const auto step = [&](double other) {
                    const double d = std::abs(other - f[0]);
                    return d > 0.5 * std::max(std::abs(other), std::abs(f[0])) ? 0.0 : d;
                };
                change += std::max(step(f[1 + 2 * c]), step(f[2 + 2 * c]));
            }
            if (std::isfinite(change)) sum += noise_weights_[node] * change;
        }
        const double area = one_d ? 0.5 * (r.u1 - r.u0) : 0.25 * (r.u1 - r.u0) * (r.v1 - r.v0);
        return area * sum;
    }

    /// Widens [f_min, f_max] by the density just outside each side of r (the
    /// midpoint of each edge moved out by 2^-20 of the region, where that stays
    /// in the domain): a jump that lies exactly on the edge between two final
    /// regions shows in neither's nodes, but here it does.
    void widen_by_edge_probes(const ParamRect& r, double& f_min, double& f_max) {
        const ParamRect b = binning_.parameter_bounds();
        const double du = 0x1p-20 * (r.u1 - r.u0), dv = 0x1p-20 * (r.v1 - r.v0);
        const double uc = 0.5 * (r.u0 + r.u1), vc = 0.5 * (r.v0 + r.v1);
        const bool one_d = binning_.parameter_dimension() == 1;
        probe_points_.clear();
        const auto probe = [&](double u, double v) {
            if (u >= b.u0 && u <= b.u1 && v >= b.v0 && v <= b.v1) probe_points_.push_back(binning_.point_at(u, v));
        };
        probe(r.u0 - du, vc);
        probe(r.u1 + du, vc);
        if (!one_d) {
            probe(uc, r.v0 - dv);
            probe(uc, r.v1 + dv);
        }
        probe_values_.resize(probe_points_.size());
        if (probe_points_.empty()) return;
        pdf_(probe_points_, probe_values_);
        evaluations += probe_values_.size();
        for (const double f : probe_values_) {
            if (!std::isfinite(f)) continue;
            f_min = std::min(f_min, f);
            f_max = std::max(f_max, f);
        }
    }

    /// The mass within one float step of a jump of the density inside the
    /// region or on its edges, bounded: where the density's values over the
    /// nodes and the edge probes span more
    /// than a factor 2 (or reach 0), a jump may cross the region, and the float
    /// points on either side of it stand for half a step beyond it (the pdf of
    /// a 0.25 degree sun, evaluated at float points, integrates to 1.003). The
    /// bound is the values' range times the jacobian times one float step of
    /// each parameter times the region's extent in the other (a line across
    /// the region is at most that long in each direction).
    double jump_band(const Region& g) {
        if (!(g.f_max > 2.0 * g.f_min) || !std::isfinite(g.f_max)) return 0.0;
        const ParamRect& r = g.rect;
        const double uc = 0.5 * (r.u0 + r.u1), vc = 0.5 * (r.v0 + r.v1);
        const double range = (g.f_max - std::max(g.f_min, 0.0)) * binning_.jacobian(uc, vc);
        if (binning_.parameter_dimension() == 1) return range * binning_.reading_resolution(0, uc, vc);
        return range * (binning_.reading_resolution(0, uc, vc) * (r.v1 - r.v0) +
                        binning_.reading_resolution(1, uc, vc) * (r.u1 - r.u0));
    }

private:
    /// On a line, points whose float rounding falls on or beyond a finite end
    /// of the domain moved to the nearest float inside: there a density with
    /// an integrable singularity (the arcsine law's, Weibull's with shape
    /// below 1) has no float value (infinite, or the largest float) that
    /// stands for the mass its float interval holds; the mass within half a
    /// float step of an end is the band the normalisation rule allows
    /// (chi2_test.cpp, boundary_band_mass).
    void keep_inside(std::vector<DomainPoint>& points) const {
        const Domain& d = binning_.domain();
        const double lo = d.a(), hi = d.b();
        const auto flo = static_cast<float>(lo), fhi = static_cast<float>(hi);
        for (DomainPoint& p : points) {
            const auto f = static_cast<float>(p[0]);
            if (std::isfinite(lo) && f <= flo) p[0] = static_cast<double>(std::nextafter(flo, INFINITY));
            else if (std::isfinite(hi) && f >= fhi) p[0] = static_cast<double>(std::nextafter(fhi, -INFINITY));
        }
    }

    /// The point as the density sees it: each coordinate rounded to float.
    static DomainPoint rounded(const DomainPoint& p) {
        return {static_cast<double>(static_cast<float>(p[0])), static_cast<double>(static_cast<float>(p[1])),
                static_cast<double>(static_cast<float>(p[2]))};
    }

    void fill_points(const std::array<double, kNodes>& us, const std::array<double, kNodes>& vs, bool one_d) {
        if (one_d) {
            for (std::size_t i = 0; i < kNodes; ++i) points_[i] = binning_.point_at(us[i], 0.5);
            return;
        }
        if (binning_.domain().azimuthal()) {
            // (phi, v) grids: one cos/sin per phi node and one ring per v node.
            std::array<double, kNodes> c{}, s{};
            for (std::size_t i = 0; i < kNodes; ++i) {
                c[i] = std::cos(us[i]);
                s[i] = std::sin(us[i]);
            }
            for (std::size_t j = 0; j < kNodes; ++j) {
                const auto [radius, z] = binning_.ring(vs[j]);
                for (std::size_t i = 0; i < kNodes; ++i) points_[j * kNodes + i] = {radius * c[i], radius * s[i], z};
            }
            return;
        }
        for (std::size_t j = 0; j < kNodes; ++j)
            for (std::size_t i = 0; i < kNodes; ++i) points_[j * kNodes + i] = binning_.point_at(us[i], vs[j]);
    }

    const Binning& binning_;
    const BatchPdf& pdf_;
    std::vector<DomainPoint> points_;
    std::vector<double> values_;
    bool probe_edges_ = false;
    std::vector<DomainPoint> noise_points_, probe_points_;
    std::vector<double> probe_values_;
    std::vector<double> noise_values_, noise_weights_;
};

struct CellOutcome {
    double value = 0.0;
    double error = 0.0;
    bool converged = true;
    double error_ratio = 0.0;
    double float_noise = 0.0;
    bool mismatch = false;
};

void resum(const std::vector<Region>& heap, double& value, double& error) {
    value = 0.0;
    error = 0.0;
    for (const Region& r : heap) {
        value += r.value;
        error += r.error();
    }
}

/// Globally adaptive integration of one rectangle within `budget` regions;
/// leaves the final regions in `heap`.
CellOutcome integrate_adaptive(RegionRule& rr, const ParamRect& cell, bool one_d, const QuadratureOptions& options,
                               std::size_t budget, std::vector<Region>& heap) {
    heap.clear();
    heap.push_back(rr.evaluate(cell));
    double value = heap.front().value, error = heap.front().error();
    while (std::isfinite(value) && !(error <= cell_tolerance(value, options)) && heap.size() < budget) {
        std::pop_heap(heap.begin(), heap.end(), less_error);
        const Region worst = heap.back();
        heap.pop_back();
        ParamRect a = worst.rect, b = worst.rect;
        if (one_d || worst.err_u >= worst.err_v) {
            a.u1 = b.u0 = 0.5 * (worst.rect.u0 + worst.rect.u1);
        } else {
            a.v1 = b.v0 = 0.5 * (worst.rect.v0 + worst.rect.v1);
        }
        value -= worst.value;
        error -= worst.error();
        for (const ParamRect& half : {a, b}) {
            const Region r = rr.evaluate(half);
            value += r.value;
            error += r.error();
            heap.push_back(r);
            std::push_heap(heap.begin(), heap.end(), less_error);
        }
        // Updated in place (a re-sum per split made a cell that used its whole
        // budget cost its square), and re-summed every 128 splits and at the
        // end, so that cancellation cannot drift.
        if (heap.size() % 128 == 0) resum(heap, value, error);
    }
    resum(heap, value, error);
    CellOutcome out;
    out.value = value;
    out.error = error;
    return out;
}

/// The rectangle cut at fractions (fu, fv) of its sides into four pieces (in
/// 1D, at fu into two), each integrated adaptively within its share of the
/// budget, summed. Cuts at irrational fractions leave no piece's nodes with
/// the symmetry of the whole cell's (a line through the cell's corners passes
/// through no piece's corners), and put a jump that lies between the first
/// rule's nodes at other places relative to the pieces' nodes, whichever
/// parameter it crosses.
CellOutcome integrate_split(RegionRule& rr, const ParamRect& cell, bool one_d, double fu, double fv,
                            const QuadratureOptions& options, std::vector<Region>& heap) {
    const double um = cell.u0 + fu * (cell.u1 - cell.u0), vm = cell.v0 + fv * (cell.v1 - cell.v0);
    std::vector<ParamRect> pieces = {{cell.u0, um, cell.v0, cell.v1}, {um, cell.u1, cell.v0, cell.v1}};
    if (!one_d)
        pieces = {{cell.u0, um, cell.v0, vm}, {um, cell.u1, cell.v0, vm}, {cell.u0, um, vm, cell.v1},
                  {um, cell.u1, vm, cell.v1}};
    CellOutcome sum;
    const std::size_t budget = std::max<std::size_t>(1, options.max_regions_per_cell / pieces.size());
    for (const ParamRect& piece : pieces) {
        const CellOutcome o = integrate_adaptive(rr, piece, one_d, options, budget, heap);
        sum.value += o.value;
        sum.error += o.error;
    }
    return sum;
}

// Irrational fractions for the verifying cuts (1 - 1/golden ratio and
// sqrt 2 - 1; for the arbiter, 1/golden ratio and 1 - 1/sqrt 2): no cut lies on
// the first rule's lines of symmetry, nor on the other split's.
constexpr double kVerifyU = 0.3819660112501051, kVerifyV = 0.41421356237309515;
constexpr double kArbiterU = 0.6180339887498949, kArbiterV = 0.2928932188134524;

/// How far two integrations of one cell may differ beyond their error bounds:
/// the density's float noise and 2^-20 of the value, since a float density's
/// rounding (2^-24 relative per value) differs between node sets.
double rounding_slack(const CellOutcome& o) { return o.float_noise + 0x1p-20 * std::abs(o.value); }

/// The first rule's result checked against the irrational split (see
/// quadrature.h): where they disagree beyond both bounds, a third split
/// arbitrates, the median value is kept and the bound covers the spread.
void verify_cell(RegionRule& rr, const ParamRect& cell, bool one_d, const QuadratureOptions& options,
                 std::vector<Region>& heap, CellOutcome& out) {
    const CellOutcome second = integrate_split(rr, cell, one_d, kVerifyU, kVerifyV, options, heap);
    if (!std::isfinite(out.value) || std::abs(out.value - second.value) <= out.error + second.error + rounding_slack(out))
        return;
    const CellOutcome third = integrate_split(rr, cell, one_d, kArbiterU, kArbiterV, options, heap);
    out.mismatch = true;
    // Two that agree within their bounds outvote the third (a rule whose nodes
    // sat on a jump); their mean is kept, with the larger bound plus their
    // difference. Without such a pair, the median, with the whole spread.
    const std::array<CellOutcome, 3> all = {out, second, third};
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t a = 0; a < 3; ++a)
        for (std::size_t b = a + 1; b < 3; ++b) {
            const double diff = std::abs(all[a].value - all[b].value);
            if (diff <= all[a].error + all[b].error + rounding_slack(all[a]) && diff < best) {
                best = diff;
                out.value = 0.5 * (all[a].value + all[b].value);
                out.error = std::max(all[a].error, all[b].error) + diff;
            }
        }
    if (best < std::numeric_limits<double>::infinity()) return;
    std::array<double, 3> v = {all[0].value, all[1].value, all[2].value};
    std::sort(v.begin(), v.end());
    out.value = v[1];
    out.error = (v[2] - v[0]) + std::max({all[0].error, all[1].error, all[2].error});
}

CellOutcome integrate_cell(RegionRule& rr, const ParamRect& cell, bool one_d, const QuadratureOptions& options,
                           std::vector<Region>& heap) {
    CellOutcome out = integrate_adaptive(rr, cell, one_d, options, options.max_regions_per_cell, heap);
    if (options.float_noise && std::isfinite(out.value))
        for (const Region& r : heap) out.float_noise += rr.noise(r.rect) + rr.jump_band(r);
    if (options.verify) verify_cell(rr, cell, one_d, options, heap, out);
    const double tol = cell_tolerance(out.value, options);
    out.converged = out.error <= tol;
    out.error_ratio = std::isfinite(out.value) ? out.error / tol : std::numeric_limits<double>::infinity();
    return out;
}

/// The cuts of [lo, hi] around the points' range [a, b] along one parameter:
/// the range widened by its own width each way (at least a 2^-20 of the
/// piece), clipped to the piece.
std::array<double, 4> cuts_around(double lo, double hi, double a, double b) {
    const double margin = std::max(b - a, 0x1p-20 * (hi - lo));
    return {lo, std::max(lo, a - margin), std::min(hi, b + margin), hi};
}

/// The piece integrated as usual; where it holds points and integrates to
/// zero, it is cut into 3 x 3 pieces at the points' range widened by its own
/// width (cuts_around), and each piece is treated the same way, so a sliver
/// of support narrow in either parameter gets pieces of its own scale.
void guided(RegionRule& rr, const ParamRect& r, const std::vector<std::array<double, 2>>& points, int depth,
            bool one_d, const QuadratureOptions& options, std::vector<Region>& heap, GuidedIntegral& sum) {
    // Whether the first rule sees the density at all decides; the piece that
    // it does see is then integrated in full (verified, with its float noise).
    const bool seen = integrate_adaptive(rr, r, one_d, options, options.max_regions_per_cell, heap).value != 0.0;
    if (points.empty() || seen || depth >= 16) {
        const CellOutcome o = integrate_cell(rr, r, one_d, options, heap);
        sum.value += o.value;
        sum.error += o.error;
        sum.float_noise += o.float_noise;
        return;
    }
    double u_min = r.u1, u_max = r.u0, v_min = r.v1, v_max = r.v0;
    for (const auto& p : points) {
        u_min = std::min(u_min, p[0]), u_max = std::max(u_max, p[0]);
        v_min = std::min(v_min, p[1]), v_max = std::max(v_max, p[1]);
    }
    const std::array<double, 4> us = cuts_around(r.u0, r.u1, u_min, u_max);
    const std::array<double, 4> vs = one_d ? std::array<double, 4>{r.v0, r.v0, r.v1, r.v1}
                                           : cuts_around(r.v0, r.v1, v_min, v_max);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            const ParamRect piece{us[i], us[i + 1], vs[j], vs[j + 1]};
            if (!(piece.u1 > piece.u0) || !(piece.v1 > piece.v0)) continue;
            std::vector<std::array<double, 2>> inside;
            for (const auto& p : points)
                if (p[0] >= piece.u0 && (p[0] < piece.u1 || (i == 2 && p[0] <= piece.u1)) && p[1] >= piece.v0 &&
                    (p[1] < piece.v1 || (j == 2 && p[1] <= piece.v1)))
                    inside.push_back(p);
            // A piece that is the whole rectangle again cannot narrow: stop.
            const bool same = piece.u0 == r.u0 && piece.u1 == r.u1 && piece.v0 == r.v0 && piece.v1 == r.v1;
            guided(rr, piece, same ? std::vector<std::array<double, 2>>{} : inside, depth + 1, one_d, options, heap, sum);
        }
}

/// The cut of `r` that partitioned() makes, if any: the axis and the pieces'
/// edges along it (2 or 3 pieces) around the pilot's densest cluster.
struct PilotCut {
    int axis = -1;
    std::vector<double> edges;
};

/// Along one axis: the run of consecutive points (sorted coordinates) whose
/// spacings are all under 1 / kPilotClusterDensity of an even spread's
/// (side / n), with the most points; kMinPilotCluster or more of them, cut
/// around it (its extent widened by itself each way, and by no less than
/// `resolution`, the float step of a sample there: points that round to one
/// float stand for its whole interval) where that leaves the cluster's piece
/// under half the side. Returns the share of the side the cluster's piece
/// keeps (1: no cut).
double cluster_cut(const std::vector<double>& c, double lo, double hi, double resolution, std::vector<double>& edges) {
    const double side = hi - lo;
    if (c.size() < kMinPilotCluster || !(side > 0.0) || !std::isfinite(side)) return 1.0;
    const double close = side / (kPilotClusterDensity * static_cast<double>(c.size()));
    std::size_t best_first = 0, best_count = 0;
    for (std::size_t i = 0; i < c.size();) {
        std::size_t j = i;
        while (j + 1 < c.size() && c[j + 1] - c[j] < close) ++j;
        if (j - i + 1 > best_count) best_first = i, best_count = j - i + 1;
        i = j + 1;
    }
    if (best_count < kMinPilotCluster) return 1.0;
    const double a = c[best_first], b = c[best_first + best_count - 1];
    const double margin = std::max(b - a, resolution);
    const std::array<double, 4> cuts = {lo, std::max(lo, a - margin), std::min(hi, b + margin), hi};
    const double kept = (cuts[2] - cuts[1]) / side;
    if (!(kept < 0.5)) return 1.0;
    edges = {lo};
    if (cuts[1] > lo) edges.push_back(cuts[1]);
    if (cuts[2] < hi) edges.push_back(cuts[2]);
    edges.push_back(hi);
    return kept;
}

/// Along one axis: the widest stretch of the side that holds no point (the
/// side's ends count as points); where it exceeds kPilotGapShare of the
/// side, the cut an eighth of the gap away from the points on each side that
/// has points (so a cluster's piece keeps a margin for its density's tails),
/// unless that eighth is under `resolution` (points that round to one float
/// stand for its whole interval: no narrower piece is meant). Returns the
/// gap's share of the side (0: no cut).
double gap_cut(const std::vector<double>& c, double lo, double hi, double resolution, double threshold,
               std::vector<double>& edges) {
    const double side = hi - lo;
    if (c.size() < 2 || !(side > 0.0) || !std::isfinite(side)) return 0.0;
    std::array<double, 2> gap{lo, c.front()};
    for (std::size_t k = 1; k <= c.size(); ++k) {
        const double a = c[k - 1], b = k == c.size() ? hi : c[k];
        if (b - a > gap[1] - gap[0]) gap = {a, b};
    }
    const double share = (gap[1] - gap[0]) / side;
    const double margin = (gap[1] - gap[0]) / 8.0;
    if (!(share > threshold) || !(margin >= resolution)) return 0.0;
    edges = {lo};
    if (gap[0] > lo) edges.push_back(gap[0] + margin);
    if (gap[1] < hi) edges.push_back(gap[1] - margin);
    edges.push_back(hi);
    return share;
}

/// `within`: whether `r` is a piece of a cell already cut, where 2 points
/// suffice to go on narrowing towards a cluster found in the cell.
PilotCut pilot_cut(const Binning& binning, const ParamRect& r, const std::vector<std::array<double, 2>>& points,
                   bool within) {
    PilotCut cut;
    double best = 1.0;
    if (points.size() < (within ? 2 : kMinPilotCluster)) return cut;
    // The float step of a sample, read at the points' mean.
    double um = 0.0, vm = 0.0;
    for (const auto& p : points) {
        um += p[0];
        vm += p[1];
    }
    um /= static_cast<double>(points.size());
    vm /= static_cast<double>(points.size());
    const double threshold = within ? kPilotGapShare : pilot_gap_share(points.size());
    for (int axis = 0; axis < binning.parameter_dimension(); ++axis) {
        const double lo = axis == 0 ? r.u0 : r.v0, hi = axis == 0 ? r.u1 : r.v1;
        std::vector<double> c;
        c.reserve(points.size());
        for (const auto& p : points) c.push_back(std::clamp(p[static_cast<std::size_t>(axis)], lo, hi));
        std::sort(c.begin(), c.end());  // both rules read the coordinates in order
        std::vector<double> edges;
        // A wide gap first (a cluster at a piece's edge, or two apart: the
        // gap's share as the share the cut removes), then a dense run.
        const double step = binning.float_resolution(axis, um, vm);
        const double resolution = std::isfinite(step) ? step : 0.0;
        const double gap = gap_cut(c, lo, hi, resolution, threshold, edges);
        const double kept = gap > 0.0 ? 1.0 - gap : cluster_cut(c, lo, hi, resolution, edges);
        if (kept < best) {
            best = kept;
            cut.axis = axis;
            cut.edges = std::move(edges);
        }
    }
    return cut;
}

/// The piece integrated as usual where its points form no cluster
/// (cluster_cut) along either parameter, or 16 cuts were made; otherwise cut
/// around the cluster that narrows most (pilot_cut) and each piece treated
/// the same way, so a cluster of points narrower than the rule's nodes ends
/// in a piece of its own scale.
void partitioned(const Binning& binning, RegionRule& rr, const ParamRect& r,
                 const std::vector<std::array<double, 2>>& points, int depth, bool one_d,
                 const QuadratureOptions& options, std::vector<Region>& heap, GuidedIntegral& sum) {
    const PilotCut cut = depth < 16 ? pilot_cut(binning, r, points, depth > 0) : PilotCut{};
    if (cut.axis < 0) {
        const CellOutcome o = integrate_cell(rr, r, one_d, options, heap);
        sum.value += o.value;
        sum.error += o.error;
        sum.float_noise += o.float_noise;
        ++sum.pieces;
        return;
    }
    const std::size_t a = static_cast<std::size_t>(cut.axis);
    for (std::size_t k = 0; k + 1 < cut.edges.size(); ++k) {
        ParamRect piece = r;
        (a == 0 ? piece.u0 : piece.v0) = cut.edges[k];
        (a == 0 ? piece.u1 : piece.v1) = cut.edges[k + 1];
        const bool last = k + 2 == cut.edges.size();
        std::vector<std::array<double, 2>> inside;
        for (const auto& p : points)
            if (p[a] >= cut.edges[k] && (p[a] < cut.edges[k + 1] || (last && p[a] <= cut.edges[k + 1])))
                inside.push_back(p);
        partitioned(binning, rr, piece, inside, depth + 1, one_d, options, heap, sum);
    }
}

/// One cell integrated by `walk` (guided or partitioned) over its points,
/// with the evaluations counted.
template <typename Walk>
GuidedIntegral walk_cell(const Binning& binning, const BatchPdf& pdf, const QuadratureOptions& options, Walk&& walk) {
    rule();
    RegionRule rr(binning, pdf, options.float_noise);
    std::vector<Region> heap;
    GuidedIntegral sum;
    walk(rr, binning.parameter_dimension() == 1, heap, sum);
    sum.evaluations = rr.evaluations;
    return sum;
}

}  // namespace

GuidedIntegral integrate_around(const Binning& binning, const ParamRect& cell,
                                std::span<const std::array<double, 2>> points, const BatchPdf& pdf,
                                const QuadratureOptions& options) {
    return walk_cell(binning, pdf, options, [&](RegionRule& rr, bool one_d, std::vector<Region>& heap, GuidedIntegral& sum) {
        guided(rr, cell, {points.begin(), points.end()}, 0, one_d, options, heap, sum);
    });
}

double pilot_gap_share(std::size_t n) {
    if (n == 0) return 1.0;
    const double k = static_cast<double>(n);
    return std::max(kPilotGapShare, -std::expm1(std::log(kPilotGapChance / (k + 1.0)) / k));
}

bool needs_pilot_partition(const Binning& binning, const ParamRect& cell, std::span<const std::array<double, 2>> points) {
    return pilot_cut(binning, cell, {points.begin(), points.end()}, false).axis >= 0;
}

GuidedIntegral integrate_partitioned(const Binning& binning, const ParamRect& cell,
                                     std::span<const std::array<double, 2>> points, const BatchPdf& pdf,
                                     const QuadratureOptions& options) {
    return walk_cell(binning, pdf, options, [&](RegionRule& rr, bool one_d, std::vector<Region>& heap, GuidedIntegral& sum) {
        partitioned(binning, rr, cell, {points.begin(), points.end()}, 0, one_d, options, heap, sum);
    });
}

double cell_tolerance(double probability, const QuadratureOptions& options) {
    const double n = static_cast<double>(std::max<uint64_t>(options.sample_count, 1));
    const double p = std::max(std::abs(probability), 1.0 / n);
    // The floor keeps the rule reachable in double precision for huge N.
    return std::max(options.accuracy_fraction * std::sqrt(p / n), 1e-13 * std::abs(probability));
}

CellIntegrals integrate_cells(const Binning& binning, const BatchPdf& pdf, const QuadratureOptions& options,
                              const ParallelFor& parallel_for) {
    const std::size_t cells = binning.cell_count();
    if (!binning.has_integration_pieces()) {
        std::vector<ParamRect> rects(cells);
        for (std::size_t c = 0; c < rects.size(); ++c) rects[c] = binning.cell_rect(c);
        return integrate_rects(binning, rects, pdf, options, parallel_for);
    }
    // Cells integrated in pieces (Binning::integration_pieces): each piece as
    // a cell of its own, then summed per cell (errors and float noise add).
    std::vector<ParamRect> pieces;
    std::vector<std::size_t> owner;
    for (std::size_t c = 0; c < cells; ++c)
        for (const ParamRect& r : binning.integration_pieces(c)) {
            pieces.push_back(r);
            owner.push_back(c);
        }
    const CellIntegrals in = integrate_rects(binning, pieces, pdf, options, parallel_for);
    CellIntegrals out;
    out.probability.assign(cells, 0.0);
    out.error.assign(cells, 0.0);
    if (options.float_noise) out.float_noise.assign(cells, 0.0);
    for (std::size_t k = 0; k < pieces.size(); ++k) {
        out.probability[owner[k]] += in.probability[k];
        out.error[owner[k]] += in.error[k];
        if (options.float_noise) out.float_noise[owner[k]] += in.float_noise[k];
    }
    for (std::size_t c = 0; c < cells; ++c) {
        out.total += out.probability[c];
        out.error_total += out.error[c];
        if (options.float_noise) out.float_noise_total += out.float_noise[c];
    }
    out.verification_mismatches = in.verification_mismatches;
    out.unconverged_cells = in.unconverged_cells;
    out.worst_error_ratio = in.worst_error_ratio;
    out.evaluations = in.evaluations;
    out.negative_values = in.negative_values;
    out.nonfinite_values = in.nonfinite_values;
    return out;
}

CellIntegrals integrate_rects(const Binning& binning, std::span<const ParamRect> rects, const BatchPdf& pdf,
                              const QuadratureOptions& options, const ParallelFor& parallel_for) {
    if (!pdf) throw std::invalid_argument("integrate_cells: no density");
    if (!(options.accuracy_fraction > 0.0)) throw std::invalid_argument("integrate_cells: accuracy fraction must be > 0");
    const std::size_t cells = rects.size();
    const bool one_d = binning.parameter_dimension() == 1;
    rule();  // build the node table before threads race to it

    // Blocks of consecutive cells; each block writes only its own entries.
    constexpr std::size_t kCellsPerBlock = 16;
    const std::size_t blocks = (cells + kCellsPerBlock - 1) / kCellsPerBlock;
    std::vector<CellOutcome> outcomes(cells);
    struct BlockStats {
        uint64_t evaluations = 0, negative = 0, nonfinite = 0;
    };
    std::vector<BlockStats> block_stats(blocks);
    const ParallelFor& run = parallel_for ? parallel_for : ParallelFor(serial_for);
    run(blocks, [&](std::size_t block) {
        RegionRule rr(binning, pdf, options.float_noise);
        std::vector<Region> heap;
        heap.reserve(options.max_regions_per_cell + 2);
        const std::size_t end = std::min(cells, (block + 1) * kCellsPerBlock);
        for (std::size_t c = block * kCellsPerBlock; c < end; ++c)
            outcomes[c] = integrate_cell(rr, rects[c], one_d, options, heap);
        block_stats[block] = {rr.evaluations, rr.negative, rr.nonfinite};
    });

    CellIntegrals out;
    out.probability.resize(cells);
    out.error.resize(cells);
    if (options.float_noise) out.float_noise.resize(cells);
    for (std::size_t c = 0; c < cells; ++c) {
        const CellOutcome& o = outcomes[c];
        out.probability[c] = o.value;
        out.error[c] = o.error;
        out.total += o.value;
        out.error_total += o.error;
        out.unconverged_cells += o.converged ? 0 : 1;
        out.verification_mismatches += o.mismatch ? 1 : 0;
        if (options.float_noise) {
            out.float_noise[c] = o.float_noise;
            out.float_noise_total += o.float_noise;
        }
        if (!(o.error_ratio <= out.worst_error_ratio)) out.worst_error_ratio = o.error_ratio;
    }
    for (const BlockStats& b : block_stats) {
        out.evaluations += b.evaluations;
        out.negative_values += b.negative;
        out.nonfinite_values += b.nonfinite;
    }
    return out;
}

}  // namespace warpcheck::chi2

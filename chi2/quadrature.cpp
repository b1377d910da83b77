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
    double error() const { return err_u + err_v; }
};

bool less_error(const Region& a, const Region& b) { return a.error() < b.error(); }

/// Evaluates the tensor rule on rectangles of one binning, reusing its buffers.
class RegionRule {
public:
    RegionRule(const Binning& binning, const BatchPdf& pdf) : binning_(binning), pdf_(pdf) {
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
        pdf_(points_, values_);
        evaluations += values_.size();

        // Weight by the measure density, screening for values that make no density.
        bool finite = true;
        for (std::size_t k = 0; k < values_.size(); ++k) {
            const double f = values_[k];
            if (!std::isfinite(f)) {
                ++nonfinite;
                finite = false;
            } else if (f < 0.0) {
                ++negative;
            }
            const std::size_t i = one_d ? k : k % kNodes, j = one_d ? 0 : k / kNodes;
            values_[k] = f * binning_.jacobian(us[i], vs[j]);
        }
        Region out{r, 0.0, 0.0, 0.0};
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

private:
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
};

struct CellOutcome {
    double value = 0.0;
    double error = 0.0;
    bool converged = true;
    double error_ratio = 0.0;
};

CellOutcome integrate_cell(RegionRule& rr, const ParamRect& cell, bool one_d, const QuadratureOptions& options,
                           std::vector<Region>& heap) {
    heap.clear();
    heap.push_back(rr.evaluate(cell));
    double value = heap.front().value, error = heap.front().error();
    while (std::isfinite(value) && !(error <= cell_tolerance(value, options)) &&
           heap.size() < options.max_regions_per_cell) {
        std::pop_heap(heap.begin(), heap.end(), less_error);
        const Region worst = heap.back();
        heap.pop_back();
        ParamRect a = worst.rect, b = worst.rect;
        if (one_d || worst.err_u >= worst.err_v) {
            a.u1 = b.u0 = 0.5 * (worst.rect.u0 + worst.rect.u1);
        } else {
            a.v1 = b.v0 = 0.5 * (worst.rect.v0 + worst.rect.v1);
        }
        for (const ParamRect& half : {a, b}) {
            heap.push_back(rr.evaluate(half));
            std::push_heap(heap.begin(), heap.end(), less_error);
        }
        // Re-sum rather than update, so that cancellation cannot drift.
        value = 0.0;
        error = 0.0;
        for (const Region& r : heap) {
            value += r.value;
            error += r.error();
        }
    }
    CellOutcome out;
    out.value = value;
    out.error = error;
    const double tol = cell_tolerance(value, options);
    out.converged = error <= tol;
    out.error_ratio = std::isfinite(value) ? error / tol : std::numeric_limits<double>::infinity();
    return out;
}

}  // namespace

double cell_tolerance(double probability, const QuadratureOptions& options) {
    const double n = static_cast<double>(std::max<uint64_t>(options.sample_count, 1));
    const double p = std::max(std::abs(probability), 1.0 / n);
    // The floor keeps the rule reachable in double precision for huge N.
    return std::max(options.accuracy_fraction * std::sqrt(p / n), 1e-13 * std::abs(probability));
}

CellIntegrals integrate_cells(const Binning& binning, const BatchPdf& pdf, const QuadratureOptions& options,
                              const ParallelFor& parallel_for) {
    std::vector<ParamRect> rects(binning.cell_count());
    for (std::size_t c = 0; c < rects.size(); ++c) rects[c] = binning.cell_rect(c);
    return integrate_rects(binning, rects, pdf, options, parallel_for);
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
        RegionRule rr(binning, pdf);
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
    for (std::size_t c = 0; c < cells; ++c) {
        const CellOutcome& o = outcomes[c];
        out.probability[c] = o.value;
        out.error[c] = o.error;
        out.total += o.value;
        out.error_total += o.error;
        out.unconverged_cells += o.converged ? 0 : 1;
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

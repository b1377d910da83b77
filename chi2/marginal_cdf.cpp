#include "chi2/marginal_cdf.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace warpcheck::chi2 {

double MarginalCdf::operator()(double t) const {
    if (std::isnan(t)) return t;
    if (!(t > edges.front())) return 0.0;
    if (!(t < edges.back())) return 1.0;
    // Strips are uniform in the parameter up to float rounding of their edges:
    // guess the strip arithmetically, then step to the exact one.
    const std::size_t last = edges.size() - 2;
    const double guess = (t - edges.front()) / (edges.back() - edges.front()) * static_cast<double>(last + 1);
    std::size_t k = std::min(last, static_cast<std::size_t>(std::max(0.0, guess)));
    while (k > 0 && t < edges[k]) --k;
    while (k < last && t >= edges[k + 1]) ++k;
    const double w = (t - edges[k]) / (edges[k + 1] - edges[k]);
    return cdf[k] + w * (cdf[k + 1] - cdf[k]);
}

Binning strip_binning(const Domain& domain, int axis, int strips, const BinResolution& line) {
    BinResolution r = line;
    r.first = axis == 0 ? strips : 1;
    r.second = axis == 0 ? 1 : strips;
    const Binning b(domain, r);
    if (axis == 1 && b.parameter_dimension() != 2) throw std::invalid_argument("a 1D domain has one parameter");
    return b;
}

MarginalCdf tabulate_marginal_cdf(const Binning& strips, int axis, const BatchPdf& pdf,
                                  const QuadratureOptions& options, const ParallelFor& parallel_for) {
    const CellIntegrals in = integrate_cells(strips, pdf, options, parallel_for);
    MarginalCdf m;
    m.axis = axis;
    m.total = in.total;
    m.quadrature_error = in.error_total / in.total;
    m.unconverged_strips = in.unconverged_cells;
    m.evaluations = in.evaluations;
    m.bad_values = in.negative_values + in.nonfinite_values;
    const std::size_t n = strips.cell_count();
    m.edges.resize(n + 1);
    m.cdf.resize(n + 1);
    double sum = 0.0;
    for (std::size_t c = 0; c < n; ++c) {
        const ParamRect r = strips.cell_rect(c);
        m.edges[c] = axis == 0 ? r.u0 : r.v0;
        m.edges[c + 1] = axis == 0 ? r.u1 : r.v1;
        m.cdf[c] = sum / in.total;
        sum += in.probability[c];
    }
    m.cdf[n] = 1.0;
    // Linear interpolation on the strips of width h errs by ~h^2 |F''| / 8; on
    // strips of width 2h (pairs) the error at the pair's midpoint is measured
    // exactly, |F(mid) - (F(a) + F(b)) / 2|, and a quarter of it estimates the
    // error on the strips used. Where F is linear within each pair (a
    // piecewise-constant density with edges on the strips' edges) it is 0, as
    // the true error is; where F bends sharply within a strip it is large.
    for (std::size_t k = 1; k < n; k += 2)
        m.interpolation_error =
            std::max(m.interpolation_error, std::abs(m.cdf[k] - 0.5 * (m.cdf[k - 1] + m.cdf[k + 1])) / 4.0);
    if (!std::isfinite(m.total) || !(m.total > 0.0)) m.interpolation_error = std::nan("");
    return m;
}

}  // namespace warpcheck::chi2

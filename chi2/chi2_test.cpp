#include "chi2/chi2_test.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <utility>

namespace warpcheck::chi2 {

namespace {

std::string format_number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

std::string count_of(uint64_t n, const char* noun) {
    return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

}  // namespace

std::size_t histogram_count(uint64_t work_items, std::size_t cells) {
    const uint64_t cap = std::clamp<uint64_t>((uint64_t{1} << 22) / std::max<std::size_t>(cells, 1), 1, 64);
    return static_cast<std::size_t>(std::max<uint64_t>(std::min(work_items, cap), 1));
}

Histogram sample_histogram(const Binning& binning, uint64_t samples, std::size_t chunk_size,
                           const SampleChunk& generate, std::span<const unsigned char> zero_cells,
                           const ParallelFor& parallel_for) {
    if (chunk_size == 0) throw std::invalid_argument("sample_histogram: chunk size must be > 0");
    if (!generate) throw std::invalid_argument("sample_histogram: no sampler");
    const std::size_t cells = binning.cell_count();
    const uint64_t chunks = (samples + chunk_size - 1) / chunk_size;
    const std::size_t lanes = histogram_count(chunks, cells);
    std::vector<Histogram> lane_hist(lanes);
    const ParallelFor& run = parallel_for ? parallel_for : ParallelFor(serial_for);
    run(lanes, [&](std::size_t lane) {
        Histogram& h = lane_hist[lane];
        h.counts.assign(cells, 0);
        std::vector<SamplePoint> buffer(chunk_size);
        for (uint64_t chunk = lane; chunk < chunks; chunk += lanes) {
            const uint64_t begin = chunk * chunk_size;
            const auto n = static_cast<std::size_t>(std::min<uint64_t>(chunk_size, samples - begin));
            const std::span<SamplePoint> out(buffer.data(), n);
            generate(static_cast<std::size_t>(chunk), out);
            binning.bin(std::span<const SamplePoint>(out), h, zero_cells);
        }
    });
    Histogram total;
    total.counts.assign(cells, 0);
    for (const Histogram& h : lane_hist) total.merge(h);
    return total;
}

std::vector<unsigned char> zero_cells_of(const CellIntegrals& integrals) {
    std::vector<unsigned char> zero(integrals.probability.size());
    for (std::size_t i = 0; i < zero.size(); ++i) zero[i] = integrals.probability[i] <= 0.0 ? 1 : 0;
    return zero;
}

namespace {

/// The probability within half a float spacing of an interval's ends. The
/// density is a float function: the quadrature's nodes there round onto the end
/// points, where a half-open interval's density is 0, so that much mass may be
/// missing from the integral (3e-5 of [0.999, 1.001], whose ends are floats
/// 1.2e-7 apart and 0.002 from each other). Estimated from the end cells'
/// average density; on other domains the band is below 2^-24 of the unit scale.
double boundary_band_mass(const Binning& binning, const CellIntegrals& q) {
    if (!binning.domain().is<Interval>() || q.probability.empty()) return 0.0;
    double band = 0.0;
    for (const std::size_t cell : {std::size_t{0}, q.probability.size() - 1}) {
        const ParamRect r = binning.cell_rect(cell);
        const double end = cell == 0 ? r.u0 : r.u1;
        const auto f = static_cast<float>(end);
        const double spacing = static_cast<double>(std::nextafter(std::abs(f), INFINITY)) - std::abs(f);
        band += std::max(q.probability[cell], 0.0) / (r.u1 - r.u0) * spacing;
    }
    return band;
}

}  // namespace

namespace {

/// Probability within kEdgeFloatSteps float steps of a sample's coordinates of
/// each interior cell edge, added to both cells that share it: the cell
/// average density next to the edge (the larger side's) times the width of
/// those float steps in the edge's parameter (Binning::float_resolution).
std::vector<double> edge_bands(const Binning& b, std::span<const double> probability) {
    const int cols = b.cols(), rows = b.rows();
    std::vector<double> band(probability.size(), 0.0);
    const auto cell = [cols](int row, int col) { return static_cast<std::size_t>(row) * cols + col; };
    const auto density = [&](std::size_t c, int axis) {
        const ParamRect r = b.cell_rect(c);
        const double width = axis == 0 ? r.u1 - r.u0 : r.v1 - r.v0;
        return std::max(probability[c], 0.0) / width;
    };
    const bool wraps = b.domain().azimuthal();
    for (int row = 0; row < rows; ++row)
        for (int col = 0; col < cols; ++col) {
            const std::size_t c = cell(row, col);
            const ParamRect r = b.cell_rect(c);
            // The edge on the high side of u (wrapping round phi) and of v.
            if (col + 1 < cols || (wraps && cols > 1)) {
                const std::size_t n = cell(row, (col + 1) % cols);
                const double res = b.float_resolution(0, r.u1, 0.5 * (r.v0 + r.v1));
                const double m = kEdgeFloatSteps * res * std::max(density(c, 0), density(n, 0));
                band[c] += m;
                band[n] += m;
            }
            if (row + 1 < rows) {
                const std::size_t n = cell(row + 1, col);
                const double res = b.float_resolution(1, 0.5 * (r.u0 + r.u1), r.v1);
                const double m = kEdgeFloatSteps * res * std::max(density(c, 1), density(n, 1));
                band[c] += m;
                band[n] += m;
            }
        }
    return band;
}

void add_failures_without_level(Chi2Outcome& out, const Binning& binning, const Chi2Options& options) {
    const Histogram& h = out.histogram;
    const CellIntegrals& q = out.integrals;
    const std::string where = binning.domain().describe();
    if (h.nan > 0)
        out.failures.push_back(h.nan == out.samples ? "every sample has NaN coordinates"
                                                    : count_of(h.nan, "sample") + " with NaN coordinates");
    if (h.outside > 0)
        out.failures.push_back(count_of(h.outside, "sample") + " outside the " + where + " (beyond the tolerance " +
                               format_number(kDomainTolerance) + ")");
    if (q.nonfinite_values > 0)
        out.failures.push_back("the density is NaN or infinite at " + count_of(q.nonfinite_values, "quadrature node"));
    if (q.negative_values > 0)
        out.failures.push_back("the density is negative at " + count_of(q.negative_values, "quadrature node"));
    // The rule: |integral - 1| within the float rounding of the values
    // (2^-20), the quadrature's verified bound, the band at an interval's ends
    // and, unless strict, the density's own float noise (quadrature.h).
    const double base = options.integral_tolerance + q.error_total + boundary_band_mass(binning, q);
    out.float_noise_allowance = options.strict ? 0.0 : kFloatNoiseFactor * q.float_noise_total;
    out.integral_tolerance = base + out.float_noise_allowance;
    const double off = std::abs(q.total - 1.0);
    out.float_noise_used = off > base && off <= out.integral_tolerance;
    if (!(off <= out.integral_tolerance)) {
        std::string why = "the density integrates to " + format_number(q.total) + " over the " + where +
                          ", not 1 (tolerance " + format_number(out.integral_tolerance) + ")";
        if (options.strict && off <= base + kFloatNoiseFactor * q.float_noise_total)
            why += "; within the density's float-noise allowance " + format_number(kFloatNoiseFactor * q.float_noise_total) +
                   ", not granted under --strict";
        out.failures.push_back(why);
    }
}

/// Expected counts, their bands and residuals; hits in cells of zero probability.
void expectations(Chi2Outcome& out, const Binning& binning, std::vector<double>& observed) {
    const Histogram& h = out.histogram;
    const CellIntegrals& q = out.integrals;
    const std::size_t cells = q.probability.size();
    const double n = static_cast<double>(out.samples);
    const std::vector<double> edges = edge_bands(binning, q.probability);
    out.expected.resize(cells);
    out.residual.resize(cells);
    out.band.resize(cells);
    observed.resize(cells);
    for (std::size_t i = 0; i < cells; ++i) {
        observed[i] = static_cast<double>(h.counts[i]);
        out.expected[i] = n * q.probability[i];
        const double noise = q.float_noise.empty() ? 0.0 : q.float_noise[i];
        out.band[i] = n * (q.error[i] + noise + edges[i]);
        out.edge_band_total += edges[i];
        const double e = out.expected[i];
        out.residual[i] = e > 0.0 ? (observed[i] - e) / std::sqrt(e) : std::numeric_limits<double>::quiet_NaN();
        if (q.probability[i] <= 0.0) {
            ++out.zero_expected_cells;
            out.zero_expected_hits += h.counts[i];
        }
    }
}

}  // namespace

Chi2Outcome evaluate_chi2(const Binning& binning, Histogram histogram, CellIntegrals integrals, uint64_t samples,
                          const Chi2Options& options) {
    const std::size_t cells = binning.cell_count();
    if (histogram.counts.size() != cells || integrals.probability.size() != cells)
        throw std::invalid_argument("evaluate_chi2: histogram or integrals of another binning");
    Chi2Outcome out;
    out.samples = samples;
    binning.spread_poles(histogram);
    out.histogram = std::move(histogram);
    out.integrals = std::move(integrals);
    add_failures_without_level(out, binning, options);
    std::vector<double> observed;
    expectations(out, binning, observed);
    const Histogram& h = out.histogram;
    const double n = static_cast<double>(samples);
    if (out.zero_expected_hits > 0)
        out.failures.push_back(count_of(out.zero_expected_hits, "sample") +
                               " in cells where the density integrates to zero (and is zero at the samples looked at there)");
    // Samples exactly on the boundary in zero-density cells (set aside by the
    // binning): a float warp reaches the boundary from exact input edges, each
    // with probability 2^-24 per sample, so a few are expected. Far more than
    // 16 edges' worth means the warp puts real mass where its density has none.
    out.boundary_hits = h.on_boundary;
    const double boundary_cap = 10.0 + 16.0 * n * 0x1p-24;
    if (static_cast<double>(h.on_boundary) > boundary_cap)
        out.failures.push_back(count_of(h.on_boundary, "sample") +
                               " on the domain's boundary where the density integrates to zero (more than the " +
                               format_number(boundary_cap) + " that exact input edges can explain)");

    out.pearson = pearson_test(observed, out.expected, out.band, options.min_expected);
    if (out.pearson.dof < 1)
        out.errors.push_back("fewer than two cells remain after pooling: too few samples for any degree of freedom");
    else if (!std::isfinite(out.pearson.statistic))
        out.failures.push_back("the chi-square statistic is not finite");
    else if (!std::isfinite(out.pearson.p_value))
        out.failures.push_back("the chi-square p-value is not finite");
    return out;
}

Chi2Outcome run_chi2_test(const Binning& binning, uint64_t samples, const SampleChunk& generate, const BatchPdf& pdf,
                          const Chi2Options& options, const ParallelFor& parallel_for) {
    const SampleHistogram histogram = [&](std::span<const unsigned char> zero) {
        return sample_histogram(binning, samples, options.chunk_size, generate, zero, parallel_for);
    };
    return run_chi2_test(binning, samples, histogram, pdf, options, parallel_for);
}

namespace {

/// Cell c of `q` integrated again as `g` (value, bound, float noise), totals kept.
void replace_cell(CellIntegrals& q, std::size_t c, const GuidedIntegral& g) {
    q.total += g.value - q.probability[c];
    q.error_total += g.error - q.error[c];
    q.probability[c] = g.value;
    q.error[c] = g.error;
    if (!q.float_noise.empty()) {
        q.float_noise_total += g.float_noise - q.float_noise[c];
        q.float_noise[c] = g.float_noise;
    }
}

/// Settles cell c of q against its pilot-guided integral g (refine_by_pilot).
void apply_guided(CellIntegrals& q, std::size_t c, const GuidedIntegral& g, const QuadratureOptions& qo,
                  PilotRefinement& out) {
    const double noise = q.float_noise.empty() ? 0.0 : q.float_noise[c];
    const double slack = noise + g.float_noise + 0x1p-20 * std::abs(g.value);
    // Within both bounds the cell's first value stands (the pieces saw
    // what its nodes saw); beyond them, the pieces, placed where the
    // pilot's mass is, saw what the nodes stepped over. The slack is
    // what verify_cell grants two node sets of one float density (a float
    // pdf's values differ between two sets of points by its float noise,
    // and each sum rounds by 2^-20 of the value), with both sets' noise,
    // since both were measured.
    if (!std::isfinite(g.value)) return;
    if (std::abs(g.value - q.probability[c]) <= g.error + q.error[c] + slack) {
        // Two estimates of one integral that agree within their bounds:
        // where the first missed the accuracy rule (its nodes straddled a
        // jump or sliver they could not resolve in their budget, such as
        // the edge of an environment map's bright pixel a 1/1000 of the
        // cell inside it) and the pieces' bound is tighter, the pieces'
        // is kept, since a bound the agreement test did not contradict and
        // a smaller one give the smaller band (and the power that comes
        // with it); a first integral that met the rule stands.
        if (q.error[c] > cell_tolerance(q.probability[c], qo) && g.error < q.error[c]) {
            replace_cell(q, c, g);
            ++out.cells_sharpened;
        }
        return;
    }
    out.missed_mass += g.value - q.probability[c];
    replace_cell(q, c, g);
    ++out.cells_changed;
}

}  // namespace

std::size_t reintegrate_missed_support(const Binning& binning, const Histogram& hist, const BatchPdf& pdf,
                                       const QuadratureOptions& qo, CellIntegrals& q) {
    if (hist.zero_cell_points.empty()) return 0;
    std::vector<DomainPoint> points;
    for (const Histogram::CellPoint& p : hist.zero_cell_points) points.push_back(p.point);
    std::vector<double> density(points.size());
    pdf(points, density);
    q.evaluations += points.size();
    std::vector<std::vector<std::array<double, 2>>> at(q.probability.size());
    for (std::size_t k = 0; k < points.size(); ++k) {
        const std::size_t c = hist.zero_cell_points[k].cell;
        if (!(density[k] > 0.0) || q.probability[c] > 0.0) continue;
        // The sample's parameters, clamped into its cell (it may lie within
        // the binning's tolerance outside it).
        const ParamRect r = binning.cell_rect(c);
        std::array<double, 2> uv = binning.parameters_of(points[k]);
        uv[0] = std::clamp(uv[0], r.u0, r.u1);
        uv[1] = std::clamp(uv[1], r.v0, r.v1);
        at[c].push_back(uv);
    }
    // At most kMaxReintegratedCells, those with the most such samples first:
    // a guided integration cuts down towards its samples (16 levels), and a
    // sampler that lands in hundreds of cells where its density is zero
    // (samples spilling beyond the pdf's support) would pay it hundreds of
    // times for a verdict the first cells already decide; cells of equal
    // probability, integrated where a pilot found their mass, leave a
    // correct sampler few such cells (the sliver light of tests/hard: none).
    std::vector<std::size_t> order;
    for (std::size_t c = 0; c < at.size(); ++c)
        if (!at[c].empty()) order.push_back(c);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return hist.counts[a] > hist.counts[b]; });
    if (order.size() > kMaxReintegratedCells) order.resize(kMaxReintegratedCells);
    std::sort(order.begin(), order.end());
    std::size_t redone = 0;
    for (std::size_t c : order) {
        const GuidedIntegral g = integrate_around(binning, binning.cell_rect(c), at[c], pdf, qo);
        replace_cell(q, c, g);
        q.evaluations += g.evaluations;
        ++redone;
    }
    return redone;
}

PilotRefinement refine_by_pilot(const Binning& binning, std::span<const SamplePoint> pilot, const BatchPdf& pdf,
                                const QuadratureOptions& qo, CellIntegrals& q, const ParallelFor& parallel_for) {
    PilotRefinement out;
    // Each pilot point's cell and parameters, in blocks on the executor; then
    // dealt to the cells in the pilot's order.
    constexpr std::size_t kBlock = 4096;
    std::vector<std::ptrdiff_t> cell_of(pilot.size(), -1);
    std::vector<std::array<double, 2>> params(pilot.size());
    parallel_for((pilot.size() + kBlock - 1) / kBlock, [&](std::size_t b) {
        for (std::size_t i = b * kBlock; i < std::min(pilot.size(), (b + 1) * kBlock); ++i) {
            const DomainPoint p{pilot[i][0], pilot[i][1], pilot[i][2]};
            const std::ptrdiff_t c = binning.cell_of(p);
            if (c < 0 || static_cast<std::size_t>(c) >= q.probability.size()) continue;
            const ParamRect r = binning.cell_rect(static_cast<std::size_t>(c));
            std::array<double, 2> uv = binning.parameters_of(p);
            if (!std::isfinite(uv[0]) || !std::isfinite(uv[1])) continue;
            params[i] = {std::clamp(uv[0], r.u0, r.u1), std::clamp(uv[1], r.v0, r.v1)};
            cell_of[i] = c;
        }
    });
    std::vector<std::vector<std::array<double, 2>>> at(q.probability.size());
    for (std::size_t i = 0; i < pilot.size(); ++i)
        if (cell_of[i] >= 0) at[static_cast<std::size_t>(cell_of[i])].push_back(params[i]);
    // Each cell's pieces with the pilot points inside them, kept for the
    // cells that call for a partition.
    struct Cut {
        std::size_t cell = 0;
        std::vector<ParamRect> pieces;
        std::vector<std::vector<std::array<double, 2>>> inside;
    };
    // Decided per cell on the executor (each cell's points sorted along both
    // parameters: a tenth of a smooth warp's check time when it ran serially),
    // then gathered in cell order, so the cuts do not depend on the threads.
    std::vector<Cut> candidates(at.size());
    std::vector<unsigned char> needed(at.size(), 0);
    parallel_for(at.size(), [&](std::size_t c) {
        if (at[c].empty()) return;
        Cut& k = candidates[c];
        k = {c, binning.integration_pieces(c), {}};
        for (const ParamRect& piece : k.pieces) {
            std::vector<std::array<double, 2>>& in = k.inside.emplace_back();
            for (const auto& p : at[c])
                if (p[0] >= piece.u0 && p[0] <= piece.u1 && p[1] >= piece.v0 && p[1] <= piece.v1) in.push_back(p);
            if (!needed[c] && needs_pilot_partition(binning, piece, in)) needed[c] = 1;
        }
    });
    std::vector<Cut> cuts;
    for (std::size_t c = 0; c < at.size(); ++c)
        if (needed[c]) cuts.push_back(std::move(candidates[c]));
    std::vector<GuidedIntegral> redone(cuts.size());
    parallel_for(cuts.size(), [&](std::size_t k) {
        for (std::size_t i = 0; i < cuts[k].pieces.size(); ++i) {
            const GuidedIntegral g = integrate_partitioned(binning, cuts[k].pieces[i], cuts[k].inside[i], pdf, qo);
            redone[k].value += g.value;
            redone[k].error += g.error;
            redone[k].float_noise += g.float_noise;
            redone[k].evaluations += g.evaluations;
            redone[k].pieces += g.pieces;
        }
    });
    out.cells_cut = cuts.size();
    for (std::size_t k = 0; k < cuts.size(); ++k) {
        q.evaluations += redone[k].evaluations;
        apply_guided(q, cuts[k].cell, redone[k], qo, out);
    }
    return out;
}

Chi2Outcome run_chi2_test(const Binning& binning, uint64_t samples, const SampleHistogram& histogram,
                          const BatchPdf& pdf, const Chi2Options& options, const ParallelFor& parallel_for) {
    QuadratureOptions qo;
    qo.sample_count = samples;
    qo.accuracy_fraction = options.accuracy_fraction;
    qo.max_regions_per_cell = options.max_regions_per_cell;
    qo.verify = true;
    qo.float_noise = true;
    using Clock = std::chrono::steady_clock;
    const auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
    const auto start = Clock::now();
    CellIntegrals integrals = integrate_cells(binning, pdf, qo, parallel_for);
    PilotRefinement refined;
    if (!options.pilot.empty()) refined = refine_by_pilot(binning, options.pilot, pdf, qo, integrals, parallel_for);
    double integration = since(start);
    const auto sampling_start = Clock::now();
    Histogram hist = histogram(zero_cells_of(integrals));
    double sampling = since(sampling_start);
    // Samples where the cubature saw no density: look there again, and bin
    // again with the corrected cells if any was missed.
    const auto redo_start = Clock::now();
    const std::size_t redone = reintegrate_missed_support(binning, hist, pdf, qo, integrals);
    integration += since(redo_start);
    if (redone > 0) {
        const auto again = Clock::now();
        hist = histogram(zero_cells_of(integrals));
        sampling += since(again);
    }
    const auto statistics_start = Clock::now();
    Chi2Outcome out = evaluate_chi2(binning, std::move(hist), std::move(integrals), samples, options);
    out.reintegrated_cells = redone;
    out.pilot_refinement = refined;
    out.integration_seconds = integration;
    out.sampling_seconds = sampling;
    out.statistics_seconds = since(statistics_start);
    return out;
}

LocalResidual largest_band_residual(const Chi2Outcome& o, uint64_t samples, const ParallelFor& parallel_for) {
    std::vector<double> lower(o.expected.size()), upper(o.expected.size());
    for (std::size_t i = 0; i < lower.size(); ++i) {
        lower[i] = std::max(0.0, o.expected[i] - o.band[i]);
        upper[i] = o.expected[i] + o.band[i];
    }
    return largest_cell_residual(o.histogram.counts, o.expected, lower, upper, samples, parallel_for);
}

}  // namespace warpcheck::chi2

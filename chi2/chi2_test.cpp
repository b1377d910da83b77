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

Chi2Outcome evaluate_chi2(const Binning& binning, Histogram histogram, CellIntegrals integrals, uint64_t samples,
                          const Chi2Options& options) {
    const std::size_t cells = binning.cell_count();
    if (histogram.counts.size() != cells || integrals.probability.size() != cells)
        throw std::invalid_argument("evaluate_chi2: histogram or integrals of another binning");
    Chi2Outcome out;
    out.samples = samples;
    out.histogram = std::move(histogram);
    out.integrals = std::move(integrals);
    const Histogram& h = out.histogram;
    const CellIntegrals& q = out.integrals;
    const std::string where = binning.domain().describe();

    // Failures that need no significance level.
    if (h.nan > 0) out.failures.push_back(count_of(h.nan, "sample") + " with NaN coordinates");
    if (h.outside > 0)
        out.failures.push_back(count_of(h.outside, "sample") + " outside the " + where + " (beyond the tolerance " +
                               format_number(kDomainTolerance) + ")");
    if (q.nonfinite_values > 0)
        out.failures.push_back("the density is NaN or infinite at " + count_of(q.nonfinite_values, "quadrature node"));
    if (q.negative_values > 0)
        out.failures.push_back("the density is negative at " + count_of(q.negative_values, "quadrature node"));
    out.integral_tolerance = options.integral_tolerance + q.error_total + boundary_band_mass(binning, q);
    if (!(std::abs(q.total - 1.0) <= out.integral_tolerance))
        out.failures.push_back("the density integrates to " + format_number(q.total) + " over the " + where +
                               ", not 1 (tolerance " + format_number(out.integral_tolerance) + ")");

    out.expected.resize(cells);
    out.residual.resize(cells);
    std::vector<double> observed(cells);
    const double n = static_cast<double>(samples);
    for (std::size_t i = 0; i < cells; ++i) {
        observed[i] = static_cast<double>(h.counts[i]);
        out.expected[i] = n * q.probability[i];
        const double e = out.expected[i];
        out.residual[i] = e > 0.0 ? (observed[i] - e) / std::sqrt(e) : std::numeric_limits<double>::quiet_NaN();
        if (q.probability[i] <= 0.0) {
            ++out.zero_expected_cells;
            out.zero_expected_hits += h.counts[i];
        }
    }
    if (out.zero_expected_hits > 0)
        out.failures.push_back(count_of(out.zero_expected_hits, "sample") +
                               " in cells where the density integrates to zero");
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

    if (q.unconverged_cells > 0)
        out.errors.push_back("quadrature missed the accuracy rule in " + count_of(q.unconverged_cells, "cell") +
                             " (worst error " + format_number(q.worst_error_ratio) +
                             " times the allowance); the density may be discontinuous or singular inside a cell");

    out.pearson = pearson_test(observed, out.expected, options.min_expected);
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

Chi2Outcome run_chi2_test(const Binning& binning, uint64_t samples, const SampleHistogram& histogram,
                          const BatchPdf& pdf, const Chi2Options& options, const ParallelFor& parallel_for) {
    QuadratureOptions qo;
    qo.sample_count = samples;
    qo.accuracy_fraction = options.accuracy_fraction;
    qo.max_regions_per_cell = options.max_regions_per_cell;
    using Clock = std::chrono::steady_clock;
    const auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
    const auto start = Clock::now();
    CellIntegrals integrals = integrate_cells(binning, pdf, qo, parallel_for);
    const double integration = since(start);
    const auto sampling_start = Clock::now();
    const std::vector<unsigned char> zero = zero_cells_of(integrals);
    Histogram hist = histogram(zero);
    const double sampling = since(sampling_start);
    const auto statistics_start = Clock::now();
    Chi2Outcome out = evaluate_chi2(binning, std::move(hist), std::move(integrals), samples, options);
    out.integration_seconds = integration;
    out.sampling_seconds = sampling;
    out.statistics_seconds = since(statistics_start);
    return out;
}

}  // namespace warpcheck::chi2

// The whole chi-square goodness-of-fit test: expected counts by quadrature,
// the observed histogram from chunked samples, then the non-statistical
// failures (NaN or outside samples, samples where the density is zero, a
// density that does not integrate to 1) and Pearson's statistic and p-value.
//
// The test does not decide pass/fail on the p-value: that takes the level
// corrected for all tests of a run (see multiple_testing.h), which the caller
// applies.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "chi2/binning.h"
#include "chi2/domain.h"
#include "chi2/local_residual.h"
#include "chi2/parallel.h"
#include "chi2/pearson.h"
#include "chi2/quadrature.h"

namespace warpcheck::chi2 {

/// How far the density's total integral may be from 1, either way, beyond the
/// quadrature's own error bound (which is added): the float rounding of the
/// density values, up to 16 ulps (2^-20 relative) if systematic. A scale error
/// larger than that is a bug, and it has to be a separate test: a normalisation
/// error d moves Pearson's statistic by only about N d^2 (= 1 for d = 1e-3 at
/// 10^6 samples), so 1/pi typed as 0.318f (d = 9.7e-4) passes chi-square.
inline constexpr double kIntegralTolerance = 0x1p-20;

/// The normalisation rule grants a float density twice its float noise (the
/// integral of its change over one float step of each argument, summed over
/// the arguments; chi2/quadrature.h): an expression that rounds its
/// intermediates and constants at its arguments' scale (1 + g^2 against
/// 2 g cos theta, a direction normalised in float) errs by about one such
/// step. Measured on Henyey-Greenstein's textbook float form over 48 random
/// directions, g = 0.9 to 0.995: the integral's deviation reached 0.79 of the
/// noise (0.95 with the same formula in double about a float-normalised
/// direction), while a smooth density's noise is ~1e-7, so a 5e-5 error in a
/// constant still fails.
inline constexpr double kFloatNoiseFactor = 2.0;

/// How many float steps of a sample's coordinates each cell edge is uncertain
/// by: one for the warp's own rounding (a correct float warp's CDF at a float's
/// rounding boundary stays within a fraction of one float's mass of the ideal:
/// 0.31 measured for pbrt's cone cos = (1 - u) + u cos_max, 0.006 for
/// 1 - u (1 - cos_max), 0.5 for a sampler that rounds down) and half a float
/// for an edge that falls inside a float's rounding interval.
inline constexpr double kEdgeFloatSteps = 1.5;

/// A sample point as warps produce it: float coordinates, unused ones 0.
using SamplePoint = std::array<float, 3>;

struct Chi2Options {
    BinResolution resolution;
    double min_expected = kMinExpectedCount;
    double accuracy_fraction = 0.01;  ///< f of the accuracy rule (quadrature.h)
    double integral_tolerance = kIntegralTolerance;
    /// Samples per chunk. Fixed, so chunk boundaries (and each chunk's random
    /// stream) do not depend on the thread count.
    std::size_t chunk_size = 4096;
    std::size_t max_regions_per_cell = 1024;
    /// Withhold the density's float-noise allowance from the normalisation
    /// rule (validate --strict): a pdf whose float rounding moves its integral
    /// then fails.
    bool strict = false;
    /// A pilot drawn from the sampler, independent of the tested samples
    /// (the one that placed cells of equal probability): the cells where it
    /// clusters are integrated again on pieces it places (refine_by_pilot).
    /// Empty: none. Not owned.
    std::span<const SamplePoint> pilot;
};

/// Fills `out` with the samples of chunk `chunk` (every chunk has chunk_size
/// samples except possibly the last). Called from several threads at once.
using SampleChunk = std::function<void(std::size_t chunk, std::span<SamplePoint> out)>;

/// How many histograms a parallel sampling loop over `work_items` items keeps
/// (each takes every n-th item; they are merged in order at the end): enough to
/// keep any thread count busy, few enough that together they stay near 2^22
/// counters. At least 1.
std::size_t histogram_count(uint64_t work_items, std::size_t cells);

/// Draws `samples` samples chunk by chunk and bins them. Chunks are spread
/// over a fixed number of lanes, each with its own histogram, merged at the
/// end; counts are integers, so the result is the same for any executor.
Histogram sample_histogram(const Binning& binning, uint64_t samples, std::size_t chunk_size,
                           const SampleChunk& generate, std::span<const unsigned char> zero_cells = {},
                           const ParallelFor& parallel_for = serial_for);

/// What refine_by_pilot did: cells whose pilot points called for a
/// partition (chi2/quadrature.h's kPilotClusterDensity), those whose value it
/// changed, and the mass it added (negative: removed).
struct PilotRefinement {
    std::size_t cells_cut = 0, cells_changed = 0;
    /// Cells whose first integral missed the accuracy rule and agreed with the
    /// pilot-guided one, whose tighter bound replaced it (its value with it).
    std::size_t cells_sharpened = 0;
    double missed_mass = 0.0;
};

struct Chi2Outcome {
    uint64_t samples = 0;
    Histogram histogram;
    CellIntegrals integrals;
    PearsonResult pearson;
    std::vector<double> expected;  ///< per cell: samples * probability
    std::vector<double> residual;  ///< per cell: (O - E) / sqrt(E); NaN where E <= 0
    /// Per cell: how far the true expected count may lie from `expected`
    /// either way (samples times the quadrature's verified error bound, the
    /// density's float noise, and kEdgeFloatSteps float steps of probability
    /// at each interior edge). Pearson's p-value allows for it as a
    /// noncentrality (chi2/pearson.h), the largest residual as a distance to
    /// the band (chi2/local_residual.h).
    std::vector<double> band;
    double edge_band_total = 0.0;   ///< probability in the edge bands, summed over cells
    /// The float-noise allowance of the normalisation rule (0 under `strict`),
    /// and whether the integral needed it to pass.
    double float_noise_allowance = 0.0;
    bool float_noise_used = false;
    /// Cells integrated as zero where samples landed and the density is
    /// positive at them: integrated again around those samples.
    std::size_t reintegrated_cells = 0;
    PilotRefinement pilot_refinement;  ///< with Chi2Options::pilot
    std::size_t zero_expected_cells = 0;  ///< cells where the density integrates to zero
    uint64_t zero_expected_hits = 0;      ///< samples that landed in them
    uint64_t boundary_hits = 0;           ///< of those, exactly on the domain's boundary (accepted up to a cap)
    double integral_tolerance = 0.0;      ///< the tolerance applied to |integral - 1|
    /// Wall seconds of the parts (run_chi2_test sets them): expected-count
    /// integration, drawing and binning the samples, and the statistics.
    double integration_seconds = 0.0, sampling_seconds = 0.0, statistics_seconds = 0.0;

    /// Failures that need no significance level, one message each.
    std::vector<std::string> failures;
    /// Reasons the test could not be trusted to run (the check reports them as errors).
    std::vector<std::string> errors;

    double statistic() const { return pearson.statistic; }
    int dof() const { return pearson.dof; }
    double p_value() const { return pearson.p_value; }
};

/// Per-cell zero flags: 1 where the probability is not positive.
std::vector<unsigned char> zero_cells_of(const CellIntegrals& integrals);

/// reintegrate_missed_support looks again at no more cells than this: a sliver
/// of support that the cubature's nodes miss touches a few cells along its
/// length (a thin light or band crosses at most ~2 x 32 cells of a 32 x 32
/// grid), so 64 covers one such sliver while bounding the cost when a density
/// is zero over a wide region where samples land (a wrong pdf: those cells
/// stay zero and fail the run on their hits).
inline constexpr std::size_t kMaxReintegratedCells = 64;

/// The cells of `q` integrated as zero where samples of `hist` landed and
/// `pdf` is positive at some of them (Histogram::zero_cell_points: a sliver
/// of support between the cubature's nodes), integrated again around those
/// samples (integrate_around) and updated in `q`, totals included; returns
/// how many. The histogram was binned with those cells flagged as zero: bin
/// again with zero_cells_of(q) when any was redone.
std::size_t reintegrate_missed_support(const Binning& binning, const Histogram& hist, const BatchPdf& pdf,
                                       const QuadratureOptions& options, CellIntegrals& q);

/// The cells of `q` whose pilot points (drawn from the sampler, independent
/// of the tested samples) cluster in a part of the cell the first rule's
/// nodes can step over, integrated again on the partition the points place
/// (integrate_partitioned); where that differs from the first value by more
/// than both bounds (and the float noise), it replaces it in `q`, totals
/// included. Depends on the pilot only, so the expected counts are fixed
/// before the tested samples are drawn.
PilotRefinement refine_by_pilot(const Binning& binning, std::span<const SamplePoint> pilot, const BatchPdf& pdf,
                                const QuadratureOptions& options, CellIntegrals& q,
                                const ParallelFor& parallel_for = serial_for);

/// Everything after sampling: expected counts, failures, pooling, statistic.
Chi2Outcome evaluate_chi2(const Binning& binning, Histogram histogram, CellIntegrals integrals, uint64_t samples,
                          const Chi2Options& options);

/// The full test: integrates `pdf` over the cells, draws and bins `samples`
/// samples from `generate`, and evaluates.
Chi2Outcome run_chi2_test(const Binning& binning, uint64_t samples, const SampleChunk& generate, const BatchPdf& pdf,
                          const Chi2Options& options, const ParallelFor& parallel_for = serial_for);

/// Builds the histogram of the samples given the zero-cell mask: what
/// sample_histogram does, or a faster path that gives the same counts.
using SampleHistogram = std::function<Histogram(std::span<const unsigned char> zero_cells)>;
/// The full test with the histogram built by `histogram`.
Chi2Outcome run_chi2_test(const Binning& binning, uint64_t samples, const SampleHistogram& histogram,
                          const BatchPdf& pdf, const Chi2Options& options, const ParallelFor& parallel_for = serial_for);

/// The largest cell residual (chi2/local_residual.h) of an outcome against
/// the same bands as its Pearson statistic: each cell's expectation within
/// [expected - band, expected + band], floored at 0.
LocalResidual largest_band_residual(const Chi2Outcome& o, uint64_t samples, const ParallelFor& parallel_for = serial_for);

}  // namespace warpcheck::chi2

// Expected cell probabilities: the density integrated over every cell by
// adaptive Gauss-Kronrod cubature, accurate enough for the sample count in use.
//
// The accuracy rule. With N samples, cell i's count has Poisson standard
// deviation sqrt(E_i), E_i = N P_i. An integration error d in P_i shifts E_i by
// N d; we require N d <= f sqrt(E_i) with f = 1% by default, i.e.
//     d <= f * sqrt(P_i / N)                                 (probability units)
// so that quadrature error moves no Pearson term by more than ~f^2 of its
// typical size. P_i is the current estimate, floored at 1/N (cells expected to
// hold less than one sample are pooled anyway, and their error then counts
// against the pool). The error estimate is Boost's |Kronrod - Gauss| difference,
// which for smooth densities exceeds the true error of the Kronrod value by
// orders of magnitude, so the rule is met with margin.
//
// The rule: the 15-point Gauss-Kronrod nodes and weights of Boost.Math (with the
// embedded 7-point Gauss rule) as a tensor product on each parameter rectangle.
// Whole rectangles are evaluated in one batch call of the density, so a warp's
// virtual pdf is paid per 225 points, not per point. A rectangle whose error
// estimate is too large is split in half across the parameter whose Gauss
// substitution changed the result most (so a sharp peak draws refinement where
// it is), globally adaptive per cell (largest error first).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "chi2/binning.h"
#include "chi2/domain.h"
#include "chi2/parallel.h"

namespace warpcheck::chi2 {

/// Density callback: densities[i] = pdf(points[i]), with respect to the domain's
/// measure (length, area, solid angle). Called from several threads at once
/// when the ParallelFor is parallel.
using BatchPdf = std::function<void(std::span<const DomainPoint> points, std::span<double> densities)>;

struct QuadratureOptions {
    uint64_t sample_count = 1'000'000;  ///< N of the accuracy rule
    double accuracy_fraction = 0.01;    ///< f of the accuracy rule
    std::size_t max_regions_per_cell = 1024;  ///< refinement budget of one cell
};

/// The accuracy rule's absolute error allowance for a cell of probability p.
double cell_tolerance(double probability, const QuadratureOptions& options);

struct CellIntegrals {
    std::vector<double> probability;  ///< per cell: the density's integral over it
    std::vector<double> error;        ///< per cell: the estimated absolute error
    double total = 0.0;               ///< sum of probability (cell order)
    double error_total = 0.0;         ///< sum of error
    std::size_t unconverged_cells = 0;  ///< cells that ran out of refinement budget
    double worst_error_ratio = 0.0;   ///< max over cells of error / tolerance (<= 1: rule met)
    uint64_t evaluations = 0;         ///< density evaluations
    uint64_t negative_values = 0;     ///< nodes where the density was negative
    uint64_t nonfinite_values = 0;    ///< nodes where the density was NaN or infinite
};

/// Integrates `pdf` over every cell of `binning`. Work is split by cell, so the
/// result does not depend on the executor.
CellIntegrals integrate_cells(const Binning& binning, const BatchPdf& pdf, const QuadratureOptions& options,
                              const ParallelFor& parallel_for = serial_for);

/// The same over any rectangles of `binning`'s parameter space, each as one
/// cell (results in the rectangles' order): pieces of cells, e.g. the refined
/// strips of a marginal CDF (chi2/marginal_cdf.h).
CellIntegrals integrate_rects(const Binning& binning, std::span<const ParamRect> rects, const BatchPdf& pdf,
                              const QuadratureOptions& options, const ParallelFor& parallel_for = serial_for);

}  // namespace warpcheck::chi2

// Plots across the cases of a family, made from the points the rows carry
// (FamilyPoint in reports/result.h): a BSDF's albedo against theta_o over its
// grid of outgoing directions, its reciprocity error likewise. A view of the
// rows like every report, so a selection, a shard or a merge of shards plots
// exactly the cases it holds.
#pragma once

#include <string>
#include <vector>

#include "reports/result.h"

namespace warpcheck {

struct FamilyPlot {
    std::string family;
    Plot plot;
    std::vector<Figure> limits;  ///< the points' limits, each (name, value) once
};

/// One plot per (family, title) of the rows' family points, in the order of
/// the rows that first give each: a line per value label and group (labelled
/// "label" or "label, group"), its points in order of x (ties in row order),
/// with error bars where a value has an interval (low <= high), and the
/// points' limits. The labels of the axes and log_y come from the first point.
/// A limit named "<quantity> bound" bounds the curves labelled "<quantity> ...":
/// where the plot has other curves too, those curves and their bound are a plot
/// of their own, next to it ("energy albedo against theta_o" under "energy
/// bound", apart from "albedo against theta_o": a radiance albedo may exceed
/// 1 across an interface, and is not judged against that bound).
std::vector<FamilyPlot> family_plots(const std::vector<CheckResult>& rows);

}  // namespace warpcheck

// Round trip: invert(sample(u)) must give u back.
//
// The rule, for uniform inputs (each part says why its tolerance has its size,
// and each excuse is counted and reported as a figure):
// - invert(x) must be a point of the input domain [0,1)^d; NaN or anything
//   outside fails, whatever sample then makes of it. One exception is its own
//   class, "rounded to 1": invert(x) == 1.0 in a coordinate where u is one of
//   the two largest floats below 1, or where 1 lies within the float cell of x
//   (below), and the other coordinates pass. The exact inverse of such an x is
//   within a float or two of 1 and rounds up to it; renderers clamp u below 1
//   where they use it, so it passes by default (counted, rounded_to_one) and
//   fails under --strict (RunOptions::strict).
// - |invert(sample(u)) - u| (max norm) within the case's tolerance passes
//   (WarpCaseInfo::roundtrip_tolerance: float trigonometry loses tens of ulps).
// - A larger error that the output's own float resolution explains passes and
//   is counted as resolution-limited. This bound is on each input's error, not
//   a count: a correct float inverse never exceeds it, so it adds no chance of
//   a false failure.
//   1D: sample(back) within 2 ulps of x, and |back - u| within the u-measure of
//   those 4 ulps, 4 pdf(x) spacing(x) (many u share one float x where the warp
//   squeezes them together).
//   Other shapes (2D inputs, 2D or 3D outputs): along each input axis j,
//   |back_j - u_j| within the tolerance or within kCellFactor = 4 extents E_j
//   of x's float cell, the float spacing of x pulled back through the warp's
//   Jacobian (float_cell.h: finite differences of sample; the pseudo-inverse
//   pull-back, or one coordinate's own where larger, as an inverse reads cos
//   theta off z alone); and sample(back) within the image of those cells (2
//   ulps plus |J| 4 E per coordinate) or the tolerance of x. A float inverse
//   reads x rounded by half a cell and adds a few rounded operations: the
//   correct triangle and cos^1000 / cos^10000 lobes of tests/ stay within 1
//   cell; 4 also covers the finite differences' 1/8 (1D uses the same 4).
//   It cannot excuse a real error: an error d passes at u only where 4 E(u) >= d,
//   i.e. where the float x cannot tell u from u + d. An inverse off by 1e-3
//   near the sqrt vertex of a triangle would need E >= 2.5e-4 there, which
//   holds only for u.x below about 6e-8 (a chance of 6e-8 per input).
// - An input on a pole: sample does not depend on u_j there at all (E_j is
//   infinite), so every u_j is a preimage of x. Edge inputs, which sit on poles
//   by construction, count as degenerate (another preimage, below). A random
//   input lands there only where sample rounds a strip of inputs onto a pole
//   (cos theta of a sharp lobe rounding to 1), a strip at most 4 cells E_i of
//   the other axis wide: such inputs (float_pole_random_inputs) may number at
//   most the 1e-9 upper quantile of a Poisson count with mean N * 2 * (the
//   widest strip seen) (two poles per axis), so a correct warp exceeds that
//   bound with probability at most 1e-9.
// - Another preimage (sample(back) within the tolerance of x, back far from u)
//   is accepted only as a set of measure zero: a warp is not injective only on
//   poles, centres and seams, lines u_k = c that a random input hits with
//   probability at most 2^-24 each (the largest float spacing of [0,1)). Such a
//   line joins the two preimages, so every point of the segment from u to back
//   must map within the tolerance of x too (probed at 1/5 .. 4/5), and the
//   random inputs accepted that way may number at most the 1e-9 upper quantile
//   of a Poisson count with mean N 2^-24 * 8 (eight such lines), so a correct
//   warp exceeds it with probability at most 1e-9; edge inputs, which sit on
//   such lines by construction, are counted and reported apart.
// - An input that sample rounds across an edge of the inverse: x sits within
//   kEdgeNeighbourFloats floats (per coordinate) of a line where invert jumps
//   (a table's row edge: x.y rounded up onto it is read in the next row,
//   whose conditional CDF differs), so invert(x) lands far from u while a
//   float neighbour of x on u's side of the edge inverts within the tolerance
//   of u. Tried only where every rule above failed; such inputs are counted
//   (inverse_edge_*). 2 floats because the real sample(u) lies within half a
//   float of x after its last rounding plus a float for the operations
//   before it. The random inputs excused so may number at most the 1e-9 upper
//   quantile of a Poisson count with mean kInverseEdgeProbability = 2^-12 per
//   input, in each chunk of random inputs: the band of 4 floats (at most
//   2^-22 wide) around lines where a correct inverse jumps holds 2^-22 of the
//   inputs per unit of density-weighted line length, so 2^-12 allows the row
//   edges of a 1024-row table (whose densities average 1 along each edge),
//   while an inverse that is wrong beyond float resolution is wrong at its
//   neighbours' floats too and is never excused. Past the bound the chunk
//   stops trying, so a wrong warp's failures cost no neighbour search.
// Raw-bit inputs: the inverse must be exact: invert(x) fits the input's width,
// sample(invert(x)) == x, and invert(x) is the first preimage, so
// invert(x) <= the bits that produced x.
//
// The check is three parts: compute (one pass over the input chunks, counting),
// judge (the rule above, on the counts) and evidence (the worst inputs, the
// worst excused inputs of each class and the error histogram). sample(invert(x))
// and a 1D warp's pdf(x) are computed only for the trips whose rule reads them
// (beyond the tolerance, or rounded to 1; every raw-bit trip).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include <fmt/format.h>

#include "chi2/count_bounds.h"
#include "sampling/float_bits.h"
#include "validate/api/light_case.h"
#include "validate/checks/checks.h"
#include "validate/checks/roundtrip/error_decades.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/float_cell.h"
#include "validate/checks/shared/formatting.h"
#include "validate/checks/shared/input_chunks.h"

namespace warpcheck {
namespace {

constexpr std::size_t kWorstKept = 10;
constexpr std::size_t kExcusedKept = 5;  // per class of excused inputs
constexpr int kFirstDecade = kErrorFirstDecade;  // error histogram: decades 1e-10 .. 1e0 (error_decades.h)
constexpr int kDecades = kErrorDecades;
constexpr double kLineProbability = 0x1p-24;  // largest chance of one input coordinate taking one value
constexpr double kSeamLines = 8.0;            // lines u_k = c where a warp may fail to be injective
constexpr double kPolesPerAxis = 2.0;         // float poles a flat axis may have (top and bottom of a sphere)
constexpr double kBoundTail = 1e-9;           // chance that a correct warp exceeds a count bound
constexpr double kCellFactor = 4.0;           // float cells of x an inverse's error may span (see the top)
constexpr double kEdgeFloats = 2.0;              // floats below 1 whose inverse may round up to 1 (see the top)
constexpr float kTopTwoFloats = 0x1.fffffcp-1f;  // the smaller of the kEdgeFloats largest floats below 1
constexpr int kEdgeNeighbourFloats = 2;              // floats of x per coordinate searched across an inverse edge
constexpr double kInverseEdgeProbability = 0x1p-12;  // largest chance of a random input rounding across one (see the top)

/// How one input's trip ended.
enum class Outcome {
    Within,         ///< |back - u| within the tolerance (or an exact first preimage for bits)
    Resolution,     ///< a larger error that x's float resolution explains
    Pole,           ///< sample ignores an input coordinate at u, and back differs in it
    RoundedToOne,   ///< back is 1.0 where u is at the edge of 1 (fails under --strict)
    OtherPreimage,  ///< sample(back) ~ x with back far from u: accepted on a set of measure zero
    InverseEdge,    ///< x rounded across an edge of the inverse: a float neighbour of x inverts to u
    OutsideInputs,  ///< back is NaN or outside the input domain
    Failed,         ///< back is a valid input that does not map to x
};

/// One input's trip: u -> x -> back.
struct Trip {
    double error = 0.0;  ///< |back - u| (max norm); for raw bits, how far below u the first preimage lies
    Outcome outcome = Outcome::Within;
    WarpInput input;
    WarpOutput output{};
    WarpInput back;
    double cells = 0.0;  ///< resolution, rounded to 1: the error in float cells of x (largest over the axes)
    double strip = 0.0;  ///< pole: the width of the strip of inputs that sample rounds onto it

    bool failed() const { return outcome == Outcome::OutsideInputs || outcome == Outcome::Failed; }
};

/// The trips of one excused class: how many, their largest error and the
/// worst of them (those nearest the limit, by float cells, where the class has
/// one; else by error).
struct Excused {
    bool by_cells = false;
    uint64_t count = 0;
    double max_error = 0.0;
    double max_cells = 0.0;
    WorstK<Trip> worst{kExcusedKept};

    void add(Trip trip, uint64_t index) {
        ++count;
        max_error = max_nan_wins(max_error, trip.error);
        max_cells = max_nan_wins(max_cells, trip.cells);
        const double key = by_cells ? trip.cells : trip.error;
        if (worst.wants(key)) worst.offer(key, index, std::move(trip));
    }
    void merge(const Excused& o) {
        count += o.count;
        max_error = max_nan_wins(max_error, o.max_error);
        max_cells = max_nan_wins(max_cells, o.max_cells);
        worst.merge(o.worst);
    }
};

/// What the compute part counts.
struct Stats {
    uint64_t count = 0, random_count = 0;
    uint64_t declined = 0;  ///< a light's inputs that gave no sample: no trip
    uint64_t failures = 0, outside_inputs = 0;
    uint64_t other_edges = 0;  ///< other preimages and poles among edge inputs (degenerate)
    Excused other_random;      ///< other preimages among random inputs
    Excused resolution{.by_cells = true};
    uint64_t resolution_random = 0;  ///< of them, random inputs
    Excused pole_random;       ///< random inputs on a float pole
    Excused rounded_to_one{.by_cells = true};
    Excused inverse_edge;            ///< inputs rounded across an edge of the inverse
    uint64_t inverse_edge_random = 0;  ///< of them, random inputs
    uint64_t inverse_edge_chunk_max = 0;  ///< the most random ones in one chunk
    uint64_t inverse_edge_chunk_bound = 0;  ///< the bound per chunk of kInputChunkSize random inputs
    double max_strip = 0.0;    ///< widest strip of inputs rounded onto a pole
    uint64_t exact = 0;
    // Over inputs that came back within the tolerance or failed; NaN wins. Edge
    // inputs apart: they sit on poles and seams, where an error up to the
    // tolerance is another preimage rather than imprecision.
    double max_error = 0.0, max_edge_error = 0.0;
    std::array<uint64_t, kDecades + 2> histogram{};  // [0]: below 1e-10 (not exact), [1..11]: decades, [12]: >= 10
    WorstK<Trip> worst{kWorstKept};                   // failures first (key inf), then largest errors

    void merge(const Stats& o) {
        count += o.count;
        declined += o.declined;
        random_count += o.random_count;
        failures += o.failures;
        outside_inputs += o.outside_inputs;
        other_edges += o.other_edges;
        other_random.merge(o.other_random);
        resolution.merge(o.resolution);
        resolution_random += o.resolution_random;
        pole_random.merge(o.pole_random);
        rounded_to_one.merge(o.rounded_to_one);
        inverse_edge.merge(o.inverse_edge);
        inverse_edge_random += o.inverse_edge_random;
        inverse_edge_chunk_max = std::max(inverse_edge_chunk_max, o.inverse_edge_chunk_max);
        inverse_edge_chunk_bound = std::max(inverse_edge_chunk_bound, o.inverse_edge_chunk_bound);
        max_strip = max_nan_wins(max_strip, o.max_strip);
        exact += o.exact;
        max_error = max_nan_wins(max_error, o.max_error);
        max_edge_error = max_nan_wins(max_edge_error, o.max_edge_error);
        for (std::size_t k = 0; k < histogram.size(); ++k) histogram[k] += o.histogram[k];
        worst.merge(o.worst);
    }
    uint64_t degenerate() const { return other_edges + other_random.count + pole_random.count; }
};

/// The case's view of the rule: what is compared, with which tolerance.
struct Rule {
    InputKind kind = InputKind::Uniform1D;
    int in_dims = 1;
    int out_dims = 1;
    double tolerance = 0.0;  ///< the case's roundtrip_tolerance; unused (exact) for raw bits
    bool strict = false;     ///< --strict: u rounded to 1 fails

    bool bits() const { return takes_bits(kind); }
    bool one_dimensional() const { return in_dims == 1 && out_dims == 1 && !bits(); }
};

double max_abs_diff(const WarpOutput& a, const WarpOutput& b, int dims) {
    double d = 0.0;
    for (int k = 0; k < dims; ++k)
        d = max_nan_wins(d, std::abs(static_cast<double>(a[k]) - static_cast<double>(b[k])));
    return d;
}

/// Where invert(x) lies: in the input domain, in it but for coordinates that
/// are exactly 1.0, or outside it (NaN included).
enum class Place { Inside, AtOne, Outside };

Place place_of(const WarpInput& back, const Rule& rule) {
    if (rule.kind == InputKind::Bits32) return back.bits <= 0xffffffffu ? Place::Inside : Place::Outside;
    if (rule.bits()) return Place::Inside;
    Place p = Place::Inside;
    for (int k = 0; k < rule.in_dims; ++k) {
        if (back.u[k] == 1.0f)
            p = Place::AtOne;
        else if (!(back.u[k] >= 0.0f && back.u[k] < 1.0f))
            return Place::Outside;
    }
    return p;
}

/// How far `back` lies from the uniform input `u` along input axis k.
double axis_error(const WarpInput& back, const WarpInput& u, int k) {
    return std::abs(static_cast<double>(back.u[k]) - u.u[k]);
}
double axis_error(const Trip& t, int k) { return axis_error(t.back, t.input, k); }

/// The largest of those over the input's `dims` axes (NaN wins): a trip's error.
double input_error(const WarpInput& back, const WarpInput& u, int dims) {
    double e = 0.0;
    for (int k = 0; k < dims; ++k) e = max_nan_wins(e, axis_error(back, u, k));
    return e;
}

Outcome bits_outcome(Trip& t, const WarpOutput& x2, const Rule& rule) {
    t.error = static_cast<double>(t.input.bits - std::min(t.input.bits, t.back.bits));
    const bool same = max_abs_diff(x2, t.output, rule.out_dims) == 0.0;
    return same && t.back.bits <= t.input.bits ? Outcome::Within : Outcome::Failed;
}

/// What judging a trip needs besides the trip: sample(back), and pdf(x) for a
/// 1D warp. A trip of uniform inputs within the tolerance (nearly every one)
/// reads neither, so each is computed when the rule first reads it; raw-bit
/// trips read sample(back) always, and it comes computed for the chunk.
class TripInputs {
public:
    TripInputs(const WarpCase& w, const Rule& r, const WarpInput& back, const WarpOutput& x,
               const WarpOutput* x2 = nullptr)
        : warp(w), rule(r), back_(back), x_(x), x2_(x2 ? std::optional(*x2) : std::nullopt) {}

    const WarpCase& warp;
    const Rule& rule;

    const WarpOutput& x2() const {
        if (!x2_) warp.sample(std::span(&back_, 1), std::span(&x2_.emplace(), 1));
        return *x2_;
    }
    double pdf() const {
        if (!pdf_) warp.pdf(std::span(&x_, 1), std::span(&pdf_.emplace(), 1));
        return *pdf_;
    }

private:
    const WarpInput& back_;
    const WarpOutput& x_;
    mutable std::optional<WarpOutput> x2_;
    mutable std::optional<double> pdf_;
};

/// The extents of x's float cell along each input axis (1D: pdf(x) spacing(x),
/// the u-measure of one float spacing, from the warp's own density).
FloatCell cell_of(const TripInputs& in, const Trip& t) {
    if (in.rule.one_dimensional()) {
        FloatCell cell;
        cell.extent[0] = in.pdf() * float_spacing(t.output[0]);
        return cell;
    }
    return measure_float_cell(in.warp, t.input, t.output, in.rule.in_dims, in.rule.out_dims);
}

/// Whether the coordinates of invert(x) that are 1.0 belong to inputs at the
/// edge of 1 and the others pass (see the top); sets the trip's cells.
bool rounded_to_one(const TripInputs& in, Trip& t) {
    const FloatCell cell = cell_of(in, t);
    for (int k = 0; k < in.rule.in_dims; ++k) {
        const bool at_one = t.back.u[k] == 1.0f;
        if (at_one ? t.input.u[k] >= kTopTwoFloats : axis_error(t, k) <= in.rule.tolerance) continue;
        // Otherwise only x's float cell can explain the gap (to 1, or to u).
        const double cells = (at_one ? 1.0 - t.input.u[k] : axis_error(t, k)) / cell.extent[k];
        if (!(cells <= kCellFactor)) return false;
        if (!cell.flat(k)) t.cells = max_nan_wins(t.cells, cells);
    }
    return true;
}

/// Whether sample(back) lies within the image of the cells the error spans
/// (2 ulps plus |J| 4 E per coordinate) or within the tolerance of x.
bool lands_in_cells(const TripInputs& in, const Trip& t, const FloatCell& cell) {
    for (int k = 0; k < in.rule.out_dims; ++k) {
        double reach = 2.0 * float_spacing(t.output[k]);
        for (int j = 0; j < in.rule.in_dims; ++j)
            if (!cell.flat(j)) reach += std::abs(cell.jacobian[k][j]) * kCellFactor * cell.extent[j];
        const double dx = std::abs(static_cast<double>(in.x2()[k]) - t.output[k]);
        if (!(dx <= std::max(reach, in.rule.tolerance))) return false;
    }
    return true;
}

/// A trip beyond the tolerance whose error x's float cell explains (see the
/// top): Resolution or Pole; Failed where it does not (the caller then tries
/// another preimage).
Outcome resolution_outcome(const TripInputs& in, Trip& t) {
    if (in.rule.one_dimensional()) {
        const double spacing = float_spacing(t.output[0]);
        const double dx = max_abs_diff(in.x2(), t.output, 1);
        t.cells = t.error / (in.pdf() * spacing);
        return dx <= 2.0 * spacing && t.error <= kCellFactor * in.pdf() * spacing ? Outcome::Resolution
                                                                                 : Outcome::Failed;
    }
    const FloatCell cell = cell_of(in, t);
    bool on_pole = false;
    double widest = 0.0;  // the cells' u-extent across a pole
    for (int j = 0; j < in.rule.in_dims; ++j) {
        const double e = axis_error(t, j);
        if (!cell.flat(j)) widest = max_nan_wins(widest, std::min(1.0, kCellFactor * cell.extent[j]));
        if (e <= in.rule.tolerance) continue;
        if (cell.flat(j)) {
            on_pole = true;
            continue;
        }
        const double cells = e / cell.extent[j];
        if (!(cells <= kCellFactor)) return Outcome::Failed;
        t.cells = max_nan_wins(t.cells, cells);
    }
    if (!lands_in_cells(in, t, cell)) return Outcome::Failed;
    t.strip = on_pole && widest == 0.0 ? 1.0 : widest;
    return on_pole ? Outcome::Pole : Outcome::Resolution;
}

/// Judges one trip by the rule at the top of this file.
Trip judge_trip(const TripInputs& in, const WarpInput& u, const WarpOutput& x, const WarpInput& back) {
    const Rule& rule = in.rule;
    Trip t{0.0, Outcome::Within, u, x, back};
    const Place place = place_of(back, rule);
    if (rule.bits()) {
        if (place == Place::Outside) {
            t.error = static_cast<double>(back.bits);
            t.outcome = Outcome::OutsideInputs;
        } else {
            t.outcome = bits_outcome(t, in.x2(), rule);
        }
        return t;
    }
    t.error = input_error(back, u, rule.in_dims);
    if (place == Place::Outside) {
        t.outcome = Outcome::OutsideInputs;
    } else if (place == Place::AtOne) {
        t.outcome = rounded_to_one(in, t) ? Outcome::RoundedToOne : Outcome::OutsideInputs;
    } else if (!(t.error <= rule.tolerance)) {
        t.outcome = resolution_outcome(in, t);
        if (t.outcome == Outcome::Failed)
            t.outcome = max_abs_diff(in.x2(), x, rule.out_dims) <= rule.tolerance ? Outcome::OtherPreimage
                                                                                  : Outcome::Failed;
    }
    return t;
}

void count_error(Stats& s, const Rule& rule, double error) {
    if (rule.bits()) return;
    if (error == 0.0) {
        ++s.exact;
    } else if (std::isfinite(error)) {
        s.histogram[error_decade_bin(error)]++;
    }
}

/// Counts an excused trip in its class; false for trips that are not excused.
bool count_excused(Stats& s, Trip& trip, bool edge, uint64_t index) {
    switch (trip.outcome) {
        case Outcome::OtherPreimage:
        case Outcome::Pole:
            if (edge) {
                ++s.other_edges;
            } else if (trip.outcome == Outcome::Pole) {
                s.max_strip = max_nan_wins(s.max_strip, trip.strip);
                s.pole_random.add(std::move(trip), index);
            } else {
                s.other_random.add(std::move(trip), index);
            }
            return true;
        case Outcome::Resolution:
            s.resolution_random += !edge;
            s.resolution.add(std::move(trip), index);
            return true;
        case Outcome::RoundedToOne: s.rounded_to_one.add(std::move(trip), index); return true;
        case Outcome::InverseEdge:
            s.inverse_edge_random += !edge;
            s.inverse_edge.add(std::move(trip), index);
            return true;
        default: return false;
    }
}

/// Counts a trip. Taken by reference: it is copied only into a list that keeps
/// it (a copy of every trip was a tenth of the check's time).
void count_trip(Stats& s, const Rule& rule, Trip&& trip, bool edge, uint64_t index) {
    ++s.count;
    s.random_count += !edge;
    if (count_excused(s, trip, edge, index)) return;
    if (trip.outcome == Outcome::OutsideInputs) ++s.outside_inputs;
    if (trip.failed()) ++s.failures;
    count_error(s, rule, trip.error);
    double& max = edge ? s.max_edge_error : s.max_error;
    max = max_nan_wins(max, trip.error);
    const double key = trip.failed() ? std::numeric_limits<double>::infinity() : trip.error;
    if (s.worst.wants(key)) s.worst.offer(key, index, std::move(trip));
}

/// Whether the segment from the input to the other preimage maps onto x: the
/// points 1/5 .. 4/5 of the way all land within the tolerance of x.
bool segment_maps_to_x(const WarpCase& warp, const Rule& rule, const Trip& t) {
    std::array<WarpInput, 4> probes{};
    for (std::size_t j = 0; j < probes.size(); ++j) {
        const float s = static_cast<float>(j + 1) / 5.0f;
        for (int k = 0; k < rule.in_dims; ++k) probes[j].u[k] = t.input.u[k] + s * (t.back.u[k] - t.input.u[k]);
    }
    std::array<WarpOutput, 4> out{};
    warp.sample(probes, out);
    for (const WarpOutput& o : out)
        if (!(max_abs_diff(o, t.output, rule.out_dims) <= rule.tolerance)) return false;
    return true;
}

/// The float neighbours of x within kEdgeNeighbourFloats floats in each
/// output coordinate (x itself left out) that lie in the warp's domain.
std::vector<WarpOutput> float_neighbours_of(const WarpCase& warp, const WarpOutput& x, int dims) {
    constexpr int kSide = 2 * kEdgeNeighbourFloats + 1;
    int combinations = 1;
    for (int k = 0; k < dims; ++k) combinations *= kSide;
    std::vector<WarpOutput> out;
    for (int c = 0; c < combinations; ++c) {
        WarpOutput p = x;
        bool moved = false;
        for (int k = 0, rest = c; k < dims; ++k, rest /= kSide) {
            const int steps = rest % kSide - kEdgeNeighbourFloats;
            for (int s = 0; s < std::abs(steps); ++s)
                p[k] = steps > 0 ? next_float_up(p[k]) : next_float_down(p[k]);
            moved = moved || steps != 0;
        }
        if (moved && warp.domain().contains(to_domain_point(p))) out.push_back(p);
    }
    return out;
}

/// Whether x was rounded across an edge of the inverse (see the top): a float
/// neighbour of x inverts to within the tolerance of u.
bool rounded_across_inverse_edge(const WarpCase& warp, const Rule& rule, const Trip& t) {
    const std::vector<WarpOutput> near = float_neighbours_of(warp, t.output, rule.out_dims);
    std::vector<WarpInput> back(near.size());
    warp.invert(near, back);
    for (const WarpInput& b : back)
        if (place_of(b, rule) == Place::Inside && input_error(b, t.input, rule.in_dims) <= rule.tolerance) return true;
    return false;
}

/// How many random inputs of a chunk may be excused as rounded across an
/// edge of the inverse (see the top).
uint64_t inverse_edge_bound(std::size_t chunk_inputs) {
    return chi2::poisson_count_bound(static_cast<double>(chunk_inputs) * kInverseEdgeProbability, kBoundTail);
}

Stats compute(const WarpCase& warp, const CheckContext& ctx, const Rule& rule) {
    auto parts = map_input_chunks<Stats>(ctx, warp.input_kind(), ctx.options().samples, true,
                                         [&](std::size_t chunk, std::span<const WarpInput> inputs) {
        Stats s;
        std::vector<WarpOutput> x(inputs.size()), x2(rule.bits() ? inputs.size() : 0);
        std::vector<WarpInput> back(inputs.size());
        warp.sample(inputs, x);
        // A light or an MIS case may decline to sample (pdf 0, a NaN direction here):
        // such an input has no trip; the direction inverted in its place is
        // never judged.
        std::vector<unsigned char> declined(declines_samples(warp) ? inputs.size() : 0);
        for (std::size_t i = 0; i < declined.size(); ++i)
            if (!std::isfinite(x[i][0])) declined[i] = 1, x[i] = {0.0f, 0.0f, 1.0f};
        warp.invert(x, back);
        if (rule.bits()) warp.sample(back, x2);
        const uint64_t base = chunk * kInputChunkSize;  // edge inputs first, then the random stream
        // Edge inputs are not random: every one may try, and is counted apart.
        const uint64_t search_limit = chunk == 0 ? inputs.size() : inverse_edge_bound(inputs.size());
        uint64_t tries = 0;
        for (std::size_t i = 0; i < inputs.size(); ++i) {
            if (!declined.empty() && declined[i]) {
                ++s.declined;
                continue;
            }
            const TripInputs trip_inputs(warp, rule, back[i], x[i], rule.bits() ? &x2[i] : nullptr);
            Trip trip = judge_trip(trip_inputs, inputs[i], x[i], back[i]);
            if (trip.outcome == Outcome::OtherPreimage && !segment_maps_to_x(warp, rule, trip))
                trip.outcome = Outcome::Failed;
            if (trip.outcome == Outcome::Failed && !rule.bits() && tries < search_limit) {
                ++tries;
                if (rounded_across_inverse_edge(warp, rule, trip)) trip.outcome = Outcome::InverseEdge;
            }
            count_trip(s, rule, std::move(trip), chunk == 0, base + i);
        }
        if (chunk > 0) {
            s.inverse_edge_chunk_max = s.inverse_edge.count;
            s.inverse_edge_chunk_bound = search_limit;
        }
        return s;
    });
    return merge_in_order(parts);
}

/// How many random inputs may come back as another preimage (see the top).
uint64_t other_preimage_bound(const Stats& s) {
    return chi2::poisson_count_bound(static_cast<double>(s.random_count) * kLineProbability * kSeamLines, kBoundTail);
}

/// How many random inputs may land on float poles (see the top).
uint64_t pole_bound(const Stats& s) {
    return chi2::poisson_count_bound(static_cast<double>(s.random_count) * kPolesPerAxis * s.max_strip, kBoundTail);
}

std::string failure_reason(const Stats& s, const Rule& rule) {
    if (rule.bits())
        return fmt::format("{} of {} inputs: sample(invert(x)) != x or invert(x) is not the first preimage",
                           s.failures - s.outside_inputs, s.count);
    std::string why = fmt::format("{} of {} inputs come back further than {:.3g} from u, and further than {} float "
                                  "cells of x",
                                  s.failures - s.outside_inputs, s.count, rule.tolerance, kCellFactor);
    if (s.inverse_edge_chunk_bound > 0 && s.inverse_edge_chunk_max >= s.inverse_edge_chunk_bound)
        why += fmt::format(" (a chunk of {} random inputs reached its bound of {} rounded across an edge of the "
                           "inverse, which a correct warp exceeds with probability {:.0e}; its later inputs were "
                           "not searched)",
                           kInputChunkSize, s.inverse_edge_chunk_bound, kBoundTail);
    return why;
}

/// The reasons for the excused classes that went over their bounds.
void excuse_reasons(std::vector<std::string>& why, const Stats& s, const Rule& rule) {
    const uint64_t bound = other_preimage_bound(s);
    if (s.other_random.count > bound)
        why.push_back(fmt::format("{} of {} random inputs come back as another preimage of x, more than the {} a "
                                  "non-injective set of measure zero explains (a correct warp exceeds it with "
                                  "probability {:.0e}): the inverse is wrong on a set of positive measure",
                                  s.other_random.count, s.random_count, bound, kBoundTail));
    const uint64_t poles = pole_bound(s);
    if (s.pole_random.count > poles)
        why.push_back(fmt::format("{} of {} random inputs land where sample ignores an input coordinate, more than "
                                  "the {} that strips {} float cells wide around {} poles explain (a correct warp "
                                  "exceeds it with probability {:.0e}): sample ignores it on a set of positive measure",
                                  s.pole_random.count, s.random_count, poles, kCellFactor, kPolesPerAxis, kBoundTail));
    if (rule.strict && s.rounded_to_one.count > 0)
        why.push_back(fmt::format("{} inputs: invert(x) == 1.0 for u at the edge of 1 (u rounded to 1; largest "
                                  "|du| {:.3g}): passes by default, fails under --strict",
                                  s.rounded_to_one.count, s.rounded_to_one.max_error));
}

std::vector<std::string> reasons(const Stats& s, const Rule& rule) {
    std::vector<std::string> why;
    const Trip* w = s.worst.empty() ? nullptr : &s.worst.front().item;
    auto example = [&] {
        return fmt::format("e.g. {} = {} -> x = {} -> invert {}", rule.bits() ? "bits" : "u",
                           format_input(w->input, rule.kind), format_output(w->output, rule.out_dims),
                           format_input(w->back, rule.kind));
    };
    if (s.outside_inputs > 0)
        why.push_back(fmt::format("{} of {} inputs: invert(x) is NaN or outside the input domain{}", s.outside_inputs,
                                  s.count, rule.bits() ? " (wider than the input)" : " [0,1)"));
    if (s.failures > s.outside_inputs) why.push_back(failure_reason(s, rule));
    if (!why.empty() && w) why.back() += "; " + example();
    excuse_reasons(why, s, rule);
    return why;
}

/// The verdict: no input fails, the excused classes stay within their bounds,
/// and under --strict nothing was rounded to 1.
void judge(CheckResult& r, const Stats& s, const Rule& rule) {
    const std::vector<std::string> why = reasons(s, rule);
    r.verdict = why.empty() ? Verdict::Pass : Verdict::Fail;
    r.message = join_reasons(why);
    if (rule.bits()) {
        r.summary = s.failures == 0 ? "exact inverse" : fmt::format("{} inputs not inverted", s.failures);
        return;
    }
    r.summary = fmt::format("max |du| {:.2e}", max_nan_wins(s.max_error, s.failures ? s.max_edge_error : 0.0));
    if (s.degenerate() > 0) r.summary += fmt::format(", {} degenerate", s.degenerate());
    if (s.resolution.count > 0) r.summary += fmt::format(", {} resolution-limited", s.resolution.count);
    if (s.inverse_edge.count > 0) r.summary += fmt::format(", {} across an inverse edge", s.inverse_edge.count);
    if (s.rounded_to_one.count > 0)
        r.summary += fmt::format(", {} rounded to 1 ({})", s.rounded_to_one.count,
                                 rule.strict ? "failed: --strict" : "fails under --strict");
}

void add_figures(CheckResult& r, const Stats& s, const Rule& rule) {
    r.samples = s.count;
    r.figures = {{"max_error", s.max_error},
                 {"max_edge_error", s.max_edge_error},
                 {"tolerance", rule.bits() ? 0.0 : rule.tolerance},
                 {"failures", static_cast<double>(s.failures)},
                 {"declined_samples", static_cast<double>(s.declined)},
                 {"outside_input_domain", static_cast<double>(s.outside_inputs)},
                 {"degenerate", static_cast<double>(s.degenerate())},
                 {"other_preimage_edge_inputs", static_cast<double>(s.other_edges)},
                 {"other_preimage_random_inputs", static_cast<double>(s.other_random.count)},
                 {"other_preimage_bound", static_cast<double>(other_preimage_bound(s))},
                 {"other_preimage_fraction", s.random_count ? static_cast<double>(s.other_random.count) /
                                                                  static_cast<double>(s.random_count)
                                                            : 0.0},
                 {"resolution_limited", static_cast<double>(s.resolution.count)},
                 {"max_resolution_limited_error", s.resolution.max_error},
                 {"exact", static_cast<double>(s.exact)},
                 {"inputs", static_cast<double>(s.count)}};
    if (rule.bits()) return;
    r.figures.insert(r.figures.end(),
                     {{"resolution_limited_random_inputs", static_cast<double>(s.resolution_random)},
                      {"max_resolution_limited_cells", s.resolution.max_cells},
                      {"resolution_cell_factor", kCellFactor},
                      {"float_pole_random_inputs", static_cast<double>(s.pole_random.count)},
                      {"float_pole_bound", static_cast<double>(pole_bound(s))},
                      {"float_pole_max_strip", s.max_strip},
                      {"count_bound_false_failure_probability", kBoundTail},
                      {"inverse_edge_inputs", static_cast<double>(s.inverse_edge.count)},
                      {"inverse_edge_random_inputs", static_cast<double>(s.inverse_edge_random)},
                      {"inverse_edge_most_in_a_chunk", static_cast<double>(s.inverse_edge_chunk_max)},
                      {"inverse_edge_chunk_bound", static_cast<double>(s.inverse_edge_chunk_bound)},
                      {"inverse_edge_neighbour_floats", static_cast<double>(kEdgeNeighbourFloats)},
                      {"rounded_to_one", static_cast<double>(s.rounded_to_one.count)},
                      {"rounded_to_one_edge_floats", kEdgeFloats},
                      {"max_rounded_to_one_error", s.rounded_to_one.max_error},
                      {"strict", rule.strict ? 1.0 : 0.0}});
}

std::string error_text(const Trip& t) { return t.failed() ? std::string("FAILED") : fmt::format("{:.3e}", t.error); }

/// The worst inputs of each excused class: what the rule let through, and why.
Table excused_table(const Stats& s, const Rule& rule) {
    Table t{"Worst excused inputs",
            {"class", "input u", "sample(u)", "invert(sample(u))", "|du|", "float cells of x"},
            {}};
    const std::pair<const char*, const Excused*> classes[] = {{"resolution-limited", &s.resolution},
                                                              {"float pole", &s.pole_random},
                                                              {"rounded to 1", &s.rounded_to_one},
                                                              {"across an inverse edge", &s.inverse_edge},
                                                              {"other preimage", &s.other_random}};
    for (const auto& [name, excused] : classes)
        for (const auto& e : excused->worst.entries())
            t.rows.push_back({name, format_input(e.item.input, rule.kind), format_output(e.item.output, rule.out_dims),
                              format_input(e.item.back, rule.kind), error_text(e.item),
                              e.item.outcome == Outcome::Resolution || e.item.outcome == Outcome::RoundedToOne
                                  ? fmt::format("{:.3g}", e.item.cells)
                                  : std::string("-")});
    return t;
}

void add_evidence(CheckResult& r, const Stats& s, const Rule& rule) {
    Table worst{"Worst inputs", {"input u", "sample(u)", "invert(sample(u))", rule.bits() ? "input offset" : "|du|"}, {}};
    for (const auto& e : s.worst.entries())
        worst.rows.push_back({format_input(e.item.input, rule.kind), format_output(e.item.output, rule.out_dims),
                              format_input(e.item.back, rule.kind), error_text(e.item)});
    r.tables.push_back(std::move(worst));
    if (rule.bits()) return;
    Table excused = excused_table(s, rule);
    if (!excused.rows.empty()) r.tables.push_back(std::move(excused));

    Plot p;
    p.kind = Plot::Kind::Bars;
    p.title = fmt::format("Round-trip error per input (tolerance {:.2e}; {} exact, {} degenerate, {} resolution-limited)",
                          rule.tolerance, s.exact, s.degenerate(), s.resolution.count);
    p.x_label = "log10 |invert(sample(u)) - u|";
    p.y_label = "inputs";
    p.log_y = true;
    Series bars{"inputs", {}, {}};
    for (int k = 0; k < kDecades + 2; ++k) {
        bars.x.push_back(kFirstDecade - 1 + k);
        bars.y.push_back(static_cast<double>(s.histogram[static_cast<std::size_t>(k)]));
    }
    p.series.push_back(std::move(bars));
    r.plots.push_back(std::move(p));
}

/// The tolerance on the bar plot of error decades (the bar of decade d,
/// errors in [10^d, 10^(d+1)), stands at x = d, so an error e lies at
/// log10(e) - 1/2 in its slot), and what the bars and the line mean.
void mark_roundtrip_plots(CheckResult& r) {
    const auto tolerance = r.figure("tolerance");
    if (!tolerance || !(*tolerance > 0.0)) return;
    for (Plot& plot : r.plots) {
        if (plot.kind != Plot::Kind::Bars) continue;
        plot.limits.push_back({true, std::log10(*tolerance) - 0.5, fmt::format("tolerance {:.3g}", *tolerance)});
        plot.note = "Each bar counts the inputs whose error lies in one decade [10^e, 10^(e+1)), drawn at e; the dashed "
                    "line stands at the tolerance's place in its decade. Right of it: inputs that missed the tolerance, "
                    "failures unless excused (counted in the Judged table).";
    }
}

class RoundtripCheck final : public Check {
public:
    std::string name() const override { return "roundtrip"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"max_error", "largest |invert(sample(u)) \u2212 u| not excused", FigureRule::AtMost, "tolerance"},
                 {"failures", "inputs beyond the tolerance, not excused", FigureRule::Zero},
                 {"outside_input_domain", "inverses outside [0, 1)", FigureRule::Zero},
                 {"other_preimage_random_inputs", "random inputs with another preimage", FigureRule::AtMost, "other_preimage_bound"},
                 {"float_pole_random_inputs", "random inputs at a float pole", FigureRule::AtMost, "float_pole_bound"},
                 {"resolution_limited", "resolution-limited inputs (excused)", FigureRule::Counted},
                 {"degenerate", "degenerate inputs (excused)", FigureRule::Counted},
                 {"rounded_to_one", "u rounded to 1 (excused; fails under --strict)", FigureRule::Counted}},
                .bounds = [](const CheckResult& r, std::vector<JudgedQuantity>& out) {
                    strict_zero_line(r, "rounded_to_one", "u rounded to 1", out);
                },
                .marks = mark_roundtrip_plots};
    }
    CheckLegend legend() const override {
        return {name(), "|invert(sample(u)) \u2212 u| against the case's tolerance (float resolution); excused "
                "classes (resolution-limited, degenerate, other preimage, rounded to 1) are counted and bounded.",
                ""};
    }
    std::string description() const override {
        return "invert(sample(u)) == u over a seeded stream plus edge inputs (exact for raw-bit inputs)";
    }
    Applicability applicability(const WarpCase& warp) const override {
        return warp.has_inverse() ? Applicability::runs() : Applicability::lacks("the warp has no inverse");
    }

    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const InputKind kind = warp.input_kind();
        const Rule rule{kind, input_dimension(kind), warp.domain().point_dimension(),
                        warp.info().roundtrip_tolerance, ctx.options().strict};
        const Stats stats = compute(warp, ctx, rule);
        CheckResult r;
        judge(r, stats, rule);
        add_figures(r, stats, rule);
        add_evidence(r, stats, rule);
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_roundtrip_check() { return std::make_unique<RoundtripCheck>(); }

}  // namespace warpcheck

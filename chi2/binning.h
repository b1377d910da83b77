// The cells of a chi-square test: a grid that is uniform in the domain's
// parameters (u, v), how a parameter point maps to a domain point and measure,
// and the fast classification of samples into cells.
//
// Each domain kind defines its parameters (chi2/domain_kinds.h); Binning
// divides their rectangle uniformly and asks the kind for the rest.
// Cells are numbered row-major: index = row * cols + col, row along v.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "chi2/domain.h"

namespace warpcheck::chi2 {

/// Counts of one histogram: per cell, plus the samples that fell in no cell.
struct Histogram {
    std::vector<uint64_t> counts;
    uint64_t outside = 0;  ///< not Domain::contains (beyond its slack)
    uint64_t nan = 0;      ///< a NaN coordinate
    uint64_t snapped = 0;  ///< moved (within tolerance) from a zero-expected cell to a neighbour
    /// In a zero-expected cell and exactly on the domain's boundary, where a
    /// density may vanish: set aside, not counted in any cell (see bin_impl).
    uint64_t on_boundary = 0;
    /// Azimuthal domains: per row, the samples exactly at the pole or centre
    /// (x = y = 0), where the azimuth is undefined. A float warp puts real mass
    /// there (a cap's cos theta rounds to 1 with the probability of one float's
    /// rounding interval: 1/320 of a 0.25 degree sun), and a density continuous
    /// at the pole spreads it evenly over the azimuth: spread_poles deals them
    /// out over the row's columns. Empty until a pole sample is binned.
    std::vector<uint64_t> poles;
    /// Where samples landed in cells flagged as of zero probability (bin's
    /// `zero_cells`): per such cell, the points extreme in a coordinate (the
    /// smallest and largest x, y and z; ties by the whole point), which span
    /// the support the samples found there and do not depend on the order
    /// samples were binned in. The test looks at the density there: a sliver
    /// of support between the quadrature's nodes is integrated again around
    /// them (chi2_test.h).
    struct CellPoint {
        std::size_t cell = 0;
        DomainPoint point{};
        auto operator<=>(const CellPoint&) const = default;
    };
    std::vector<CellPoint> zero_cell_points;
    uint64_t total() const;
    /// Adds another histogram of the same binning (integer sums: any order gives the same result).
    void merge(const Histogram& other);
    /// Deals each row's pole samples out over its `cols` columns, n / cols to
    /// each and one more to the first n % cols (at most one sample from an
    /// even share), and clears `poles`.
    void spread_poles(int cols);
    /// The same for columns of unequal azimuth: per row, `shares` (cols
    /// weights each, row after row) deal its pole samples out in proportion,
    /// the remainders one at a time to the largest fractions (ties to the
    /// first column), and clears `poles`.
    void spread_poles(int cols, std::span<const double> shares);
};

/// Cells with edges of their own instead of a uniform grid of the parameter
/// rectangle: rows between `rows` (v edges, ascending, from the rectangle's
/// v0 to its v1) and, in each row, columns between that row's `cols` (u
/// edges, ascending, from u0 to u1), the same number in every row. A 1D
/// domain has one row, rows = {v0, v1}. Cells of about equal probability are
/// made this way (chi2/equal_probability.h); any edges may be given.
struct CellEdges {
    std::vector<double> rows;
    std::vector<std::vector<double>> cols;
    /// Optional, per cell (row-major): the rectangles the cell's density is
    /// integrated over, which tile it (an empty list: the cell itself).
    /// chi2/equal_probability.h cuts a cell where its mass was seen, so that
    /// the cubature's nodes fall there: a cell that reaches from a lobe's edge
    /// to the far side of the sphere holds its mass within 1e-5 of one end,
    /// between any fixed rule's nodes.
    std::vector<std::vector<ParamRect>> pieces;
    bool empty() const { return rows.empty(); }
};

/// What a vectorised binning loop needs (validate/lanes/lane_cells.h): the constants
/// of Binning's own arithmetic for an azimuthal domain, so that the lanes put
/// every ordinary sample in the cell bin() would.
struct LanePlan {
    static constexpr int kMaxOctantCols = 16;
    bool sphere = false;        ///< SphericalCap (else Disk)
    double len2_lo = 0.0, len2_hi = 0.0;  ///< bin_contains' bounds on |p|^2 (len2_lo unused on the disk)
    double z_floor = 0.0;       ///< SphericalCap: z_min - slack
    double v0 = 0.0, inv_dv = 1.0;
    int rows = 1, cols = 1, octant_cols = 1;
    /// tan(k du) for k = 1 .. octant_cols - 1 (column edges within an octant).
    double tan_edges[kMaxOctantCols] = {};
};

class Binning {
public:
    static constexpr std::ptrdiff_t kOutside = -1;
    static constexpr std::ptrdiff_t kNaN = -2;

    /// Bins `domain` at `resolution`; zero fields take the defaults: 200 cells
    /// for 1D domains and 32 x 32 for boxes, the disk (phi x r^2) and spherical
    /// caps (phi x z). About 1000 cells is what Mann and Wald's rule for the
    /// number of chi-square classes gives at 10^6 samples and a level near 1e-3
    /// (k ~ 4 (2 N^2 / z^2)^(1/5) ~ 700): more cells dilute the power against
    /// the broad, smooth deviations typical of warp bugs (a 2% error over half
    /// the domain gives p ~ 1e-6 with 2048 cells but ~1e-15 with 1024); fewer
    /// blur local ones. A uniform density gets ~1000 samples per cell.
    explicit Binning(const Domain& domain, BinResolution resolution = {});
    /// Bins `domain` into the cells of `edges` (checked: ascending, spanning
    /// the parameter rectangle, as many columns in every row); `resolution`
    /// supplies only an unbounded line's half_line_scale and line_center. An
    /// interval's interior column edges are rounded up to floats, as the
    /// uniform cells' are (see interval_edges_).
    Binning(const Domain& domain, BinResolution resolution, CellEdges edges);

    const Domain& domain() const { return domain_; }
    const BinResolution& resolution() const { return resolution_; }
    /// 1 for intervals and half-lines, 2 otherwise.
    int parameter_dimension() const { return dims_; }
    int cols() const { return cols_; }
    int rows() const { return rows_; }
    std::size_t cell_count() const { return static_cast<std::size_t>(cols_) * static_cast<std::size_t>(rows_); }

    /// How far parameter `axis` moves when one coordinate of the domain point at
    /// parameters (u, v) moves by one float step (the largest over the
    /// coordinates): the resolution of a float sample along that axis there.
    double float_resolution(int axis, double u, double v) const;
    /// The same for a density that reads its point's coordinates as it
    /// likes: on a spherical cap also z itself (a cap's pdf tests w.z >=
    /// cos_max), whose float step near the pole is far coarser than cos theta
    /// read off x and y. What a jump of the density at float points may move
    /// by (chi2/quadrature.h's jump band).
    double reading_resolution(int axis, double u, double v) const;

    /// Whether the cells have edges of their own (CellEdges) rather than a uniform grid.
    bool has_own_edges() const { return !edges_.empty(); }
    const CellEdges& edges() const { return edges_; }

    /// The parameter range; v is [0, 1] for 1D domains.
    ParamRect parameter_bounds() const { return bounds_; }
    ParamRect cell_rect(std::size_t cell) const;
    /// The rectangles the density is integrated over for `cell`: the cell
    /// itself, or its pieces (CellEdges::pieces).
    std::vector<ParamRect> integration_pieces(std::size_t cell) const;
    bool has_integration_pieces() const { return !edges_.pieces.empty(); }

    /// The cell's length, area or solid angle (infinite for a half-line's tail cell).
    double cell_measure(std::size_t cell) const;

    /// The domain point at parameters (u, v) and the measure density there.
    DomainPoint point_at(double u, double v) const;
    double jacobian(double u, double v) const;
    /// Azimuthal domains only (Domain::azimuthal): the radius and height of the
    /// ring at parameter v, so that point_at(u, v) = (r cos u, r sin u, z).
    std::array<double, 2> ring(double v) const;

    /// Parameters of a point of the domain (no tolerance handling): the inverse of point_at.
    std::array<double, 2> parameters_of(const DomainPoint& p) const;

    /// The cell of `p`, or kOutside / kNaN. Points within kDomainTolerance
    /// outside go to the nearest cell. Uses the exact (libm) atan2.
    std::ptrdiff_t cell_of(const DomainPoint& p) const;
    /// The cell at parameters (u, v), clamped into the grid (u wraps for phi).
    std::size_t cell_at_parameters(double u, double v) const;

    /// Deals the pole samples of `hist` out over each row's columns, evenly
    /// for uniform columns and in proportion to their azimuth otherwise (a
    /// density continuous at the pole is uniform in the azimuth there).
    void spread_poles(Histogram& hist) const;

    /// Adds `points` to `hist` (whose counts must have cell_count() entries).
    /// When `zero_cells` is not empty (one flag per cell), a sample that lands in
    /// a flagged cell but lies within the tolerance of an unflagged cell is
    /// moved there and counted in hist.snapped: rounding at the edge of a
    /// density's support must not read as a sample where the density is zero.
    void bin(std::span<const std::array<float, 3>> points, Histogram& hist,
             std::span<const unsigned char> zero_cells = {}) const;
    void bin(std::span<const DomainPoint> points, Histogram& hist, std::span<const unsigned char> zero_cells = {}) const;

    /// The constants for validate/lanes/lane_cells.h, when this binning has them: an
    /// azimuthal domain (disk, sphere, cap) with the octant table and at most
    /// LanePlan::kMaxOctantCols columns per octant. Empty otherwise.
    std::optional<LanePlan> lane_plan() const;

    /// Axis names for plots: "x", "phi", "cos theta", "r^2", "t = d/(s+d)".
    std::string u_label() const;
    std::string v_label() const;
    /// The centre of a cell along u in the domain's own coordinate (for 1D plots:
    /// x for intervals; for the half-line the left edge of the tail cell).
    double cell_position(std::size_t cell) const;

private:
    template <typename Point>
    void bin_impl(std::span<const Point> points, Histogram& hist, std::span<const unsigned char> zero_cells) const;
    void count_pole(Histogram& hist, std::size_t row) const;
    void check_edges();
    int row_of(double v) const;
    int column_of(int row, double u) const;
    /// The column of (x, y)'s azimuth on the uniform grid.
    int uniform_phi_column(double x, double y) const;
    /// The column of (x, y)'s azimuth in `row` of cells with own edges; sets phi.
    int own_phi_column(int row, double x, double y, double& phi) const;
    void build_interval_edges();
    void build_phi_table();
    bool on_parameter_boundary(double u, double v) const;
    std::size_t snap_from_zero_cell(double u, double v, std::size_t cell, std::span<const unsigned char> zero_cells,
                                    uint64_t& snapped) const;
    /// How far each parameter moves when a coordinate of the point at (u, v)
    /// moves kSnapFloatSteps float spacings of the domain's extent.
    std::array<double, 2> rounding_reach(double u, double v) const;
    /// A float warp's coordinates are within a few roundings of terms as large
    /// as the domain (the consistency check's probe uses 4 such spacings).
    static constexpr double kSnapFloatSteps = 4.0;

    Domain domain_;
    BinResolution resolution_;
    int dims_ = 1;
    int cols_ = 1;
    int rows_ = 1;
    ParamRect bounds_;
    double du_ = 1.0, dv_ = 1.0;  // cell sizes in parameter space
    double tol_x_ = 0.0, tol_y_ = 0.0;  // domain_.slack(), cached for the binning loops
    // Column of phi without atan (when cols is a multiple of 8): reduce (x, y)
    // to t = min/max in [0, 1] of one octant; the octant's column edges are at
    // t = tan(k du), found by a lookup on t and a comparison or two.
    int octant_cols_ = 0;              // cols / 8, or 0 when the table is not used
    std::vector<double> tan_edges_;    // tan(k du), k = 0..octant_cols_ - 1, then +inf
    std::vector<int> edge_lookup_;     // edges <= m / lookup_scale_, for m = 0..lookup_scale_
    double lookup_scale_ = 0.0;
    int phi_column_by_table(double x, double y) const;
    // Interval cells: interior edges rounded up to the next float. Samples are
    // floats, and a float x satisfies x >= e exactly when x >= (e rounded up to a
    // float), so the cells hold the same samples while their expected counts are
    // integrated over the span that those samples actually cover. This makes the
    // test exact for samplers whose outputs are discrete at the cell scale (every
    // float of a narrow interval, drawn with the probability of its spacing).
    std::vector<double> interval_edges_;
    int interval_column(double x) const;
    // Cells with edges of their own (empty: the uniform grid above), and a
    // lookup for each list of edges: uniform buckets across its range, each
    // naming the part that holds its start, so that a point's part is found
    // by one multiplication and, where a bucket holds edges, a search among
    // those alone.
    CellEdges edges_;
    struct EdgeLookup {
        double lo = 0.0, scale = 0.0;
        std::vector<uint32_t> first;  ///< per bucket, and one past the end
        void build(const std::vector<double>& e, std::size_t buckets_per_part);
        /// The largest i < e.size() - 1 with e[i] <= x (0 below e[1] and for NaN).
        int find(const std::vector<double>& e, double x) const;
    };
    EdgeLookup row_lookup_;
    std::vector<EdgeLookup> column_lookup_;
};

/// `requested` (zero fields: the domain's defaults, as Binning fills them in)
/// with fewer cells along any axis whose cells are too narrow for float
/// samples: a cell's expected count is uncertain by kEdgeFloatSteps float
/// steps of probability at each of its two edges (chi2_test.h), so cells are
/// halved along that axis until each spans at least 3 sqrt(E) float steps
/// there, E being the average expected count per cell (the band of an
/// average cell then stays within one Poisson deviation). A tiny cap's
/// cos theta or a narrow interval gets fewer, wider cells; other domains are
/// unchanged. An azimuth keeps at least 8 columns.
BinResolution float_aware_resolution(const Domain& domain, BinResolution requested, uint64_t samples);

/// atan2(y, x) mapped to [0, 2 pi), within 3e-8 of the exact value: the
/// polynomial of Abramowitz & Stegun 4.4.49 (|error| <= 2e-8 on [0, 1]) after
/// reduction to the first octant. Binning uses it away from cell edges and the
/// exact atan2 near them.
double fast_phi(double x, double y);

}  // namespace warpcheck::chi2

// Registering warps from a C++17 translation unit. warpcheck's own headers are
// C++20; a renderer that compiles as C++17 includes only this header (which
// is C++17 and includes nothing else of warpcheck) in its own files, links
// warpcheck::main as usual (the program's main() and the checks are compiled as
// C++20), and defines warpcheck_register with the functions below:
//
//     #include <validate/api/register17.h>
//     void warpcheck_register(warpcheck::Registry& registry) {
//         warpcheck::cxx17::add_case(registry, info, MyWarp{...});
//     }
//
// The same one way as make_warp_case (validate/api/warp_case.h): a warp object
// with const members sample, and pdf, invert, eval as it has them, whose types
// say the input and the kind of case. Its types are the plain ones below
// (float, Point2, Point, uint32_t, uint64_t, an integer index, PdfSample,
// WeightedSample, DiscreteSample): a renderer's own types go through a small
// adapter object. The header turns the object into std::functions over plain
// arrays, and the C++20 side makes the same case of it as make_warp_case
// would, validated the same way. In CMake, link the C++17 files' target to
// warpcheck::register17 (include path only) and the program to warpcheck::main.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace warpcheck {
class Registry;  // defined in validate/api/registry.h (C++20); only referred to here
}  // namespace warpcheck

/// Defined by the program that links warpcheck::main (as in validate/api/external.h).
void warpcheck_register(warpcheck::Registry& registry);

namespace warpcheck::cxx17 {

/// A uniform input of [0,1)^2, or a point of the plane: (x, y).
using Point2 = std::array<float, 2>;
/// A direction (x, y, z).
using Point = std::array<float, 3>;

/// What sample returns besides the point (warp_case.h says what each means).
template <typename X>
struct PdfSample {
    X x;
    float pdf;
};
template <typename X>
struct WeightedSample {
    X x;
    float weight;
};
struct DiscreteSample {
    std::uint32_t index;
    float u_remapped;
};

/// The domain and the measure the pdf is a density of.
struct Domain {
    enum class Kind {
        Interval,       ///< [a, b], length
        HalfLine,       ///< [a, inf), length
        LowerHalfLine,  ///< (-inf, b], length
        RealLine,       ///< (-inf, inf), length
        Box,            ///< [a, b] x [c, d], area
        UnitDisk,       ///< area
        SphericalCap,   ///< directions with z >= c (sphere: c = -1, hemisphere: 0), solid angle
        Triangle,       ///< the triangle of `vertices`, area
    };
    Kind kind = Kind::Interval;
    double a = 0.0, b = 1.0, c = 0.0, d = 1.0;
    /// Triangle: its vertices (x0, y0, x1, y1, x2, y2).
    std::array<double, 6> vertices{};

    static Domain interval(double lo, double hi) { return {Kind::Interval, lo, hi, 0.0, 0.0}; }
    static Domain half_line(double lo) { return {Kind::HalfLine, lo, 0.0, 0.0, 0.0}; }
    static Domain lower_half_line(double hi) { return {Kind::LowerHalfLine, 0.0, hi, 0.0, 0.0}; }
    static Domain real_line() { return {Kind::RealLine, 0.0, 0.0, 0.0, 0.0}; }
    static Domain box(double x0, double x1, double y0, double y1) { return {Kind::Box, x0, x1, y0, y1}; }
    static Domain unit_square() { return box(0.0, 1.0, 0.0, 1.0); }
    static Domain unit_disk() { return {Kind::UnitDisk, 0.0, 0.0, 0.0, 0.0}; }
    static Domain spherical_cap(double z_min) { return {Kind::SphericalCap, 0.0, 0.0, z_min, 0.0}; }
    static Domain sphere() { return spherical_cap(-1.0); }
    static Domain hemisphere() { return spherical_cap(0.0); }
    /// The triangle with vertices p, q, r (e.g. a light's triangle or half of a quad).
    static Domain triangle(const std::array<double, 2>& p, const std::array<double, 2>& q,
                           const std::array<double, 2>& r) {
        Domain t{Kind::Triangle, 0.0, 0.0, 0.0, 0.0};
        t.vertices = {p[0], p[1], q[0], q[1], r[0], r[1]};
        return t;
    }
};

/// How many cells the chi-square checks use (WarpCaseInfo::chi2_resolution,
/// chi2::BinResolution, says what each field means); zeros take the defaults.
struct BinResolution {
    int first = 0;
    int second = 0;
    double half_line_scale = 0.0;
    double line_center = 0.0;
};

/// A monotone 1D view of the warp for the tabulated check (validate/api/warp_case.h,
/// MonotoneMarginal, says what each field means).
struct View {
    int input_coordinate = 0;
    bool increasing = true;
    double lo = 0.0, hi = 1.0;
    double tail_mass = 0.0;        ///< probability above hi
    double lower_tail_mass = 0.0;  ///< probability below lo
    std::string label;
    std::function<double(const Point&)> coordinate;  ///< empty: x
    std::function<double(double)> pdf;               ///< empty: the warp's pdf (1D warps)
};

/// Whether sample is the inversion method (WarpCaseInfo::inversion says what each means).
enum class Inversion { Measure, Claimed, NotInversion };

/// The case's description (WarpCaseInfo says what each field means); the
/// input is read off sample's argument.
struct CaseInfo {
    std::string family;
    std::vector<std::pair<std::string, double>> params;
    std::string description;
    Domain domain = Domain::unit_square();
    double roundtrip_tolerance = 1.0 / 65536.0;
    bool exact_inverse = false;
    std::vector<View> views;
    Inversion inversion = Inversion::Measure;
    double support_measure = 0.0;  ///< where the density is positive, if less than the domain
    std::size_t categories = 0;    ///< discrete cases: how many indices sample chooses among
    BinResolution chi2_resolution{};  ///< the chi-square checks' cells (zeros: the defaults)
};

/// What a float sampler claims about its order (external.h, Monotone).
enum class Monotone : bool { NotClaimed = false, Claimed = true };
/// Which inputs of a u64 -> float sampler the exhaustive check enumerates (external.h, U64Subrange).
struct U64Subrange {
    int shift = 32;
    std::uint64_t low_bits = 0;
};

/// The values a parameter may take beyond its grid, for validate --fuzz
/// (validate/api/registry.h, ParamRange): [lo, hi], each end included
/// unless open.
struct ParamRange {
    double lo = std::numeric_limits<double>::quiet_NaN();
    double hi = std::numeric_limits<double>::quiet_NaN();
    bool lo_open = false;
    bool hi_open = false;
};

/// One parameter of a grid, the values it takes, in order, and the ranges
/// --fuzz may draw it from (none: its grid values only).
struct GridAxis {
    std::string name;
    std::vector<double> values;
    std::vector<ParamRange> ranges{};
};

/// One point of a grid: its parameters in axis order, looked up by name.
class GridPoint {
public:
    explicit GridPoint(std::vector<std::pair<std::string, double>> params) : params_(std::move(params)) {}
    /// The value of the named axis; an unknown name is a std::invalid_argument.
    double operator[](const std::string& name) const;
    const std::vector<std::pair<std::string, double>>& params() const { return params_; }

private:
    std::vector<std::pair<std::string, double>> params_;
};

/// A BSDF's or phase function's sample as a renderer returns it (pbrt-v4's
/// BSDFSample): the direction wi, f(wo, wi) (for a delta lobe the value whose
/// f |cos theta_i| / pdf is the weight), the pdf (for a delta lobe the
/// probability of choosing it; 0: no sample), its lobe, and for transmission
/// eta(wi's side) / eta(wo's side). Directions in the shading frame, z the normal.
struct BsdfSample {
    Point wi{};
    float f = 0.0f;
    float pdf = 0.0f;
    bool transmission = false;  ///< wi on the other side of the surface
    bool delta = false;         ///< a delta lobe (mirror, smooth refraction)
    float eta = 1.0f;
};

/// A BSDF case: its name, the outgoing direction wo it is checked at, and what
/// it claims (BsdfClaims in validate/api/bsdf_case.h says what each means).
struct BsdfInfo {
    std::string family;
    std::vector<std::pair<std::string, double>> params;
    std::string description;
    Point wo{0.0f, 0.0f, 1.0f};  ///< unit length, off the horizon
    bool reflection = true, transmission = false;  ///< the sides it samples
    bool continuous = true, delta = false;         ///< lobes with a density, delta lobes
    bool reciprocal = true;      ///< f(wo, wi) = f(wi, wo) (the eta^2 rule across an interface)
    bool importance = false;     ///< transmitted f without the 1 / eta^2 of radiance
    float eta = 1.0f;            ///< index below the surface over above
    bool phase_function = false; ///< wi on the whole sphere, weight p / pdf (no cosine)
    bool stochastic = false;     ///< f an estimate, the sample's pdf proportional, pdf() for MIS (a layered BSDF)
    BinResolution chi2_resolution{};  ///< bsdf_chi2's cells (zeros: the defaults)
};

/// A spectral BSDF's sample with N channels (SpectralSample of sampling/bsdf.h):
/// RGB, or N wavelengths of which the hero drew wi. f and pdf per channel (a
/// secondary wavelength the sample terminates, as a dispersive refraction
/// does: pdf 0 in that channel), the lobe as BsdfSample's, and the hero's eta.
template <std::size_t N>
struct SpectralBsdfSample {
    Point wi{};
    std::array<float, N> f{};
    std::array<float, N> pdf{};
    bool transmission = false;
    bool delta = false;
    float eta = 1.0f;
};

/// A light's sample seen from a reference point, as a renderer returns it
/// (LightSample of sampling/light_sample.h): the unit direction wi towards
/// the light, its pdf per solid angle (0: no sample), the radiance L arriving
/// along wi, and the distance to the light.
struct LightSample {
    Point wi{};
    float pdf = 0.0f;
    float L = 0.0f;
    float distance = 0.0f;
};

/// A light case: its name, and the reference point (with the normal of the
/// surface there, or zero for a point in a medium) it is seen from
/// (LightClaims in validate/api/light_case.h).
struct LightInfo {
    std::string family;
    std::vector<std::pair<std::string, double>> params;
    std::string description;
    Point ref{};
    Point normal{};
    BinResolution chi2_resolution{};  ///< the chi-square check's cells (zeros: the defaults)
};

/// An MIS case (MisCase in validate/api/light_case.h): its name, and the
/// heuristic the renderer's MIS sum weighs with (power, exponent 2, or balance).
struct MisInfo {
    std::string family;
    std::vector<std::pair<std::string, double>> params;
    std::string description;
    bool power_heuristic = true;
    BinResolution chi2_resolution{};  ///< the chi-square check's cells (zeros: the defaults)
};

/// One light of an MIS case of several lights (add_mis with a vector): made
/// by mis_light from a light object as add_light takes it, seen from
/// info.ref, with the pdf the MIS sum evaluates at the other strategies'
/// samples where it is not the light's own (empty: the same).
struct MisLight {
    LightInfo info;
    std::function<LightSample(const Point& ref, const Point2& u)> sample;
    std::function<double(const Point& ref, const Point& wi)> pdf, radiance, mis_pdf;
};

namespace detail {

/// What a warp consumes and what its sample returns (warp_case.h: InputKind, SampleReturns).
enum class Input { Uniform1D, Uniform2D, Bits32, Bits64 };
enum class Returns { Point, PointAndPdf, PointAndWeight, Index, IndexAndRemappedU };

/// One input as the C++20 side hands it over: u for uniform inputs, bits for raw bits.
struct WarpInput {
    Point2 u{};
    std::uint64_t bits = 0;
};

/// A warp as the C++20 side takes it: what its types say, as values, and its
/// parts as std::functions over plain arrays (an empty one: the part is missing).
struct ErasedWarp {
    Input input = Input::Uniform2D;
    Returns returns = Returns::Point;
    int dimension = 2;
    /// The point of sample(in), and in `value` what came with it (pdf, weight, remapped u).
    std::function<Point(const WarpInput& in, double& value)> sample;
    std::function<double(const Point&)> pdf;
    std::function<WarpInput(const Point&)> invert;
    std::function<double(const Point&)> eval;
};

/// How the exhaustive check sweeps a float sampler: input_bits 0 (no fast
/// path), 32 (every input) or 64 (the subrange); `block` writes out[i] =
/// sample(i-th input of the sweep from `first`) for i < n.
struct Sweep {
    int input_bits = 0;
    U64Subrange subrange{};
    Monotone monotone = Monotone::NotClaimed;
    std::function<void(std::uint64_t first, std::size_t n, float* out)> block;
};

/// Registers the case of an erased warp (validate/api/register17.cpp).
void add_erased(Registry& registry, const CaseInfo& info, ErasedWarp warp, Sweep sweep = {});
/// grid_points of validate/api/case_grid.h: the product of the axes.
std::vector<GridPoint> grid_points(const CaseInfo& base, const std::vector<GridAxis>& axes);
/// Adds the case of one grid point (its axes' parameters, in order) to a registry.
using PointAdder = std::function<void(Registry& registry, const std::vector<std::pair<std::string, double>>& point)>;
/// Keeps a grid's family (Registry::add_family): --fuzz makes its cases at
/// other points of the axes' ranges through add_point.
void add_family(Registry& registry, const std::string& family,
                const std::vector<std::pair<std::string, double>>& base_params, const std::string& description,
                const std::vector<GridAxis>& axes, PointAdder add_point);
/// A BSDF grid point's wo: bsdf_direction(theta_o, phi_o) of validate/api/bsdf_case.h, in degrees.
Point grid_wo(const GridPoint& point);

using BsdfSampleFn = std::function<BsdfSample(const Point& wo, float uc, const Point2& u)>;
using BsdfEvalFn = std::function<double(const Point& wo, const Point& wi)>;
void add_erased_bsdf(Registry& registry, const BsdfInfo& info, BsdfSampleFn sample, BsdfEvalFn f, BsdfEvalFn pdf);

using LightSampleFn = std::function<LightSample(const Point& ref, const Point2& u)>;
using LightEvalFn = std::function<double(const Point& ref, const Point& wi)>;
void add_erased_light(Registry& registry, const LightInfo& info, LightSampleFn sample, LightEvalFn pdf,
                      LightEvalFn radiance);

/// A BSDF's parts and its lights, and the pdfs the MIS sum evaluates (empty: their own).
struct ErasedMis {
    BsdfSampleFn bsdf_sample;
    BsdfEvalFn bsdf_f, bsdf_pdf, bsdf_mis_pdf;
    std::vector<MisLight> lights;
};
void add_erased_mis(Registry& registry, const MisInfo& info, const BsdfInfo& bsdf, ErasedMis parts);

/// A spectral BSDF's parts over plain arrays of `channels` floats: sample
/// returns wi, the lobe and eta (its f and pdf unused) and writes every
/// channel's f and pdf; f and pdf write every channel's value at (wo, wi).
struct ErasedSpectralBsdf {
    std::size_t channels = 0;
    std::function<BsdfSample(const Point& wo, float uc, const Point2& u, int hero, float* f, float* pdf)> sample;
    std::function<void(const Point& wo, const Point& wi, float* out)> f, pdf;
};
/// Registers the case of one hero channel (validate/api/register17.cpp); at most 16 channels.
void add_erased_spectral_bsdf(Registry& registry, const BsdfInfo& info, ErasedSpectralBsdf bsdf, int hero);

/// What sample returns, when it is a point or an index: itself, and nothing with it.
template <typename T, Returns R>
struct ReturnedAlone {
    static constexpr bool known = true;
    using PointType = T;
    static constexpr Returns returns = R;
    static const T& point(const T& r) { return r; }
    static double value(const T&) { return 0.0; }
};

/// One traits struct per type, as warp_case.h's WarpType: as sample's
/// argument (is_input, input, to_input, from_input), as a point (dimension,
/// to_point, from_point) and as what sample returns (point, value).
template <typename T, typename = void>
struct Type {
    static constexpr bool known = false;
    static constexpr bool is_input = false;
};
template <>
struct Type<float> : ReturnedAlone<float, Returns::Point> {
    static constexpr bool is_input = true;
    static constexpr Input input = Input::Uniform1D;
    static constexpr int dimension = 1;
    static WarpInput to_input(float u) { return {{u, 0.0f}, 0}; }
    static float from_input(const WarpInput& in) { return in.u[0]; }
    static Point to_point(float x) { return {x, 0.0f, 0.0f}; }
    static float from_point(const Point& p) { return p[0]; }
};
template <>
struct Type<Point2> : ReturnedAlone<Point2, Returns::Point> {
    static constexpr bool is_input = true;
    static constexpr Input input = Input::Uniform2D;
    static constexpr int dimension = 2;
    static WarpInput to_input(const Point2& u) { return {u, 0}; }
    static Point2 from_input(const WarpInput& in) { return in.u; }
    static Point to_point(const Point2& p) { return {p[0], p[1], 0.0f}; }
    static Point2 from_point(const Point& p) { return {p[0], p[1]}; }
};
template <>
struct Type<Point> : ReturnedAlone<Point, Returns::Point> {
    static constexpr bool is_input = false;
    static constexpr int dimension = 3;
    static Point to_point(const Point& p) { return p; }
    static Point from_point(const Point& p) { return p; }
};
/// An integer: as an input, raw bits (uint32_t or uint64_t); as what sample
/// returns, a discrete index.
template <typename T>
struct Type<T, std::enable_if_t<std::is_integral_v<T>>> : ReturnedAlone<T, Returns::Index> {
    static constexpr bool is_input = std::is_same_v<T, std::uint32_t> || std::is_same_v<T, std::uint64_t>;
    static constexpr Input input = std::is_same_v<T, std::uint32_t> ? Input::Bits32 : Input::Bits64;
    static constexpr int dimension = 0;
    static WarpInput to_input(T bits) { return {{}, static_cast<std::uint64_t>(bits)}; }
    static T from_input(const WarpInput& in) { return static_cast<T>(in.bits); }
    static Point to_point(T index) { return {static_cast<float>(index), 0.0f, 0.0f}; }
    static T from_point(const Point& p) { return static_cast<T>(p[0]); }
};
template <typename X>
struct Type<PdfSample<X>> {
    static constexpr bool known = Type<X>::known;
    static constexpr bool is_input = false;
    using PointType = X;
    static constexpr Returns returns = Returns::PointAndPdf;
    static const X& point(const PdfSample<X>& r) { return r.x; }
    static double value(const PdfSample<X>& r) { return r.pdf; }
};
template <typename X>
struct Type<WeightedSample<X>> {
    static constexpr bool known = Type<X>::known;
    static constexpr bool is_input = false;
    using PointType = X;
    static constexpr Returns returns = Returns::PointAndWeight;
    static const X& point(const WeightedSample<X>& r) { return r.x; }
    static double value(const WeightedSample<X>& r) { return r.weight; }
};
template <>
struct Type<DiscreteSample> {
    static constexpr bool known = true;
    static constexpr bool is_input = false;
    using PointType = std::uint32_t;
    static constexpr Returns returns = Returns::IndexAndRemappedU;
    static std::uint32_t point(const DiscreteSample& r) { return r.index; }
    static double value(const DiscreteSample& r) { return r.u_remapped; }
};

/// The argument type of a const member function.
template <typename M>
struct ArgOf {};
template <typename C, typename R, typename A>
struct ArgOf<R (C::*)(A) const> {
    using type = std::decay_t<A>;
};
template <typename C, typename R, typename A>
struct ArgOf<R (C::*)(A) const noexcept> : ArgOf<R (C::*)(A) const> {};

/// Whether W has the member.
template <typename W, typename = void>
struct HasPdf : std::false_type {};
template <typename W>
struct HasPdf<W, std::void_t<decltype(&W::pdf)>> : std::true_type {};
template <typename W, typename = void>
struct HasInvert : std::false_type {};
template <typename W>
struct HasInvert<W, std::void_t<decltype(&W::invert)>> : std::true_type {};
template <typename W, typename = void>
struct HasEval : std::false_type {};
template <typename W>
struct HasEval<W, std::void_t<decltype(&W::eval)>> : std::true_type {};

/// A warp object's types: In what sample takes, Result what it returns, Out the point in it.
template <typename W>
struct TypesOf {
    using In = typename ArgOf<decltype(&W::sample)>::type;
    using Result = std::decay_t<decltype(std::declval<const W&>().sample(std::declval<In>()))>;
    using Out = typename Type<Result>::PointType;
};

/// The warp object as an ErasedWarp: one shared copy, called by every part.
template <typename W>
ErasedWarp erase(W warp) {
    using In = typename TypesOf<W>::In;
    using Result = typename TypesOf<W>::Result;
    using Out = typename TypesOf<W>::Out;
    static_assert(Type<In>::is_input, "sample must take float or Point2 (uniform input) or uint32_t or uint64_t");
    static_assert(Type<Result>::known && Type<Out>::known,
                  "sample must return float, Point2, Point, an integer index, PdfSample<X>, WeightedSample<X> or "
                  "DiscreteSample");
    using R = Type<Result>;
    using O = Type<Out>;
    const auto w = std::make_shared<const W>(std::move(warp));
    ErasedWarp e;
    e.input = Type<In>::input;
    e.returns = R::returns;
    e.dimension = O::dimension;
    e.sample = [w](const WarpInput& in, double& value) {
        const Result r = w->sample(Type<In>::from_input(in));
        value = R::value(r);
        return O::to_point(R::point(r));
    };
    if constexpr (HasPdf<W>::value)
        e.pdf = [w](const Point& p) { return static_cast<double>(w->pdf(O::from_point(p))); };
    if constexpr (HasInvert<W>::value)
        e.invert = [w](const Point& p) { return Type<In>::to_input(w->invert(O::from_point(p))); };
    if constexpr (HasEval<W>::value)
        e.eval = [w](const Point& p) { return static_cast<double>(w->eval(O::from_point(p))); };
    return e;
}

/// Whether a BSDF object's sample takes the lobe's uc (sample(wo, uc, u)) or
/// not (a phase function's sample(wo, u)), and whether it names its value f or p.
template <typename B, typename = void>
struct SamplesWithUc : std::false_type {};
template <typename B>
struct SamplesWithUc<B, std::void_t<decltype(std::declval<const B&>().sample(std::declval<const Point&>(), 0.0f,
                                                                             std::declval<const Point2&>()))>>
    : std::true_type {};
template <typename B, typename = void>
struct HasF : std::false_type {};
template <typename B>
struct HasF<B, std::void_t<decltype(&B::f)>> : std::true_type {};
template <typename B, typename = void>
struct HasEtaOf : std::false_type {};
template <typename B>
struct HasEtaOf<B, std::void_t<decltype(std::declval<const B&>().eta(0))>> : std::true_type {};

/// A BSDF object's sample, with or without the lobe's uc.
template <typename B>
BsdfSampleFn erase_bsdf_sample(std::shared_ptr<const B> b) {
    return [b](const Point& wo, float uc, const Point2& u) {
        if constexpr (SamplesWithUc<B>::value) {
            return BsdfSample(b->sample(wo, uc, u));
        } else {
            (void)uc;
            return BsdfSample(b->sample(wo, u));
        }
    };
}

/// The number of channels of a spectral BSDF object: the size of the array its f returns.
template <typename B>
constexpr std::size_t channels_of() {
    using Values = std::decay_t<decltype(std::declval<const B&>().f(std::declval<const Point&>(),
                                                                      std::declval<const Point&>()))>;
    return std::tuple_size<Values>::value;
}

/// add_bsdf_grid's loop: `add` registers one point's case (its info, the point).
template <typename Add>
void add_grid_of_bsdfs(Registry& registry, const BsdfInfo& base, const std::vector<GridAxis>& axes, Add add) {
    const auto add_point = [base, add](Registry& r, const std::vector<std::pair<std::string, double>>& point) {
        BsdfInfo info = base;
        info.params.insert(info.params.end(), point.begin(), point.end());
        const GridPoint p(point);
        info.wo = grid_wo(p);
        add(r, info, p);
    };
    CaseInfo names;
    names.family = base.family;
    names.params = base.params;
    for (const GridPoint& point : grid_points(names, axes)) add_point(registry, point.params());
    add_family(registry, base.family, base.params, base.description, axes, add_point);
}

}  // namespace detail

/// Adds the case of a warp object: a class with a const `sample(In)` member
/// and, as it has them, `pdf(Out)`, `invert(Out) -> In` and `eval(Out)`, none
/// overloaded or a template. In is float or Point2 (uniform floats) or
/// uint32_t or uint64_t (raw bits); sample returns Out (float, Point2 or
/// Point), PdfSample<Out>, WeightedSample<Out> (with eval), an integer index or
/// DiscreteSample (with info.categories; pdf is the pmf). Refused, as
/// Registry::add_case refuses, where the declaration contradicts itself.
template <typename W>
void add_case(Registry& registry, const CaseInfo& info, W warp) {
    detail::add_erased(registry, info, detail::erase(std::move(warp)));
}

/// A u32 -> float sampler on the exhaustive check's fast path (external.h,
/// make_u32_float_case): a warp object whose sample(std::uint32_t) returns a
/// float, on an interval domain. The block loop over all 2^32 inputs is
/// compiled here, with sample inlined.
template <typename W>
void add_u32_float_case(Registry& registry, const CaseInfo& info, Monotone monotone, W warp) {
    static_assert(std::is_same_v<typename detail::TypesOf<W>::In, std::uint32_t> &&
                      std::is_same_v<typename detail::TypesOf<W>::Result, float>,
                  "add_u32_float_case: sample must be std::uint32_t -> float");
    const auto w = std::make_shared<const W>(warp);
    detail::Sweep sweep{32, {}, monotone, [w](std::uint64_t first, std::size_t n, float* out) {
                            const auto base = static_cast<std::uint32_t>(first);
                            const auto count = static_cast<std::uint32_t>(n);  // keeps the loop in 32-bit lanes
                            for (std::uint32_t i = 0; i < count; ++i) out[i] = w->sample(base + i);
                        }};
    detail::add_erased(registry, info, detail::erase(std::move(warp)), std::move(sweep));
}

/// A u64 -> float sampler on the fast path (make_u64_float_case): its sweep
/// enumerates u = (i << shift) | low_bits for every i < 2^(64 - shift).
template <typename W>
void add_u64_float_case(Registry& registry, const CaseInfo& info, U64Subrange subrange, Monotone monotone, W warp) {
    static_assert(std::is_same_v<typename detail::TypesOf<W>::In, std::uint64_t> &&
                      std::is_same_v<typename detail::TypesOf<W>::Result, float>,
                  "add_u64_float_case: sample must be std::uint64_t -> float");
    const auto w = std::make_shared<const W>(warp);
    detail::Sweep sweep{64, subrange, monotone, [w, subrange](std::uint64_t first, std::size_t n, float* out) {
                            for (std::size_t i = 0; i < n; ++i)
                                out[i] = w->sample(((first + i) << subrange.shift) | subrange.low_bits);
                        }};
    detail::add_erased(registry, info, detail::erase(std::move(warp)), std::move(sweep));
}

/// add_case for every point of the product of the axes (the first varying
/// slowest): make(point) returns the point's warp object, and the case is
/// named family[...base params...,axis=value,...]. Refused as add_case_grid
/// (validate/api/case_grid.h) refuses: an axis without values or with a
/// non-finite one, two parameters of one name.
/// The family is kept too, for --fuzz (the axes' ranges).
template <typename Maker>
void add_case_grid(Registry& registry, const CaseInfo& base, const std::vector<GridAxis>& axes, Maker make) {
    const auto shared = std::make_shared<Maker>(std::move(make));
    const auto add_point = [base, shared](Registry& r, const std::vector<std::pair<std::string, double>>& point) {
        CaseInfo info = base;
        info.params.insert(info.params.end(), point.begin(), point.end());
        add_case(r, info, (*shared)(GridPoint(point)));
    };
    for (const GridPoint& point : detail::grid_points(base, axes)) add_point(registry, point.params());
    detail::add_family(registry, base.family, base.params, base.description, axes, add_point);
}

/// Adds a BSDF case that the BSDF checks take (bsdf_chi2, bsdf_weight,
/// bsdf_delta, bsdf_albedo, bsdf_reciprocity), from a BSDF object: const
/// members sample(const Point& wo, float uc, const Point2& u) -> BsdfSample
/// (or sample(wo, u) without the lobe's uc), f(wo, wi) (a phase function's
/// p(wo, wi)) and pdf(wo, wi). Validated as make_bsdf_case validates (a bad wo
/// or no lobes throws std::invalid_argument naming the case).
template <typename B>
void add_bsdf(Registry& registry, const BsdfInfo& info, B bsdf) {
    const auto b = std::make_shared<const B>(std::move(bsdf));
    detail::BsdfSampleFn sample = detail::erase_bsdf_sample(b);
    detail::BsdfEvalFn f = [b](const Point& wo, const Point& wi) {
        if constexpr (detail::HasF<B>::value) return static_cast<double>(b->f(wo, wi));
        else return static_cast<double>(b->p(wo, wi));
    };
    detail::BsdfEvalFn pdf = [b](const Point& wo, const Point& wi) { return static_cast<double>(b->pdf(wo, wi)); };
    detail::add_erased_bsdf(registry, info, std::move(sample), std::move(f), std::move(pdf));
}

/// add_bsdf for every point of the product of the axes (bsdf_grid.h): wo from
/// the point's theta_o (and phi_o, where there is one) in degrees, make(point)
/// the BSDF object; cases named family[...base params...,axis=value,...]. The
/// family is kept too, for --fuzz (the axes' ranges: theta_o's may reach
/// grazing and below the surface, with the horizon itself left out).
template <typename Maker>
void add_bsdf_grid(Registry& registry, const BsdfInfo& base, const std::vector<GridAxis>& axes, Maker make) {
    const auto shared = std::make_shared<Maker>(std::move(make));
    detail::add_grid_of_bsdfs(registry, base, axes, [shared](Registry& r, const BsdfInfo& info, const GridPoint& p) {
        add_bsdf(r, info, (*shared)(p));
    });
}

/// Adds the case of one channel of a spectral BSDF (make_spectral_bsdf_case
/// of validate/api/bsdf_case.h): `hero` in [0, N) is the channel it samples
/// with (name it: add hero to info.params, or use add_spectral_bsdf_grid).
/// The object has const members sample(const Point& wo, float uc, const
/// Point2& u, int hero) -> SpectralBsdfSample<N>, f(wo, wi) and pdf(wo, wi)
/// -> std::array<float, N> (every channel's, N <= 16), and where it
/// transmits with an index per channel, eta(int channel) (info.eta then
/// takes the hero's). Every BSDF check runs on the hero channel, and
/// bsdf_spectral holds the other channels' values at its samples to f() and
/// pdf(). A hero outside [0, N) is a std::invalid_argument.
template <typename B>
void add_spectral_bsdf(Registry& registry, BsdfInfo info, B bsdf, int hero) {
    constexpr std::size_t kN = detail::channels_of<B>();
    static_assert(kN >= 1 && kN <= 16, "add_spectral_bsdf: f must return std::array<float, N> with 1 <= N <= 16");
    if constexpr (detail::HasEtaOf<B>::value) {
        if (hero >= 0 && hero < static_cast<int>(kN)) info.eta = static_cast<float>(bsdf.eta(hero));
    }
    const auto b = std::make_shared<const B>(std::move(bsdf));
    detail::ErasedSpectralBsdf e;
    e.channels = kN;
    e.sample = [b](const Point& wo, float uc, const Point2& u, int h, float* f, float* pdf) {
        const SpectralBsdfSample<kN> s = b->sample(wo, uc, u, h);
        for (std::size_t c = 0; c < kN; ++c) f[c] = s.f[c], pdf[c] = s.pdf[c];
        BsdfSample out;
        out.wi = s.wi;
        out.transmission = s.transmission;
        out.delta = s.delta;
        out.eta = s.eta;
        return out;
    };
    e.f = [b](const Point& wo, const Point& wi, float* out) {
        const std::array<float, kN> v = b->f(wo, wi);
        for (std::size_t c = 0; c < kN; ++c) out[c] = v[c];
    };
    e.pdf = [b](const Point& wo, const Point& wi, float* out) {
        const std::array<float, kN> v = b->pdf(wo, wi);
        for (std::size_t c = 0; c < kN; ++c) out[c] = v[c];
    };
    detail::add_erased_spectral_bsdf(registry, info, std::move(e), hero);
}

/// add_spectral_bsdf for every point of the product of the axes, as
/// add_bsdf_grid: one axis must be "hero" (the channel each case samples
/// with: its values 0 .. N - 1, or the ones to check), make(point) returns
/// the spectral BSDF object.
template <typename Maker>
void add_spectral_bsdf_grid(Registry& registry, const BsdfInfo& base, const std::vector<GridAxis>& axes, Maker make) {
    const auto shared = std::make_shared<Maker>(std::move(make));
    detail::add_grid_of_bsdfs(registry, base, axes, [shared](Registry& r, const BsdfInfo& info, const GridPoint& p) {
        add_spectral_bsdf(r, info, (*shared)(p), static_cast<int>(p["hero"]));
    });
}

/// Adds a light case (validate/api/light_case.h) that the warp checks (chi2,
/// consistency, sample_pdf) and the light checks (light_radiance,
/// light_support, light_irradiance) take, from a light object: const members
/// sample(const Point& ref, const Point2& u) -> LightSample, pdf(ref, wi) per
/// solid angle and L(ref, wi), the light's own intersection (the radiance
/// arriving along wi, 0 on a miss). Validated as make_light_case validates (a
/// non-finite ref or a normal neither zero nor unit throws std::invalid_argument).
template <typename Lt>
void add_light(Registry& registry, const LightInfo& info, Lt light) {
    const auto l = std::make_shared<const Lt>(std::move(light));
    detail::LightSampleFn sample = [l](const Point& ref, const Point2& u) { return LightSample(l->sample(ref, u)); };
    detail::LightEvalFn pdf = [l](const Point& ref, const Point& wi) { return static_cast<double>(l->pdf(ref, wi)); };
    detail::LightEvalFn radiance = [l](const Point& ref, const Point& wi) { return static_cast<double>(l->L(ref, wi)); };
    detail::add_erased_light(registry, info, std::move(sample), std::move(pdf), std::move(radiance));
}

/// One light of an MIS case (MisLight), from a light object as add_light
/// takes it, seen from info.ref.
template <typename Lt>
MisLight mis_light(const LightInfo& info, Lt light,
                   std::function<double(const Point& ref, const Point& wi)> mis_pdf = nullptr) {
    const auto l = std::make_shared<const Lt>(std::move(light));
    MisLight m;
    m.info = info;
    m.sample = [l](const Point& ref, const Point2& u) { return LightSample(l->sample(ref, u)); };
    m.pdf = [l](const Point& ref, const Point& wi) { return static_cast<double>(l->pdf(ref, wi)); };
    m.radiance = [l](const Point& ref, const Point& wi) { return static_cast<double>(l->L(ref, wi)); };
    m.mis_pdf = std::move(mis_pdf);
    return m;
}

/// Adds an MIS case of a BSDF (as add_bsdf takes it, seen from bsdf_info.wo)
/// and one or more lights (mis_light), all seen from one shading point (the
/// lights' info.ref the same, normal (0, 0, 1), the BSDF's): strategy 0 the
/// BSDF, 1.. the lights in order (make_mis_case of validate/api/light_case.h).
/// bsdf_mis_pdf as below.
template <typename B>
void add_mis(Registry& registry, const MisInfo& info, const BsdfInfo& bsdf_info, B bsdf, std::vector<MisLight> lights,
             std::function<double(const Point& wo, const Point& wi)> bsdf_mis_pdf = nullptr) {
    const auto b = std::make_shared<const B>(std::move(bsdf));
    detail::ErasedMis parts;
    parts.bsdf_sample = detail::erase_bsdf_sample(b);
    parts.bsdf_f = [b](const Point& wo, const Point& wi) { return static_cast<double>(b->f(wo, wi)); };
    parts.bsdf_pdf = [b](const Point& wo, const Point& wi) { return static_cast<double>(b->pdf(wo, wi)); };
    parts.bsdf_mis_pdf = std::move(bsdf_mis_pdf);
    parts.lights = std::move(lights);
    detail::add_erased_mis(registry, info, bsdf_info, std::move(parts));
}

/// Adds an MIS case of a BSDF (as add_bsdf takes it, seen from bsdf_info.wo)
/// and a light (as add_light takes it, seen from light_info.ref with the
/// normal (0, 0, 1), the BSDF's): the MIS checks (mis_weights, mis_estimator)
/// take it. light_mis_pdf(ref, wi) and bsdf_mis_pdf(wo, wi) are the pdfs your
/// MIS code evaluates at the other strategy's samples, where they are not the
/// objects' own pdf() (pass nullptr for "the same"). Validated as
/// make_mis_case validates (delta lobes, another normal: std::invalid_argument).
template <typename B, typename Lt>
void add_mis(Registry& registry, const MisInfo& info, const BsdfInfo& bsdf_info, B bsdf, const LightInfo& light_info,
             Lt light, std::function<double(const Point& ref, const Point& wi)> light_mis_pdf = nullptr,
             std::function<double(const Point& wo, const Point& wi)> bsdf_mis_pdf = nullptr) {
    add_mis(registry, info, bsdf_info, std::move(bsdf), {mis_light(light_info, std::move(light), std::move(light_mis_pdf))},
            std::move(bsdf_mis_pdf));
}

/// The outgoing direction at theta degrees from the normal and azimuth phi degrees.
Point bsdf_direction(double theta_degrees, double phi_degrees = 0.0);

/// Registry::mark_known_flaw for one check of a case ("" for the whole case).
void mark_known_flaw(Registry& registry, const std::string& case_name, const std::string& check_name,
                     const std::string& flaw);

}  // namespace warpcheck::cxx17

// A warp case: one warp with concrete parameter values and a stable name. The
// checks see every warp through this one type-erased interface, which works on
// batches so that the virtual call is paid once per batch, not once per sample.
//
// One way to make a case: make_warp_case(info, warp), where warp is a warp
// object (const members sample, and pdf, invert, eval as it has them) or the
// same parts as named callables, warp_of(sample).with_pdf(pdf). What sample takes and
// returns, and so the input kind and the kind of case, is read off its type
// (detail::WarpType, one traits struct per type).
#pragma once

#include <array>
#include <concepts>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "chi2/domain.h"
#include "sampling/vector.h"

namespace warpcheck {

// The domain a case description names, in warpcheck's own namespace, so that a
// renderer writes warpcheck::Domain::hemisphere() and needs no chi2/ header:
// the domain (chi2/domain.h) and the azimuth in [0, 2 pi) that its spherical
// kinds bin by, for a marginal on phi (chi2/domain_kinds.h).
using chi2::Domain;
using chi2::exact_phi;

struct LaneSampler;

/// What a warp consumes.
enum class InputKind {
    Uniform1D,  ///< one float in [0,1)
    Uniform2D,  ///< a point of [0,1)^2
    Bits32,     ///< 32 raw random bits
    Bits64,     ///< 64 raw random bits
    /// A point of [0,1)^3: a BSDF's (uc, u) (validate/api/bsdf_case.h), uc in u[0].
    Uniform3D,
};

constexpr int input_dimension(InputKind k) {
    return k == InputKind::Uniform3D ? 3 : k == InputKind::Uniform2D ? 2 : 1;
}
constexpr bool takes_bits(InputKind k) { return k == InputKind::Bits32 || k == InputKind::Bits64; }

/// One input of a warp: u[0..2] for uniform inputs (unused coordinates 0),
/// `bits` for raw-bit inputs.
struct WarpInput {
    std::array<float, 3> u{};
    uint64_t bits = 0;
};

/// One output point, laid out as chi2::DomainPoint (unused coordinates are 0).
/// A discrete case's output is its index, as a float in [0] (exact below 2^24).
using WarpOutput = std::array<float, 3>;

/// What a warp's sample returns with its point, read off its return type.
enum class SampleReturns {
    Point,              ///< the point only
    PointAndPdf,        ///< PdfSample: the point and its pdf, as renderers' Sample(u, &pdf)
    PointAndWeight,     ///< WeightedSample: the point and the weight eval(x) / pdf(x)
    Index,              ///< an integer: a discrete choice among WarpCaseInfo::categories
    IndexAndRemappedU,  ///< DiscreteSample: the index and the input remapped to [0,1) for reuse
    /// A BSDF's or phase function's sample (wi, f, pdf, flags, eta): a BsdfCase
    /// (validate/api/bsdf_case.h), which only the BSDF checks take.
    Bsdf,
};

/// A sample that carries its pdf (with respect to the domain's measure).
template <typename X>
struct PdfSample {
    X x;
    float pdf;
};

/// A sample that carries its weight eval(x) / pdf(x), as BSDF samplers return.
template <typename X>
struct WeightedSample {
    X x;
    float weight;
};

/// A discrete choice with the input remapped for reuse: u_remapped is where u
/// fell inside the chosen category's share of [0,1), rescaled to [0,1), and
/// must itself be uniform (pbrt's AliasTable::Sample(u, &pmf, &uRemapped)).
struct DiscreteSample {
    uint32_t index;
    float u_remapped;
};

struct Parameter {
    std::string name;
    double value = 0.0;
};

/// A parameter's value in a case name: the shortest decimal that reads back as
/// the value; for a value that is exactly a float (a float parameter stored as
/// a double), the float's shortest decimal when that is shorter: 0.3f gives
/// "0.3", not "0.30000001192092896".
std::string parameter_value(double value);

/// Name and parameters, e.g. family "uniform_cone", {cos_theta_max: 0.3}
/// -> "uniform_cone[cos_theta_max=0.3]" (values as parameter_value writes them).
std::string case_name(const std::string& family, const std::vector<Parameter>& params);

/// A monotone one-dimensional view of a warp, for the "tabulated" check (a case
/// may declare several, WarpCaseInfo::views): one
/// coordinate of the output that depends on one input coordinate only, and
/// monotonically, with its marginal density. The check tabulates the density
/// into a PiecewiseConstant1D and compares the warp with the table's inversion
/// method, sample by sample. A declared view is a claim that the coordinate is
/// monotone in its input. A 1D warp on an interval is its own view and needs
/// none (whether it is monotone is then measured, or declared with
/// WarpCaseInfo::inversion); a 1D warp on an unbounded line needs one to say where to truncate
/// (`lo`, `hi`) and how much probability lies beyond each end (`lower_tail_mass`
/// below lo, `tail_mass` above hi, from the case's own CDF).
struct MonotoneMarginal {
    int input_coordinate = 0;   ///< which input drives the coordinate: 0 (u.x) or 1 (u.y)
    bool increasing = true;     ///< whether the coordinate grows with that input
    double lo = 0.0, hi = 1.0;  ///< range of the coordinate; for a half-line, hi is the truncation point
    double tail_mass = 0.0;     ///< probability that the coordinate exceeds hi (0 on a bounded range)
    double lower_tail_mass = 0.0;  ///< probability that the coordinate lies below lo (0 on a bounded range)
    std::string label;          ///< axis label, e.g. "cos theta"
    /// The coordinate of an output; empty: x[0]. NaN where the output does not
    /// determine it (the azimuth at a pole): such samples are skipped and counted.
    std::function<double(const WarpOutput&)> coordinate;
    /// Its marginal density on [lo, hi]; empty: the warp's own pdf (1D warps only).
    std::function<double(double)> pdf;
};

/// Whether a case's sample is the inversion method of its density (monotone in
/// u), which the tabulated check compares it with.
enum class Inversion {
    Measure,  ///< declared views are claims; a 1D warp without views is measured on a grid of inputs
    Claimed,  ///< the 1D warp's sample is monotone in u: compared without measuring (and failed where it is not)
    /// Not an inversion sampler (an alias table, a mixture chosen by u): the
    /// tabulated check does not apply (chi2 and unbinned test the distribution).
    NotInversion,
};

/// Built with designated initialisers, e.g. {.family = "uniform_cone", .params = ...,
/// .domain = ...}; every field has a default, so a case names only what it sets.
struct WarpCaseInfo {
    std::string family{};             ///< e.g. "uniform_cone"
    std::vector<Parameter> params{};  ///< concrete values, in display order
    std::string description{};        ///< one line: what it samples, with which density
    /// What sample consumes. Unset (the usual): read off the type of sample's
    /// argument. Set, it is a claim that must agree with that type: a case
    /// whose sample takes something else is refused.
    std::optional<InputKind> input{};
    chi2::Domain domain = chi2::Domain::unit_square();
    /// Largest |invert(sample(u)) - u| (max norm, in u units) that the round trip
    /// accepts. The default, 2^-16, is ~500 float ulps at u = 0.5: float warps with
    /// trigonometry lose tens of ulps, while a wrong inverse is off by far more.
    double roundtrip_tolerance = 0x1p-16;
    /// Whether the inverse is expected to be exact on raw bits (invert returns
    /// the first input that maps to x) rather than within a tolerance.
    bool exact_inverse = false;
    /// How many cells the chi-square checks use (columns, rows), and an
    /// unbounded line's length scale and centre; zero fields take the
    /// defaults (chi2/binning.h: 32 x 32 on 2D domains, 200 on lines; the
    /// line's scale and centre from the warp). The counts are all it sets:
    /// where the samples would fill under a quarter of a uniform grid of that
    /// many cells (a sharp lobe, a small light), the cells move to the
    /// quantiles of a pilot sample, each of about equal probability
    /// (chi2/equal_probability.h); cells narrower than the float resolution
    /// allows are merged. More cells see local deviations better and broad
    /// ones worse (Binning's constructor says why ~1000), and every row
    /// states the tilt its cells can see at 90% power: raise the counts only
    /// to look for narrow features, with the samples to fill them
    /// (--samples).
    chi2::BinResolution chi2_resolution{};
    /// The case's monotone 1D views, each tabulated by the tabulated check and,
    /// on 2D domains, tested by the unbinned check: e.g. cos theta and the
    /// azimuth of a spherical warp, so that an error in either shows. Each
    /// needs its own label (results name the view by it). Empty: a 1D warp on
    /// an interval is its own view; other cases have none.
    std::vector<MonotoneMarginal> views{};
    /// Whether sample is the inversion method (Inversion): by default measured
    /// where no view claims it.
    Inversion inversion = Inversion::Measure;
    /// The measure (length, area, solid angle) of the set where the density is
    /// positive, when that is less than the domain's: a tabulated sampler with
    /// empty buckets, an environment map with empty rows. 0: not declared.
    /// inverse_pdf_mean tests E[1/pdf], which is this measure, against it
    /// (undeclared: one-sided, against the domain's measure).
    double support_measure = 0.0;
    /// Discrete cases only: the number of categories; sample returns an index
    /// of 0 .. categories - 1 and the pdf is a pmf over them. A discrete case
    /// leaves `domain` unset (0 here means a continuous case).
    std::size_t categories = 0;
    /// Built-in 2D warps only: the warp's lane form (validate/lanes/lane_sampling.h),
    /// which the chi-square check uses to draw, warp and bin 24 samples at a
    /// time. It must give the same bits as sample(); leave it empty otherwise.
    const LaneSampler* lanes = nullptr;
};

/// What a case's parts are: what sample takes and returns, and which of pdf,
/// invert and eval it has. make_warp_case reads it off the types of the warp's
/// members; a case class written by hand states it.
struct WarpSignature {
    InputKind input = InputKind::Uniform2D;
    SampleReturns returns = SampleReturns::Point;
    int output_dimension = 2;  ///< coordinates of a point: 1, 2 or 3; 0 for an index
    bool has_pdf = true;
    bool has_inverse = false;
    bool has_eval = false;
};

class WarpCase {
public:
    /// `signature` says what the case's sample takes and returns; info.input,
    /// when set, must agree with it (validate_case says so where it does not).
    WarpCase(WarpCaseInfo info, const WarpSignature& signature);
    virtual ~WarpCase() = default;
    WarpCase(const WarpCase&) = delete;
    WarpCase& operator=(const WarpCase&) = delete;

    const std::string& name() const { return name_; }
    const WarpCaseInfo& info() const { return info_; }
    const chi2::Domain& domain() const { return info_.domain; }
    const WarpSignature& signature() const { return signature_; }
    /// What sample consumes, as its argument's type says.
    InputKind input_kind() const { return signature_.input; }

    /// out[i] = sample(in[i]). Sizes must match.
    virtual void sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const = 0;
    /// sample() of a Uniform2D warp on planar arrays, the layout of the
    /// vectorised chi-square path (validate/lanes/lane_sampling.h): (x[i], y[i], z[i])
    /// = sample({u0[i], u1[i]}) for i < n (z = 0 for a point of the plane). A
    /// case made by make_warp_case does it in one loop with sample inlined; this
    /// default converts through sample().
    virtual void sample_planar(const float* u0, const float* u1, float* x, float* y, float* z, std::size_t n) const;
    /// out[i] = pdf(x[i]), the density with respect to the domain's measure.
    virtual void pdf(std::span<const WarpOutput> x, std::span<double> out) const = 0;
    /// out[i] = the input that sample maps to x[i]. Only where has_inverse().
    virtual void invert(std::span<const WarpOutput> x, std::span<WarpInput> out) const = 0;
    /// Whether the warp has an inverse. Many real warps have none (visible-normal
    /// or table-driven samplers): for them the round-trip checks do not apply,
    /// which is not an error.
    bool has_inverse() const { return signature_.has_inverse; }

    /// What sample returns besides the point (SampleReturns).
    SampleReturns sample_returns() const { return signature_.returns; }
    /// Whether the case has a pdf function. One whose sample returns the pdf may
    /// have none: then only the checks that need the pdf at the samples apply.
    bool has_pdf() const { return signature_.has_pdf; }
    /// Whether the case chooses among WarpCaseInfo::categories.
    bool is_discrete() const {
        const SampleReturns r = sample_returns();
        return r == SampleReturns::Index || r == SampleReturns::IndexAndRemappedU;
    }
    /// out[i] = sample(in[i]) and value[i] = what sample returned with it: the
    /// pdf, the weight or the remapped u. Only where sample_returns() says so.
    virtual void sample_with_value(std::span<const WarpInput> in, std::span<WarpOutput> out,
                                   std::span<double> value) const {
        (void)in, (void)out, (void)value;
        throw std::logic_error("warp case " + name() + " returns nothing with its samples");
    }
    /// out[i] = eval(x[i]), the integrand whose estimate a weighted sampler's
    /// weight is. Only where sample_returns() is PointAndWeight.
    virtual void eval(std::span<const WarpOutput> x, std::span<double> out) const {
        (void)x, (void)out;
        throw std::logic_error("warp case " + name() + " has no eval");
    }

private:
    WarpCaseInfo info_;
    WarpSignature signature_;
    std::string name_;
};

/// Everything inconsistent in a case's declaration, one sentence each; empty
/// when nothing is: its types against .input, .domain and .categories, the
/// parts its kind needs (a weight needs eval), its settings and views, a BSDF's
/// claims, a swept float sampler's domain.
std::vector<std::string> case_problems(const WarpCase& warp);

/// The one error of a refused declaration: "<what> is declared inconsistently:"
/// and a line per problem; `what` names it ("warp case cone[x=1]").
std::invalid_argument declaration_error(const std::string& what, const std::vector<std::string>& problems);

/// Throws declaration_error("warp case <name>", problems) where case_problems
/// finds any. make_warp_case, make_bsdf_case and Registry::add_case call it, so
/// a case is refused where it is made, and a case class written by hand where
/// it is registered.
void validate_case(const WarpCase& warp);

namespace detail {

/// What sample returns, when it is a point or an index: the value itself, and
/// nothing with it.
template <typename T, SampleReturns Returns>
struct ReturnedAlone {
    static constexpr bool known = true;
    using Point = T;
    static constexpr SampleReturns returns = Returns;
    static const T& point(const T& r) { return r; }
    static double value(const T&) { return 0.0; }
};

/// One traits struct per type a warp's sample takes or returns, with all that
/// the type says: as sample's argument, its input kind (`input`, empty where
/// the type is no input) and the conversions from and to WarpInput; as a
/// point, its coordinates (`dimension`, 0 for an index) and the conversions
/// from and to WarpOutput; as what sample returns, the point in it and the
/// value that comes with it (SampleReturns). `known` is false for any other type.
template <typename T>
struct WarpType {
    static constexpr bool known = false;
};

template <>
struct WarpType<float> : ReturnedAlone<float, SampleReturns::Point> {
    static constexpr std::optional<InputKind> input = InputKind::Uniform1D;
    static constexpr int dimension = 1;
    static WarpInput to_input(float u) { return {{u, 0.0f, 0.0f}, 0}; }
    static float from_input(const WarpInput& in) { return in.u[0]; }
    static WarpOutput to_output(float v) { return {v, 0.0f, 0.0f}; }
    static float from_output(const WarpOutput& o) { return o[0]; }
};

template <>
struct WarpType<Point2f> : ReturnedAlone<Point2f, SampleReturns::Point> {
    static constexpr std::optional<InputKind> input = InputKind::Uniform2D;
    static constexpr int dimension = 2;
    static WarpInput to_input(Point2f u) { return {{u.x, u.y, 0.0f}, 0}; }
    static Point2f from_input(const WarpInput& in) { return {in.u[0], in.u[1]}; }
    static WarpOutput to_output(Point2f p) { return {p.x, p.y, 0.0f}; }
    static Point2f from_output(const WarpOutput& o) { return {o[0], o[1]}; }
};

template <>
struct WarpType<Vector3f> : ReturnedAlone<Vector3f, SampleReturns::Point> {
    static constexpr std::optional<InputKind> input{};  // no warp takes a direction
    static constexpr int dimension = 3;
    static WarpOutput to_output(Vector3f v) { return {v.x, v.y, v.z}; }
    static Vector3f from_output(const WarpOutput& o) { return {o[0], o[1], o[2]}; }
};

/// An integer: as an input, raw random bits (uint32_t or uint64_t); as what
/// sample returns, a discrete index, carried as a float (exact below 2^24).
template <std::integral T>
struct WarpType<T> : ReturnedAlone<T, SampleReturns::Index> {
    static constexpr std::optional<InputKind> input = std::is_same_v<T, uint32_t>   ? InputKind::Bits32
                                                      : std::is_same_v<T, uint64_t> ? InputKind::Bits64
                                                                                     : std::optional<InputKind>{};
    static constexpr int dimension = 0;
    static WarpInput to_input(T bits) { return {{}, static_cast<uint64_t>(bits)}; }
    static T from_input(const WarpInput& in) { return static_cast<T>(in.bits); }
    static WarpOutput to_output(T index) { return {static_cast<float>(index), 0.0f, 0.0f}; }
    static T from_output(const WarpOutput& o) { return static_cast<T>(o[0]); }
};

template <typename X>
struct WarpType<PdfSample<X>> {
    static constexpr bool known = WarpType<X>::known;
    using Point = X;
    static constexpr SampleReturns returns = SampleReturns::PointAndPdf;
    static const X& point(const PdfSample<X>& r) { return r.x; }
    static double value(const PdfSample<X>& r) { return r.pdf; }
};

template <typename X>
struct WarpType<WeightedSample<X>> {
    static constexpr bool known = WarpType<X>::known;
    using Point = X;
    static constexpr SampleReturns returns = SampleReturns::PointAndWeight;
    static const X& point(const WeightedSample<X>& r) { return r.x; }
    static double value(const WeightedSample<X>& r) { return r.weight; }
};

template <>
struct WarpType<DiscreteSample> {
    static constexpr bool known = true;
    using Point = uint32_t;
    static constexpr SampleReturns returns = SampleReturns::IndexAndRemappedU;
    static uint32_t point(const DiscreteSample& r) { return r.index; }
    static double value(const DiscreteSample& r) { return r.u_remapped; }
};

/// Whether T can be sample's argument, and whether it can be the point sample returns.
template <typename T>
constexpr bool is_input = [] {
    if constexpr (requires { WarpType<T>::input; }) return WarpType<T>::input.has_value();
    else return false;
}();
template <typename T>
constexpr bool is_point = requires { WarpType<T>::dimension; };

/// The value of a CallableWarp's part that is not given.
struct NotGiven {};

/// The one-argument call behind a callable type, or behind a pointer to a
/// member (a const member function, or a data member that holds a callable):
/// whether there is one (`given`) and its argument type (`Arg`).
template <typename F>
struct CallOf : CallOf<decltype(&F::operator())> {};
template <>
struct CallOf<NotGiven> {
    static constexpr bool given = false;
    using Arg = void;
};
template <typename R, typename A>
struct CallOf<R (*)(A)> {
    static constexpr bool given = true;
    using Arg = std::remove_cvref_t<A>;
};
template <typename R, typename A>
struct CallOf<R (*)(A) noexcept> : CallOf<R (*)(A)> {};
template <typename C, typename R, typename A>
struct CallOf<R (C::*)(A) const> : CallOf<R (*)(A)> {};
template <typename C, typename R, typename A>
struct CallOf<R (C::*)(A) const noexcept> : CallOf<R (*)(A)> {};
template <typename C, typename F>
    requires(!std::is_function_v<F>)
struct CallOf<F C::*> : CallOf<F> {};

/// Whether W has the part: a const member function, or a data member holding
/// a callable (a CallableWarp's part that is not NotGiven).
template <typename W>
constexpr bool warp_has_pdf = [] {
    if constexpr (requires { &W::pdf; }) return CallOf<decltype(&W::pdf)>::given;
    else return false;
}();
template <typename W>
constexpr bool warp_has_invert = [] {
    if constexpr (requires { &W::invert; }) return CallOf<decltype(&W::invert)>::given;
    else return false;
}();
template <typename W>
constexpr bool warp_has_eval = [] {
    if constexpr (requires { &W::eval; }) return CallOf<decltype(&W::eval)>::given;
    else return false;
}();

/// A warp's types: In what sample takes, Result what it returns, Out the point in it.
template <typename W>
struct WarpTypesOf {
    using In = typename CallOf<decltype(&W::sample)>::Arg;
    using Result = std::remove_cvref_t<decltype(std::declval<const W&>().sample(std::declval<In>()))>;
    using Out = typename WarpType<Result>::Point;
};

/// A warp case around a warp object (or a CallableWarp), whose members
/// are called directly, so that they inline into the batch loops.
template <typename W>
class ObjectWarpCase final : public WarpCase {
    using In = typename WarpTypesOf<W>::In;
    using Result = WarpType<typename WarpTypesOf<W>::Result>;
    using Out = typename WarpTypesOf<W>::Out;
    using InType = WarpType<In>;
    using OutType = WarpType<Out>;

public:
    ObjectWarpCase(WarpCaseInfo info, W warp) : WarpCase(std::move(info), signature()), warp_(std::move(warp)) {}

    static constexpr WarpSignature signature() {
        return {.input = *InType::input,
                .returns = Result::returns,
                .output_dimension = OutType::dimension,
                .has_pdf = warp_has_pdf<W>,
                .has_inverse = warp_has_invert<W>,
                .has_eval = warp_has_eval<W>};
    }

    void sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const override {
        for (std::size_t k = 0; k < in.size(); ++k)
            out[k] = OutType::to_output(Result::point(warp_.sample(InType::from_input(in[k]))));
    }
    void sample_planar(const float* u0, const float* u1, float* x, float* y, float* z,
                       std::size_t n) const override {
        if constexpr (std::is_same_v<In, Point2f>) {
            for (std::size_t k = 0; k < n; ++k) {
                const WarpOutput o = OutType::to_output(Result::point(warp_.sample(Point2f{u0[k], u1[k]})));
                x[k] = o[0], y[k] = o[1], z[k] = o[2];
            }
        } else {
            WarpCase::sample_planar(u0, u1, x, y, z, n);
        }
    }
    void sample_with_value(std::span<const WarpInput> in, std::span<WarpOutput> out,
                           std::span<double> value) const override {
        if constexpr (Result::returns == SampleReturns::Point || Result::returns == SampleReturns::Index) {
            WarpCase::sample_with_value(in, out, value);
        } else {
            for (std::size_t k = 0; k < in.size(); ++k) {
                const auto r = warp_.sample(InType::from_input(in[k]));
                out[k] = OutType::to_output(Result::point(r));
                value[k] = Result::value(r);
            }
        }
    }
    void pdf(std::span<const WarpOutput> x, std::span<double> out) const override {
        if constexpr (warp_has_pdf<W>) {
            for (std::size_t k = 0; k < x.size(); ++k)
                out[k] = static_cast<double>(warp_.pdf(OutType::from_output(x[k])));
        } else {
            (void)x, (void)out;
            throw std::logic_error("warp case " + name() + " has no pdf function");
        }
    }
    void eval(std::span<const WarpOutput> x, std::span<double> out) const override {
        if constexpr (warp_has_eval<W>) {
            for (std::size_t k = 0; k < x.size(); ++k)
                out[k] = static_cast<double>(warp_.eval(OutType::from_output(x[k])));
        } else {
            WarpCase::eval(x, out);
        }
    }
    void invert(std::span<const WarpOutput> x, std::span<WarpInput> out) const override {
        if constexpr (warp_has_invert<W>) {
            for (std::size_t k = 0; k < x.size(); ++k)
                out[k] = InType::to_input(warp_.invert(OutType::from_output(x[k])));
        } else {
            (void)x, (void)out;
            throw std::logic_error("warp case " + name() + " has no inverse");
        }
    }

private:
    W warp_;
};

}  // namespace detail

/// A warp given as callables, each part named, so that none can take another's
/// place (eval and pdf have the same type): made by warp_of(sample) and its
/// with_ members, e.g.
///   warp_of([](Point2f u) { ... }).with_pdf([](Vector3f w) { ... }).with_eval(...)
/// each part a lambda or function of one argument; a part not given is not
/// there (no inverse, no pdf function, no eval). Its data members are what
/// make_warp_case calls, as a warp object's members.
template <typename Sample, typename Pdf = detail::NotGiven, typename Invert = detail::NotGiven,
          typename Eval = detail::NotGiven>
struct CallableWarp {
    Sample sample;
    Pdf pdf{};
    Invert invert{};
    Eval eval{};

    /// This warp with `f` as its pdf: the density of the point sample returns (the pmf of an index).
    template <typename F>
    CallableWarp<Sample, F, Invert, Eval> with_pdf(F f) const {
        static_assert(std::is_same_v<Pdf, detail::NotGiven>, "the pdf is given twice");
        return {sample, std::move(f), invert, eval};
    }
    /// This warp with `f` as its inverse: the input that sample maps to a point.
    template <typename F>
    CallableWarp<Sample, Pdf, F, Eval> with_invert(F f) const {
        static_assert(std::is_same_v<Invert, detail::NotGiven>, "the inverse is given twice");
        return {sample, pdf, std::move(f), eval};
    }
    /// This warp with `f` as its eval: the integrand whose estimate a weighted sampler's weight is.
    template <typename F>
    CallableWarp<Sample, Pdf, Invert, F> with_eval(F f) const {
        static_assert(std::is_same_v<Eval, detail::NotGiven>, "the eval is given twice");
        return {sample, pdf, invert, std::move(f)};
    }
};

/// A warp of callables whose sample is `sample` (CallableWarp): add its other
/// parts by name, warp_of(sample).with_pdf(pdf).with_invert(invert).
template <typename Sample>
CallableWarp<Sample> warp_of(Sample sample) {
    return {std::move(sample)};
}

/// A warp object: a class with a `sample(In)` const member and, as it has
/// them, `pdf(Out)`, `invert(Out)` and `eval(Out)` (sampling/README.md), none
/// overloaded or a template; or a CallableWarp (warp_of).
template <typename W>
concept WarpObject = requires { &W::sample; };

/// Makes a warp case from its description and a warp object, e.g.
/// make_warp_case(info, UniformCone(0.3f)), or from named callables,
/// make_warp_case(info, warp_of(sample).with_pdf(pdf)). Everything else is
/// read off the types of its members:
///  - sample takes the input: float or Point2f (uniform floats in [0,1)),
///    uint32_t or uint64_t (raw random bits);
///  - sample returns the point (float, Point2f or Vector3f), or PdfSample<X>
///    (with its pdf), WeightedSample<X> (with its weight eval / pdf: give
///    eval), an integer index or DiscreteSample (a discrete choice among
///    .categories; pdf is then the pmf);
///  - pdf(Out) is the density, invert(Out) -> In the inverse, eval(Out) the
///    integrand of a weighted sampler; each may be missing, and the checks
///    that need it then do not apply.
/// A declaration that contradicts itself is refused (validate_case).
template <WarpObject W>
std::unique_ptr<WarpCase> make_warp_case(WarpCaseInfo info, W warp) {
    using Types = detail::WarpTypesOf<W>;
    static_assert(detail::CallOf<decltype(&W::sample)>::given, "a warp needs a sample");
    static_assert(detail::is_input<typename Types::In>,
                  "sample must take float or Point2f (uniform input) or uint32_t or uint64_t (raw bits)");
    static_assert(detail::WarpType<typename Types::Result>::known && detail::is_point<typename Types::Out>,
                  "sample must return float, Point2f, Vector3f, an integer index, PdfSample<X>, WeightedSample<X> "
                  "or DiscreteSample");
    using Out = typename Types::Out;
    if constexpr (detail::warp_has_pdf<W>)
        static_assert(requires(const W& w, Out x) { static_cast<double>(w.pdf(x)); },
                      "pdf must take the point that sample returns and return a number");
    if constexpr (detail::warp_has_eval<W>)
        static_assert(requires(const W& w, Out x) { static_cast<double>(w.eval(x)); },
                      "eval must take the point that sample returns and return a number");
    if constexpr (detail::warp_has_invert<W>)
        static_assert(requires(const W& w, Out x) { static_cast<typename Types::In>(w.invert(x)); },
                      "invert must take the point that sample returns and return sample's input");
    auto warp_case = std::make_unique<detail::ObjectWarpCase<W>>(std::move(info), std::move(warp));
    validate_case(*warp_case);
    return warp_case;
}

}  // namespace warpcheck

// A warp case: one warp with concrete parameter values and a stable name. The
// checks see every warp through this one type-erased interface, which works on
// batches so that the virtual call is paid once per batch, not once per sample.
#pragma once

#include <array>
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
    /// A point of [0,1)^3: a BSDF's (uc, u) (validate/bsdf/bsdf_case.h), uc in u[0].
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
    /// (validate/bsdf/bsdf_case.h), which only the BSDF checks take.
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
    InputKind input = InputKind::Uniform2D;
    chi2::Domain domain = chi2::Domain::unit_square();
    /// Largest |invert(sample(u)) - u| (max norm, in u units) that the round trip
    /// accepts. The default, 2^-16, is ~500 float ulps at u = 0.5: float warps with
    /// trigonometry lose tens of ulps, while a wrong inverse is off by far more.
    double roundtrip_tolerance = 0x1p-16;
    /// Whether the inverse is expected to be exact on raw bits (invert returns
    /// the first input that maps to x) rather than within a tolerance.
    bool exact_inverse = false;
    /// Cells of the chi-square test; zero fields take the domain's defaults
    /// (chi2/binning.h: 32 x 32 on 2D domains, 200 on lines). Rarely needed:
    /// the check merges cells that are narrower than the float resolution
    /// allows, integrates jumps with a verified bound and finds support its
    /// first nodes miss around the samples, so a discontinuous density or a
    /// small light needs no finer grid. A finer grid sees local deviations
    /// better and broad ones worse (Binning's constructor says why ~1000
    /// cells); a half-line's or the real line's length scale and centre are
    /// chosen from the warp unless set here.
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

class WarpCase {
public:
    explicit WarpCase(WarpCaseInfo info) : info_(std::move(info)), name_(case_name(info_.family, info_.params)) {}
    virtual ~WarpCase() = default;
    WarpCase(const WarpCase&) = delete;
    WarpCase& operator=(const WarpCase&) = delete;

    const std::string& name() const { return name_; }
    const WarpCaseInfo& info() const { return info_; }
    const chi2::Domain& domain() const { return info_.domain; }
    InputKind input_kind() const { return info_.input; }

    /// out[i] = sample(in[i]). Sizes must match.
    virtual void sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const = 0;
    /// sample() of a Uniform2D warp on planar arrays, the layout of the
    /// vectorised chi-square path (validate/lane_sampling.h): (x[i], y[i], z[i])
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
    virtual bool has_inverse() const { return true; }

    /// What sample returns besides the point (SampleReturns).
    virtual SampleReturns sample_returns() const { return SampleReturns::Point; }
    /// Whether the case has a pdf function. One whose sample returns the pdf may
    /// have none: then only the checks that need the pdf at the samples apply.
    virtual bool has_pdf() const { return true; }
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

protected:
    /// What a case's callables declare, for validate_declaration.
    struct Declaration {
        std::optional<InputKind> input;  ///< the kind its sample's argument type implies
        int output_dimension = 0;        ///< 1, 2 or 3 for points; 0 for indices
        bool has_eval = false;
    };
    /// Refuses an inconsistent case at registration (a discrete case with a
    /// continuous domain, a weight without eval, a point of the wrong dimension,
    /// ...): throws std::invalid_argument naming the case.
    void validate_declaration(const Declaration& d) const;

private:
    WarpCaseInfo info_;
    std::string name_;
};

namespace detail {

// Conversions between a warp's natural types and the uniform WarpInput/WarpOutput.
template <typename T> struct WarpTypes;
template <> struct WarpTypes<float> {
    static WarpOutput to_output(float v) { return {v, 0.0f, 0.0f}; }
    static float from_output(const WarpOutput& o) { return o[0]; }
    static WarpInput to_input(float u) { return {{u, 0.0f}, 0}; }
    static float from_input(const WarpInput& in) { return in.u[0]; }
};
template <> struct WarpTypes<Point2f> {
    static WarpOutput to_output(Point2f p) { return {p.x, p.y, 0.0f}; }
    static Point2f from_output(const WarpOutput& o) { return {o[0], o[1]}; }
    static WarpInput to_input(Point2f u) { return {{u.x, u.y}, 0}; }
    static Point2f from_input(const WarpInput& in) { return {in.u[0], in.u[1]}; }
};
template <> struct WarpTypes<Vector3f> {
    static WarpOutput to_output(Vector3f v) { return {v.x, v.y, v.z}; }
    static Vector3f from_output(const WarpOutput& o) { return {o[0], o[1], o[2]}; }
};
template <> struct WarpTypes<uint32_t> {
    static WarpInput to_input(uint32_t b) { return {{0.0f, 0.0f}, b}; }
    static uint32_t from_input(const WarpInput& in) { return static_cast<uint32_t>(in.bits); }
};
template <> struct WarpTypes<uint64_t> {
    static WarpInput to_input(uint64_t b) { return {{0.0f, 0.0f}, b}; }
    static uint64_t from_input(const WarpInput& in) { return in.bits; }
};

// Integer outputs are discrete indices, carried as floats (exact below 2^24).
template <typename T>
WarpOutput to_output(const T& v) {
    if constexpr (std::is_integral_v<T>) return {static_cast<float>(v), 0.0f, 0.0f};
    else return WarpTypes<T>::to_output(v);
}
template <typename T>
T from_output(const WarpOutput& o) {
    if constexpr (std::is_integral_v<T>) return static_cast<T>(o[0]);
    else return WarpTypes<T>::from_output(o);
}
template <typename T>
constexpr int output_dimension() {
    if constexpr (std::is_integral_v<T>) return 0;
    else if constexpr (std::is_same_v<T, float>) return 1;
    else if constexpr (std::is_same_v<T, Point2f>) return 2;
    else return 3;
}
template <typename T>
constexpr std::optional<InputKind> input_kind_of() {
    if constexpr (std::is_same_v<T, float>) return InputKind::Uniform1D;
    else if constexpr (std::is_same_v<T, Point2f>) return InputKind::Uniform2D;
    else if constexpr (std::is_same_v<T, uint32_t>) return InputKind::Bits32;
    else if constexpr (std::is_same_v<T, uint64_t>) return InputKind::Bits64;
    else return std::nullopt;
}

// What sample returns, split into its point and the value that comes with it.
template <typename R>
struct SampleResult {
    using Point = R;
    static constexpr SampleReturns kReturns = std::is_integral_v<R> ? SampleReturns::Index : SampleReturns::Point;
    static const R& point(const R& r) { return r; }
    static double value(const R&) { return 0.0; }
};
template <typename X>
struct SampleResult<PdfSample<X>> {
    using Point = X;
    static constexpr SampleReturns kReturns = SampleReturns::PointAndPdf;
    static const X& point(const PdfSample<X>& r) { return r.x; }
    static double value(const PdfSample<X>& r) { return r.pdf; }
};
template <typename X>
struct SampleResult<WeightedSample<X>> {
    using Point = X;
    static constexpr SampleReturns kReturns = SampleReturns::PointAndWeight;
    static const X& point(const WeightedSample<X>& r) { return r.x; }
    static double value(const WeightedSample<X>& r) { return r.weight; }
};
template <>
struct SampleResult<DiscreteSample> {
    using Point = uint32_t;
    static constexpr SampleReturns kReturns = SampleReturns::IndexAndRemappedU;
    static uint32_t point(const DiscreteSample& r) { return r.index; }
    static double value(const DiscreteSample& r) { return r.u_remapped; }
};

template <typename F> struct FirstArg : FirstArg<decltype(&F::operator())> {};
template <typename C, typename R, typename A> struct FirstArg<R (C::*)(A) const> {
    using type = std::remove_cvref_t<A>;
};
template <typename R, typename A> struct FirstArg<R (*)(A)> {
    using type = std::remove_cvref_t<A>;
};

/// The Invert of a warp without an inverse.
struct NoInverse {};
/// The Pdf of a warp whose sample returns its pdf and has no pdf function.
struct NoPdf {};
/// The Eval of a warp that returns no weight.
struct NoEval {};

// The output type: the pdf's argument, or the point sample returns when there is no pdf.
template <typename Pdf, typename Point> struct OutputType {
    using type = typename FirstArg<Pdf>::type;
};
template <typename Point> struct OutputType<NoPdf, Point> {
    using type = Point;
};

template <typename Sample, typename Pdf, typename Invert, typename Eval = NoEval>
class LambdaWarpCase final : public WarpCase {
    using In = typename FirstArg<Sample>::type;
    using Result = SampleResult<std::remove_cvref_t<std::invoke_result_t<const Sample&, In>>>;
    using Out = typename OutputType<Pdf, typename Result::Point>::type;

public:
    LambdaWarpCase(WarpCaseInfo info, Sample s, Pdf p, Invert i, Eval e = {})
        : WarpCase(std::move(info)), sample_(std::move(s)), pdf_(std::move(p)), invert_(std::move(i)),
          eval_(std::move(e)) {
        validate_declaration({input_kind_of<In>(), detail::output_dimension<Out>(), !std::is_same_v<Eval, NoEval>});
    }

    void sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const override {
        for (std::size_t k = 0; k < in.size(); ++k)
            out[k] = to_output<Out>(Result::point(sample_(WarpTypes<In>::from_input(in[k]))));
    }
    void sample_planar(const float* u0, const float* u1, float* x, float* y, float* z,
                       std::size_t n) const override {
        if constexpr (std::is_same_v<In, Point2f>) {
            for (std::size_t k = 0; k < n; ++k) {
                const WarpOutput o = to_output<Out>(Result::point(sample_(Point2f{u0[k], u1[k]})));
                x[k] = o[0], y[k] = o[1], z[k] = o[2];
            }
        } else {
            WarpCase::sample_planar(u0, u1, x, y, z, n);
        }
    }
    void sample_with_value(std::span<const WarpInput> in, std::span<WarpOutput> out,
                           std::span<double> value) const override {
        if constexpr (Result::kReturns == SampleReturns::Point || Result::kReturns == SampleReturns::Index) {
            WarpCase::sample_with_value(in, out, value);
        } else {
            for (std::size_t k = 0; k < in.size(); ++k) {
                const auto r = sample_(WarpTypes<In>::from_input(in[k]));
                out[k] = to_output<Out>(Result::point(r));
                value[k] = Result::value(r);
            }
        }
    }
    void pdf(std::span<const WarpOutput> x, std::span<double> out) const override {
        if constexpr (std::is_same_v<Pdf, NoPdf>) {
            (void)x, (void)out;
            throw std::logic_error("warp case " + name() + " has no pdf function");
        } else {
            for (std::size_t k = 0; k < x.size(); ++k) out[k] = static_cast<double>(pdf_(from_output<Out>(x[k])));
        }
    }
    void eval(std::span<const WarpOutput> x, std::span<double> out) const override {
        if constexpr (std::is_same_v<Eval, NoEval>) {
            WarpCase::eval(x, out);
        } else {
            for (std::size_t k = 0; k < x.size(); ++k) out[k] = static_cast<double>(eval_(from_output<Out>(x[k])));
        }
    }
    SampleReturns sample_returns() const override { return Result::kReturns; }
    bool has_pdf() const override { return !std::is_same_v<Pdf, NoPdf>; }
    void invert(std::span<const WarpOutput> x, std::span<WarpInput> out) const override {
        if constexpr (std::is_same_v<Invert, NoInverse>) {
            (void)x;
            (void)out;
            throw std::logic_error("warp case " + name() + " has no inverse");
        } else {
            for (std::size_t k = 0; k < x.size(); ++k)
                out[k] = WarpTypes<In>::to_input(invert_(from_output<Out>(x[k])));
        }
    }
    bool has_inverse() const override { return !std::is_same_v<Invert, NoInverse>; }

private:
    Sample sample_;
    Pdf pdf_;
    Invert invert_;
    Eval eval_;
};

}  // namespace detail

/// Makes a warp case from three callables over the warp's natural types:
///   sample: In -> Out, pdf: Out -> float/double, invert: Out -> In,
/// with In one of float, Point2f, uint32_t, uint64_t and Out one of float,
/// Point2f, Vector3f. Lambdas are inlined into the batch loops; plain functions
/// are called through a pointer. sample may return PdfSample<Out> instead: its
/// pdf is then checked against pdf(x) ("sample_pdf"). Refused (std::invalid_argument
/// naming the case) where the callables and the info disagree.
template <typename Sample, typename Pdf, typename Invert>
std::unique_ptr<WarpCase> make_warp_case(WarpCaseInfo info, Sample sample, Pdf pdf, Invert invert) {
    return std::make_unique<detail::LambdaWarpCase<Sample, Pdf, Invert>>(std::move(info), std::move(sample),
                                                                         std::move(pdf), std::move(invert));
}

/// Makes a warp case without an inverse from two callables (sample and pdf, as
/// above): the round-trip checks do not apply to it. A discrete case is made
/// this way too: sample: In -> an integer index, or DiscreteSample with the
/// remapped u; pdf: index -> its probability (the pmf); with .categories set.
template <typename Sample, typename Pdf>
std::unique_ptr<WarpCase> make_warp_case(WarpCaseInfo info, Sample sample, Pdf pdf) {
    return make_warp_case(std::move(info), std::move(sample), std::move(pdf), detail::NoInverse{});
}

/// Makes a warp case from its sample alone, for a sampler that returns its pdf
/// (sample: In -> PdfSample<Out>) and has no pdf function: the checks that need
/// the pdf only at the samples use the returned one (consistency and
/// inverse_pdf_mean); those that need it elsewhere (chi2, tabulated, unbinned)
/// do not apply. No inverse.
template <typename Sample>
std::unique_ptr<WarpCase> make_warp_case(WarpCaseInfo info, Sample sample) {
    return std::make_unique<detail::LambdaWarpCase<Sample, detail::NoPdf, detail::NoInverse>>(
        std::move(info), std::move(sample), detail::NoPdf{}, detail::NoInverse{});
}

/// Makes a weighted sampler's case, as a BSDF's: sample: In -> WeightedSample<Out>
/// returns a point and its weight eval(x) / pdf(x); eval: Out -> float is the
/// integrand (a BSDF value times the cosine) and pdf: Out -> float the density
/// sample draws from. No inverse.
template <typename Sample, typename Eval, typename Pdf>
std::unique_ptr<WarpCase> make_weighted_case(WarpCaseInfo info, Sample sample, Eval eval, Pdf pdf) {
    return std::make_unique<detail::LambdaWarpCase<Sample, Pdf, detail::NoInverse, Eval>>(
        std::move(info), std::move(sample), std::move(pdf), detail::NoInverse{}, std::move(eval));
}

/// A warp object: a class with `sample(In)` and `pdf(Out)` const members, and
/// usually `invert(Out)`, that are not overloaded or templates (sampling/README.md).
template <typename W>
concept WarpObject = requires {
    typename detail::FirstArg<decltype(&W::sample)>::type;
    typename detail::FirstArg<decltype(&W::pdf)>::type;
};

/// Makes a warp case from a warp object, e.g. make_warp_case(info, UniformCone(0.3f)):
/// In and Out are read off the member signatures; a warp without an `invert`
/// member has no inverse. The object is held by value; the members are called
/// directly, so they inline into the batch loops.
template <WarpObject W>
std::unique_ptr<WarpCase> make_warp_case(WarpCaseInfo info, W warp) {
    using In = typename detail::FirstArg<decltype(&W::sample)>::type;
    using Out = typename detail::FirstArg<decltype(&W::pdf)>::type;
    auto sample = [warp](In u) { return warp.sample(u); };
    auto pdf = [warp](Out x) { return warp.pdf(x); };
    if constexpr (requires { &W::invert; })
        return make_warp_case(std::move(info), sample, pdf, [warp](Out x) { return warp.invert(x); });
    else
        return make_warp_case(std::move(info), sample, pdf);
}

}  // namespace warpcheck

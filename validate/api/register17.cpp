// The C++17 registration header's functions (validate/api/register17.h), compiled
// as C++20 with the rest of warpcheck: each converts the plain description to
// a WarpCaseInfo and the erased warp to a WarpCase, and takes the path a case
// made by make_warp_case takes (the same signature, validation and sweeps).
#include "validate/api/register17.h"

#include <memory>
#include <stdexcept>
#include <string>

#include "validate/api/bsdf_case.h"
#include "validate/api/case_grid.h"
#include "validate/api/external.h"
#include "validate/api/light_case.h"
#include "validate/api/registry.h"

namespace warpcheck::cxx17 {
namespace {

chi2::Domain to_domain(const Domain& d) {
    switch (d.kind) {
        case Domain::Kind::Interval: return chi2::Domain::interval(d.a, d.b);
        case Domain::Kind::HalfLine: return chi2::Domain::half_line(d.a);
        case Domain::Kind::LowerHalfLine: return chi2::Domain::lower_half_line(d.b);
        case Domain::Kind::RealLine: return chi2::Domain::real_line();
        case Domain::Kind::Box: return chi2::Domain::box(d.a, d.b, d.c, d.d);
        case Domain::Kind::UnitDisk: return chi2::Domain::unit_disk();
        case Domain::Kind::SphericalCap: return chi2::Domain::spherical_cap(d.c);
        case Domain::Kind::Triangle:
            return chi2::Domain::triangle({d.vertices[0], d.vertices[1]}, {d.vertices[2], d.vertices[3]},
                                          {d.vertices[4], d.vertices[5]});
    }
    throw std::invalid_argument("register17: unknown domain kind");
}

MonotoneMarginal to_view(const View& v) {
    MonotoneMarginal m;
    m.input_coordinate = v.input_coordinate;
    m.increasing = v.increasing;
    m.lo = v.lo;
    m.hi = v.hi;
    m.tail_mass = v.tail_mass;
    m.lower_tail_mass = v.lower_tail_mass;
    m.label = v.label;
    if (v.coordinate) m.coordinate = [f = v.coordinate](const WarpOutput& o) { return f(o); };
    m.pdf = v.pdf;
    return m;
}

std::vector<Parameter> to_params(const std::vector<std::pair<std::string, double>>& params) {
    std::vector<Parameter> out;
    for (const auto& [name, value] : params) out.push_back({name, value});
    return out;
}

chi2::BinResolution to_resolution(const BinResolution& r) {
    return {.first = r.first, .second = r.second, .half_line_scale = r.half_line_scale, .line_center = r.line_center};
}

/// The case description of a BSDF, light or MIS case: its names and cells.
template <typename Info>
WarpCaseInfo named(const Info& in, const BinResolution& resolution = {}) {
    return {.family = in.family,
            .params = to_params(in.params),
            .description = in.description,
            .chi2_resolution = to_resolution(resolution)};
}

WarpCaseInfo to_info(const CaseInfo& in) {
    WarpCaseInfo info;
    info.family = in.family;
    info.params = to_params(in.params);
    info.description = in.description;
    info.domain = to_domain(in.domain);
    info.roundtrip_tolerance = in.roundtrip_tolerance;
    info.exact_inverse = in.exact_inverse;
    for (const View& v : in.views) info.views.push_back(to_view(v));
    info.inversion = in.inversion == Inversion::Claimed        ? warpcheck::Inversion::Claimed
                     : in.inversion == Inversion::NotInversion ? warpcheck::Inversion::NotInversion
                                                               : warpcheck::Inversion::Measure;
    info.support_measure = in.support_measure;
    info.categories = in.categories;
    info.chi2_resolution = to_resolution(in.chi2_resolution);
    return info;
}

InputKind to_input_kind(detail::Input input) {
    switch (input) {
        case detail::Input::Uniform1D: return InputKind::Uniform1D;
        case detail::Input::Uniform2D: return InputKind::Uniform2D;
        case detail::Input::Bits32: return InputKind::Bits32;
        case detail::Input::Bits64: return InputKind::Bits64;
    }
    throw std::invalid_argument("register17: unknown input kind");
}

SampleReturns to_returns(detail::Returns returns) {
    switch (returns) {
        case detail::Returns::Point: return SampleReturns::Point;
        case detail::Returns::PointAndPdf: return SampleReturns::PointAndPdf;
        case detail::Returns::PointAndWeight: return SampleReturns::PointAndWeight;
        case detail::Returns::Index: return SampleReturns::Index;
        case detail::Returns::IndexAndRemappedU: return SampleReturns::IndexAndRemappedU;
    }
    throw std::invalid_argument("register17: unknown sample result");
}

/// What the erased warp's types said, as make_warp_case would read them.
WarpSignature signature_of(const detail::ErasedWarp& w) {
    return {.input = to_input_kind(w.input),
            .returns = to_returns(w.returns),
            .output_dimension = w.dimension,
            .has_pdf = static_cast<bool>(w.pdf),
            .has_inverse = static_cast<bool>(w.invert),
            .has_eval = static_cast<bool>(w.eval)};
}

detail::WarpInput to_input17(const warpcheck::WarpInput& in) { return {{in.u[0], in.u[1]}, in.bits}; }

/// A warp given as std::functions over plain arrays.
class ErasedWarpCase final : public WarpCase {
public:
    ErasedWarpCase(WarpCaseInfo info, detail::ErasedWarp warp)
        : WarpCase(std::move(info), signature_of(warp)), warp_(std::move(warp)) {}

    void sample(std::span<const warpcheck::WarpInput> in, std::span<WarpOutput> out) const override {
        double value = 0.0;
        for (std::size_t k = 0; k < in.size(); ++k) out[k] = warp_.sample(to_input17(in[k]), value);
    }
    void sample_with_value(std::span<const warpcheck::WarpInput> in, std::span<WarpOutput> out,
                           std::span<double> value) const override {
        if (sample_returns() == SampleReturns::Point || sample_returns() == SampleReturns::Index)
            return WarpCase::sample_with_value(in, out, value);
        for (std::size_t k = 0; k < in.size(); ++k) out[k] = warp_.sample(to_input17(in[k]), value[k]);
    }
    void pdf(std::span<const WarpOutput> x, std::span<double> out) const override {
        if (!warp_.pdf) throw std::logic_error("warp case " + name() + " has no pdf function");
        for (std::size_t k = 0; k < x.size(); ++k) out[k] = warp_.pdf(x[k]);
    }
    void eval(std::span<const WarpOutput> x, std::span<double> out) const override {
        if (!warp_.eval) return WarpCase::eval(x, out);
        for (std::size_t k = 0; k < x.size(); ++k) out[k] = warp_.eval(x[k]);
    }
    void invert(std::span<const WarpOutput> x, std::span<warpcheck::WarpInput> out) const override {
        if (!warp_.invert) throw std::logic_error("warp case " + name() + " has no inverse");
        for (std::size_t k = 0; k < x.size(); ++k) {
            const detail::WarpInput u = warp_.invert(x[k]);
            out[k] = {{u.u[0], u.u[1], 0.0f}, u.bits};
        }
    }

private:
    detail::ErasedWarp warp_;
};

BsdfFlags to_lobes(const BsdfInfo& in) {
    BsdfFlags lobes = BsdfFlags::None;
    if (in.reflection) lobes = lobes | BsdfFlags::Reflection;
    if (in.transmission) lobes = lobes | BsdfFlags::Transmission;
    if (in.continuous) lobes = lobes | BsdfFlags::Continuous;
    if (in.delta) lobes = lobes | BsdfFlags::Delta;
    return lobes;
}

BsdfClaims to_claims(const BsdfInfo& in) {
    return {.wo = {in.wo[0], in.wo[1], in.wo[2]},
            .lobes = in.phase_function ? BsdfFlags::Continuous : to_lobes(in),
            .reciprocal = in.reciprocal,
            .transport = in.importance ? Transport::Importance : Transport::Radiance,
            .eta = in.eta,
            .phase_function = in.phase_function,
            .stochastic = in.stochastic};
}

/// The plain sample as the checks see it: its lobe's flags from the two bools.
::warpcheck::BsdfSample to_sample(const BsdfSample& s) {
    BsdfFlags flags = s.transmission ? BsdfFlags::Transmission : BsdfFlags::Reflection;
    flags = flags | (s.delta ? BsdfFlags::Delta : BsdfFlags::Continuous);
    return {{s.wi[0], s.wi[1], s.wi[2]}, s.f, s.pdf, flags, s.eta};
}

Point to_point(Vector3f v) { return {v.x, v.y, v.z}; }

/// A spectral BSDF of erased parts with N channels, as make_spectral_bsdf_case takes it.
template <std::size_t N>
struct ErasedSpectralObject {
    std::shared_ptr<const detail::ErasedSpectralBsdf> parts;
    BsdfFlags lobes;

    SpectralSample<N> sample(Vector3f wo, float uc, Point2f u, int hero) const {
        SpectralSample<N> out;
        const BsdfSample s = parts->sample(to_point(wo), uc, {u.x, u.y}, hero, out.f.data(), out.pdf.data());
        const ::warpcheck::BsdfSample lobe = to_sample(s);
        out.wi = lobe.wi;
        out.flags = lobe.flags;
        out.eta = s.eta;
        return out;
    }
    std::array<float, N> f(Vector3f wo, Vector3f wi) const {
        std::array<float, N> out{};
        parts->f(to_point(wo), to_point(wi), out.data());
        return out;
    }
    std::array<float, N> pdf(Vector3f wo, Vector3f wi) const {
        std::array<float, N> out{};
        parts->pdf(to_point(wo), to_point(wi), out.data());
        return out;
    }
    BsdfFlags flags() const { return lobes; }
};

constexpr std::size_t kMaxChannels = 16;

/// make_spectral_bsdf_case of the erased parts, with their channel count as a
/// type: N from 1 up to kMaxChannels, tried in turn.
template <std::size_t N = 1>
std::unique_ptr<WarpCase> spectral_case(WarpCaseInfo info, const BsdfClaims& claims,
                                        std::shared_ptr<const detail::ErasedSpectralBsdf> parts, int hero) {
    if constexpr (N > kMaxChannels) {
        throw std::invalid_argument("add_spectral_bsdf: " + info.family + " has " + std::to_string(parts->channels) +
                                    " channels; at most " + std::to_string(kMaxChannels) + " are supported");
    } else {
        if (parts->channels != N) return spectral_case<N + 1>(std::move(info), claims, std::move(parts), hero);
        const BsdfFlags lobes = claims.lobes;
        return make_spectral_bsdf_case(std::move(info), claims, ErasedSpectralObject<N>{std::move(parts), lobes}, hero);
    }
}

}  // namespace

double GridPoint::operator[](const std::string& name) const {
    for (const auto& [axis, value] : params_)
        if (axis == name) return value;
    throw std::invalid_argument("grid point has no parameter " + name);
}

namespace detail {

void add_erased(Registry& registry, const CaseInfo& info, ErasedWarp warp, Sweep sweep) {
    std::unique_ptr<WarpCase> made = std::make_unique<ErasedWarpCase>(to_info(info), std::move(warp));
    if (sweep.input_bits == 32)
        made = warpcheck::detail::u32_sweep(std::move(made), std::move(sweep.block),
                                            static_cast<warpcheck::Monotone>(sweep.monotone));
    else if (sweep.input_bits == 64)
        made = warpcheck::detail::u64_sweep(std::move(made), std::move(sweep.block),
                                            {.shift = sweep.subrange.shift, .low_bits = sweep.subrange.low_bits},
                                            static_cast<warpcheck::Monotone>(sweep.monotone));
    registry.add_case(std::move(made));
}

std::vector<GridPoint> grid_points(const CaseInfo& base, const std::vector<GridAxis>& axes) {
    WarpCaseInfo info;
    info.family = base.family;
    info.params = to_params(base.params);
    std::vector<warpcheck::GridAxis> converted;
    for (const GridAxis& axis : axes) converted.push_back({axis.name, axis.values, {}});
    std::vector<GridPoint> points;
    for (const warpcheck::GridPoint& point : warpcheck::grid_points(info, converted)) {
        std::vector<std::pair<std::string, double>> params;
        for (const Parameter& p : point.params()) params.emplace_back(p.name, p.value);
        points.emplace_back(std::move(params));
    }
    return points;
}

void add_family(Registry& registry, const std::string& family,
                const std::vector<std::pair<std::string, double>>& base_params, const std::string& description,
                const std::vector<GridAxis>& axes, PointAdder add_point) {
    CaseFamily made;
    made.base.family = family;
    made.base.params = to_params(base_params);
    made.base.description = description;
    for (const GridAxis& axis : axes) {
        warpcheck::GridAxis converted{axis.name, axis.values, {}};
        for (const ParamRange& r : axis.ranges) converted.ranges.push_back({r.lo, r.hi, r.lo_open, r.hi_open});
        made.axes.push_back(std::move(converted));
    }
    // A point's case is made by the C++17 side's own registration, into a
    // registry of its own, and handed over.
    made.make = [adder = std::make_shared<PointAdder>(std::move(add_point))](
                    WarpCaseInfo, const warpcheck::GridPoint& p) -> std::unique_ptr<WarpCase> {
        std::vector<std::pair<std::string, double>> point;
        for (const Parameter& q : p.params()) point.emplace_back(q.name, q.value);
        Registry own;
        (*adder)(own, point);
        std::vector<std::unique_ptr<WarpCase>> cases = own.take_cases();
        if (cases.size() != 1) throw std::logic_error("a C++17 grid point made " + std::to_string(cases.size()) + " cases");
        return std::move(cases.front());
    };
    registry.add_family(std::move(made));
}

Point grid_wo(const GridPoint& point) {
    double phi = 0.0;
    for (const auto& [name, value] : point.params())
        if (name == "phi_o") phi = value;
    return bsdf_direction(point["theta_o"], phi);
}

void add_erased_bsdf(Registry& registry, const BsdfInfo& info, BsdfSampleFn sample, BsdfEvalFn f, BsdfEvalFn pdf) {
    WarpCaseInfo converted = named(info, info.chi2_resolution);
    registry.add_case(make_bsdf_case(
        std::move(converted), to_claims(info),
        bsdf_of([sample = std::move(sample)](Vector3f wo, float uc, Point2f u) {
            return to_sample(sample(to_point(wo), uc, {u.x, u.y}));
        })
            .with_f([f = std::move(f)](Vector3f wo, Vector3f wi) { return f(to_point(wo), to_point(wi)); })
            .with_pdf([pdf = std::move(pdf)](Vector3f wo, Vector3f wi) { return pdf(to_point(wo), to_point(wi)); })));
}

/// A light of erased parts, as make_light_case takes it.
struct ErasedLight {
    LightSampleFn sample_fn;
    LightEvalFn pdf_fn, radiance_fn;

    ::warpcheck::LightSample sample(Vector3f ref, Point2f u) const {
        const LightSample s = sample_fn(to_point(ref), {u.x, u.y});
        return {{s.wi[0], s.wi[1], s.wi[2]}, s.pdf, s.L, s.distance};
    }
    double pdf(Vector3f ref, Vector3f wi) const { return pdf_fn(to_point(ref), to_point(wi)); }
    double L(Vector3f ref, Vector3f wi) const { return radiance_fn(to_point(ref), to_point(wi)); }
};

void add_erased_light(Registry& registry, const LightInfo& info, LightSampleFn sample, LightEvalFn pdf,
                      LightEvalFn radiance) {
    WarpCaseInfo converted = named(info, info.chi2_resolution);
    const LightClaims claims{.ref = {info.ref[0], info.ref[1], info.ref[2]},
                             .normal = {info.normal[0], info.normal[1], info.normal[2]}};
    registry.add_case(make_light_case(std::move(converted), claims,
                                      ErasedLight{std::move(sample), std::move(pdf), std::move(radiance)}));
}

void add_erased_mis(Registry& registry, const MisInfo& info, const BsdfInfo& bsdf, ErasedMis parts) {
    WarpCaseInfo bsdf_case = named(bsdf, bsdf.chi2_resolution);
    auto b = make_bsdf_case(
        std::move(bsdf_case), to_claims(bsdf),
        bsdf_of([sample = parts.bsdf_sample](Vector3f wo, float uc, Point2f u) {
            return to_sample(sample(to_point(wo), uc, {u.x, u.y}));
        })
            .with_f([f = parts.bsdf_f](Vector3f wo, Vector3f wi) { return f(to_point(wo), to_point(wi)); })
            .with_pdf([pdf = parts.bsdf_pdf](Vector3f wo, Vector3f wi) { return pdf(to_point(wo), to_point(wi)); }));
    MisClaims mis{.heuristic = info.power_heuristic ? MisHeuristic::Power : MisHeuristic::Balance};
    if (parts.bsdf_mis_pdf)
        mis.pdfs.bsdf = [pdf = parts.bsdf_mis_pdf](Vector3f wo, Vector3f wi) {
            return static_cast<float>(pdf(to_point(wo), to_point(wi)));
        };
    std::vector<std::unique_ptr<WarpCase>> lights;
    for (MisLight& light : parts.lights) {
        WarpCaseInfo light_case = named(light.info, light.info.chi2_resolution);
        const LightClaims claims{.ref = {light.info.ref[0], light.info.ref[1], light.info.ref[2]},
                                 .normal = {light.info.normal[0], light.info.normal[1], light.info.normal[2]}};
        lights.push_back(make_light_case(std::move(light_case), claims,
                                         ErasedLight{light.sample, light.pdf, light.radiance}));
        std::function<float(Vector3f, Vector3f)> mis_pdf;  // empty: the light's own pdf
        if (light.mis_pdf)
            mis_pdf = [pdf = std::move(light.mis_pdf)](Vector3f ref, Vector3f wi) {
                return static_cast<float>(pdf(to_point(ref), to_point(wi)));
            };
        mis.pdfs.lights.push_back(std::move(mis_pdf));
    }
    WarpCaseInfo converted = named(info, info.chi2_resolution);
    registry.add_case(make_mis_case(std::move(converted), std::move(mis), std::move(b), std::move(lights)));
}

void add_erased_spectral_bsdf(Registry& registry, const BsdfInfo& info, ErasedSpectralBsdf bsdf, int hero) {
    WarpCaseInfo converted = named(info, info.chi2_resolution);
    registry.add_case(spectral_case(std::move(converted), to_claims(info),
                                    std::make_shared<const ErasedSpectralBsdf>(std::move(bsdf)), hero));
}

}  // namespace detail

Point bsdf_direction(double theta_degrees, double phi_degrees) {
    return to_point(::warpcheck::bsdf_direction(theta_degrees, phi_degrees));
}

void mark_known_flaw(Registry& registry, const std::string& case_name, const std::string& check_name,
                     const std::string& flaw) {
    if (check_name.empty()) registry.mark_known_flaw(case_name, flaw);
    else registry.mark_known_flaw(case_name, check_name, flaw);
}

}  // namespace warpcheck::cxx17

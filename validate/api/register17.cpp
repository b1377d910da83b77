// The C++17 registration header's functions (validate/api/register17.h), compiled
// as C++20 with the rest of warpcheck: each converts the plain description to
// a WarpCaseInfo and wraps the callables in a WarpCase.
#include "validate/api/register17.h"

#include <stdexcept>

#include "validate/api/bsdf_case.h"
#include "validate/api/registry.h"

namespace warpcheck::cxx17 {
namespace {

InputKind to_input_kind(Input input) {
    switch (input) {
        case Input::Uniform1D: return InputKind::Uniform1D;
        case Input::Uniform2D: return InputKind::Uniform2D;
        case Input::Bits32: return InputKind::Bits32;
        case Input::Bits64: return InputKind::Bits64;
    }
    throw std::invalid_argument("register17: unknown input kind");
}

chi2::Domain to_domain(const Domain& d) {
    switch (d.kind) {
        case Domain::Kind::Interval: return chi2::Domain::interval(d.a, d.b);
        case Domain::Kind::HalfLine: return chi2::Domain::half_line(d.a);
        case Domain::Kind::LowerHalfLine: return chi2::Domain::lower_half_line(d.b);
        case Domain::Kind::RealLine: return chi2::Domain::real_line();
        case Domain::Kind::Box: return chi2::Domain::box(d.a, d.b, d.c, d.d);
        case Domain::Kind::UnitDisk: return chi2::Domain::unit_disk();
        case Domain::Kind::SphericalCap: return chi2::Domain::spherical_cap(d.c);
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

WarpCaseInfo to_info(const CaseInfo& in) {
    WarpCaseInfo info;
    info.family = in.family;
    for (const auto& [name, value] : in.params) info.params.push_back({name, value});
    info.description = in.description;
    info.input = to_input_kind(in.input);
    info.domain = to_domain(in.domain);
    info.roundtrip_tolerance = in.roundtrip_tolerance;
    for (const View& v : in.views) info.views.push_back(to_view(v));
    info.inversion = in.inversion == Inversion::Claimed        ? warpcheck::Inversion::Claimed
                     : in.inversion == Inversion::NotInversion ? warpcheck::Inversion::NotInversion
                                                               : warpcheck::Inversion::Measure;
    return info;
}

/// A warp given as std::functions over plain arrays.
class FunctionWarpCase final : public WarpCase {
public:
    FunctionWarpCase(WarpCaseInfo info, SampleFn sample, PdfFn pdf, InvertFn invert)
        : WarpCase(std::move(info)), sample_(std::move(sample)), pdf_(std::move(pdf)), invert_(std::move(invert)) {}

    void sample(std::span<const warpcheck::WarpInput> in, std::span<WarpOutput> out) const override {
        for (std::size_t k = 0; k < in.size(); ++k) out[k] = sample_({{in[k].u[0], in[k].u[1]}, in[k].bits});
    }
    void pdf(std::span<const WarpOutput> x, std::span<double> out) const override {
        for (std::size_t k = 0; k < x.size(); ++k) out[k] = pdf_(x[k]);
    }
    void invert(std::span<const WarpOutput> x, std::span<warpcheck::WarpInput> out) const override {
        if (!invert_) throw std::logic_error("warp case " + name() + " has no inverse");
        for (std::size_t k = 0; k < x.size(); ++k) {
            const WarpInput u = invert_(x[k]);
            out[k] = {{u.u[0], u.u[1]}, u.bits};
        }
    }
    bool has_inverse() const override { return static_cast<bool>(invert_); }

private:
    SampleFn sample_;
    PdfFn pdf_;
    InvertFn invert_;
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
            .phase_function = in.phase_function};
}

/// The plain sample as the checks see it: its lobe's flags from the two bools.
::warpcheck::BsdfSample to_sample(const BsdfSample& s) {
    BsdfFlags flags = s.transmission ? BsdfFlags::Transmission : BsdfFlags::Reflection;
    flags = flags | (s.delta ? BsdfFlags::Delta : BsdfFlags::Continuous);
    return {{s.wi[0], s.wi[1], s.wi[2]}, s.f, s.pdf, flags, s.eta};
}

Point to_point(Vector3f v) { return {v.x, v.y, v.z}; }

}  // namespace

void add_bsdf(Registry& registry, const BsdfInfo& info, BsdfSampleFn sample, BsdfEvalFn f, BsdfEvalFn pdf) {
    WarpCaseInfo converted;
    converted.family = info.family;
    for (const auto& [name, value] : info.params) converted.params.push_back({name, value});
    converted.description = info.description;
    const std::string name = case_name(converted.family, converted.params);
    if (!sample || !f || !pdf) throw std::invalid_argument("registry: BSDF case " + name + " needs sample, f and pdf");
    const BsdfClaims claims = to_claims(info);
    registry.add_case(make_bsdf_case(
        std::move(converted), claims,
        [sample = std::move(sample)](Vector3f wo, float uc, Point2f u) {
            return to_sample(sample(to_point(wo), uc, {u.x, u.y}));
        },
        [f = std::move(f)](Vector3f wo, Vector3f wi) { return f(to_point(wo), to_point(wi)); },
        [pdf = std::move(pdf)](Vector3f wo, Vector3f wi) { return pdf(to_point(wo), to_point(wi)); }));
}

Point bsdf_direction(double theta_degrees, double phi_degrees) {
    return to_point(::warpcheck::bsdf_direction(theta_degrees, phi_degrees));
}

void add_case(Registry& registry, const CaseInfo& info, SampleFn sample, PdfFn pdf, InvertFn invert) {
    WarpCaseInfo converted = to_info(info);
    const std::string name = case_name(converted.family, converted.params);
    if (!sample || !pdf) throw std::invalid_argument("registry: warp case " + name + " needs sample and pdf functions");
    registry.add_case(
        std::make_unique<FunctionWarpCase>(std::move(converted), std::move(sample), std::move(pdf), std::move(invert)));
}

void mark_known_flaw(Registry& registry, const std::string& case_name, const std::string& check_name,
                     const std::string& flaw) {
    if (check_name.empty()) registry.mark_known_flaw(case_name, flaw);
    else registry.mark_known_flaw(case_name, check_name, flaw);
}

}  // namespace warpcheck::cxx17

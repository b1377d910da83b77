#include "validate/api/bsdf_case.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace warpcheck {

Vector3f bsdf_direction(double theta_degrees, double phi_degrees) {
    const double t = theta_degrees * std::numbers::pi / 180.0, p = phi_degrees * std::numbers::pi / 180.0;
    return {static_cast<float>(std::sin(t) * std::cos(p)), static_cast<float>(std::sin(t) * std::sin(p)),
            static_cast<float>(std::cos(t))};
}

namespace {

WarpCaseInfo bsdf_info(WarpCaseInfo info) {
    info.domain = chi2::Domain::sphere();
    return info;
}

/// What every BSDF case is: (uc, u) in, a direction on the sphere out, with f and a pdf.
constexpr WarpSignature kBsdfSignature{.input = InputKind::Uniform3D,
                                       .returns = SampleReturns::Bsdf,
                                       .output_dimension = 3,
                                       .has_pdf = true,
                                       .has_inverse = false,
                                       .has_eval = false};

}  // namespace

BsdfCase::BsdfCase(WarpCaseInfo info, BsdfClaims claims)
    : WarpCase(bsdf_info(std::move(info)), kBsdfSignature), claims_(claims) {}

void BsdfCase::f_cos(std::span<const WarpOutput> wi, std::span<double> out) const {
    const std::vector<WarpOutput> wo(wi.size(), detail::to_output_of(claims_.wo));
    f(wo, wi, out);
    for (std::size_t k = 0; k < wi.size(); ++k) out[k] *= cosine(wi[k]);
}

double BsdfCase::energy_factor(const WarpOutput& wi) const {
    if (!transmitted(wi) || claims_.transport != Transport::Radiance) return 1.0;
    const double eta = claims_.eta;
    // eta(wi) / eta(wo): the index below over above when wi is below.
    const double ratio = wi[2] < 0.0f ? eta : 1.0 / eta;
    return ratio * ratio;
}

void BsdfCase::sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const {
    std::vector<BsdfRecord> records(in.size());
    sample_bsdf(in, records);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (std::size_t k = 0; k < in.size(); ++k) out[k] = records[k].sampled() ? records[k].wi : WarpOutput{nan, nan, nan};
}

void BsdfCase::invert(std::span<const WarpOutput>, std::span<WarpInput>) const {
    throw std::logic_error("BSDF case " + name() + " has no inverse");
}

}  // namespace warpcheck

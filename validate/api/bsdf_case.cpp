#include "validate/api/bsdf_case.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <fmt/format.h>

namespace warpcheck {

Vector3f bsdf_direction(double theta_degrees, double phi_degrees) {
    const double t = theta_degrees * std::numbers::pi / 180.0, p = phi_degrees * std::numbers::pi / 180.0;
    return {static_cast<float>(std::sin(t) * std::cos(p)), static_cast<float>(std::sin(t) * std::sin(p)),
            static_cast<float>(std::cos(t))};
}

namespace {

WarpCaseInfo bsdf_info(WarpCaseInfo info) {
    info.input = InputKind::Uniform3D;
    info.domain = chi2::Domain::sphere();
    return info;
}

/// The first thing wrong with the claims, or "".
std::string claims_problem(const BsdfClaims& c) {
    const double len = std::hypot(static_cast<double>(c.wo.x), static_cast<double>(c.wo.y), static_cast<double>(c.wo.z));
    // A float direction rounded from a unit vector is within 2^-23 of unit length;
    // 2^-16 leaves room for a renderer's own normalisation and still refuses a
    // wo that was never normalised.
    if (!(std::abs(len - 1.0) <= 0x1p-16))
        return fmt::format("wo ({}, {}, {}) is not a unit vector (length {})", c.wo.x, c.wo.y, c.wo.z, len);
    if (c.wo.z == 0.0f && !c.phase_function) return "wo lies on the horizon (z = 0): on neither side of the surface";
    if (!has(c.lobes, BsdfFlags::Continuous) && !has(c.lobes, BsdfFlags::Delta))
        return "claims.lobes names no lobe: set BsdfFlags::Continuous and/or BsdfFlags::Delta";
    if (c.phase_function && c.lobes != BsdfFlags::Continuous)
        return "a phase function has one continuous lobe on the sphere (claims.lobes = BsdfFlags::Continuous)";
    if (!c.phase_function && !has(c.lobes, BsdfFlags::Reflection) && !has(c.lobes, BsdfFlags::Transmission))
        return "claims.lobes names neither Reflection nor Transmission";
    if (!(c.eta > 0.0f && std::isfinite(c.eta))) return fmt::format("claims.eta {} is not a positive index", c.eta);
    return "";
}

}  // namespace

BsdfCase::BsdfCase(WarpCaseInfo info, BsdfClaims claims) : WarpCase(bsdf_info(std::move(info))), claims_(claims) {
    if (const std::string problem = claims_problem(claims_); !problem.empty())
        throw std::invalid_argument("BSDF case " + name() + ": " + problem);
}

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

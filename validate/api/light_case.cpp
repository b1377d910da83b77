#include "validate/api/light_case.h"

#include <limits>
#include <vector>

namespace warpcheck {
namespace {

WarpCaseInfo light_info(WarpCaseInfo info) {
    info.domain = chi2::Domain::sphere();
    return info;
}

/// What every light case is: u in, a direction on the sphere out, with its pdf.
constexpr WarpSignature light_signature(bool has_inverse) {
    return {.input = InputKind::Uniform2D,
            .returns = SampleReturns::PointAndPdf,
            .output_dimension = 3,
            .has_pdf = true,
            .has_inverse = has_inverse,
            .has_eval = false};
}

}  // namespace

LightCase::LightCase(WarpCaseInfo info, LightClaims claims, bool has_inverse)
    : WarpCase(light_info(std::move(info)), light_signature(has_inverse)), claims_(claims) {}

void LightCase::sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const {
    std::vector<LightRecord> records(in.size());
    sample_light(in, records);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (std::size_t k = 0; k < in.size(); ++k) out[k] = records[k].sampled() ? records[k].wi : WarpOutput{nan, nan, nan};
}

void LightCase::sample_with_value(std::span<const WarpInput> in, std::span<WarpOutput> out,
                                  std::span<double> value) const {
    std::vector<LightRecord> records(in.size());
    sample_light(in, records);
    for (std::size_t k = 0; k < in.size(); ++k) {
        out[k] = records[k].wi;
        value[k] = static_cast<double>(records[k].pdf);
    }
}

}  // namespace warpcheck

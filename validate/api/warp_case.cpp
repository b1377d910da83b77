#include "validate/api/warp_case.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

namespace warpcheck {

std::string parameter_value(double value) {
    // {} gives the shortest decimal that reads back as the same value: 0.3,
    // 1e-06, 85. A parameter that came from a float (0.3f, stored as the double
    // 0.30000001192092896) reads as that float's shortest decimal, "0.3", when
    // that is the shorter of the two; reading it back as a float gives the
    // parameter again. A double that is no float keeps all its digits.
    const std::string as_double = fmt::format("{}", value);
    if (!(std::abs(value) <= std::numeric_limits<float>::max())) return as_double;  // NaN, inf, beyond float
    const auto narrow = static_cast<float>(value);
    if (static_cast<double>(narrow) != value) return as_double;
    const std::string as_float = fmt::format("{}", narrow);
    return as_float.size() < as_double.size() ? as_float : as_double;
}

WarpCase::WarpCase(WarpCaseInfo info, const WarpSignature& signature)
    : info_(std::move(info)), signature_(signature), name_(case_name(info_.family, info_.params)) {
    // Unset, the input is what the signature says; set, it is a claim that
    // validate_case holds against the signature.
    if (!info_.input) info_.input = signature_.input;
}

void WarpCase::sample_planar(const float* u0, const float* u1, float* x, float* y, float* z, std::size_t n) const {
    constexpr std::size_t kBlock = 256;
    std::array<WarpInput, kBlock> in{};
    std::array<WarpOutput, kBlock> out{};
    for (std::size_t first = 0; first < n; first += kBlock) {
        const std::size_t m = std::min(kBlock, n - first);
        for (std::size_t k = 0; k < m; ++k) in[k].u = {u0[first + k], u1[first + k]};
        sample(std::span<const WarpInput>(in.data(), m), std::span<WarpOutput>(out.data(), m));
        for (std::size_t k = 0; k < m; ++k)
            x[first + k] = out[k][0], y[first + k] = out[k][1], z[first + k] = out[k][2];
    }
}

std::string case_name(const std::string& family, const std::vector<Parameter>& params) {
    if (params.empty()) return family;
    std::string name = family + "[";
    for (std::size_t i = 0; i < params.size(); ++i) {
        if (i > 0) name += ",";
        name += params[i].name + "=" + parameter_value(params[i].value);
    }
    return name + "]";
}

}  // namespace warpcheck

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

namespace {

const char* input_name(InputKind k) {
    switch (k) {
        case InputKind::Uniform1D: return "Uniform1D (a float)";
        case InputKind::Uniform2D: return "Uniform2D (a Point2f)";
        case InputKind::Bits32: return "Bits32 (a uint32_t)";
        case InputKind::Bits64: return "Bits64 (a uint64_t)";
        case InputKind::Uniform3D: return "Uniform3D (a BSDF's uc and u)";
    }
    return "?";
}

/// Whether the domain is the one WarpCaseInfo starts with, i.e. left unset.
bool default_domain(const chi2::Domain& d) {
    if (!d.is<chi2::Box>()) return false;
    const chi2::Box& b = d.as<chi2::Box>();
    return b.x0 == 0.0 && b.x1 == 1.0 && b.y0 == 0.0 && b.y1 == 1.0;
}

// The first thing wrong with a discrete case, or "".
std::string discrete_problem(const WarpCaseInfo& info, bool has_inverse, bool has_eval) {
    if (info.categories == 0) return "its sample returns an index, so it needs .categories (how many there are)";
    if (info.categories > (std::size_t{1} << 24))
        return fmt::format("{} categories: at most 2^24 (indices travel as exact floats)", info.categories);
    if (!default_domain(info.domain))
        return fmt::format("a discrete case has no continuous domain, but .domain is the {} (leave it unset: "
                           ".categories declares the choices)", info.domain.describe());
    if (has_inverse) return "a discrete case has no inverse";
    if (has_eval) return "a discrete case has no eval";
    if (!info.views.empty()) return "a discrete case has no monotone views";
    return "";
}

// The first thing wrong with a continuous case, or "".
std::string continuous_problem(const WarpCase& c, int output_dimension, bool has_eval) {
    const WarpCaseInfo& info = c.info();
    const SampleReturns r = c.sample_returns();
    if (info.categories != 0) return "it declares .categories but its sample returns a point, not an index";
    if (output_dimension != info.domain.point_dimension())
        return fmt::format("its points have {} coordinates, but the {} has {}", output_dimension,
                           info.domain.describe(), info.domain.point_dimension());
    if (r == SampleReturns::PointAndWeight && !has_eval)
        return "its sample returns a weight but there is no eval to check it against "
               "(make_weighted_case(info, sample, eval, pdf))";
    if (has_eval && r != SampleReturns::PointAndWeight)
        return "it has an eval but its sample returns no weight (return a WeightedSample)";
    if (!c.has_pdf() && r != SampleReturns::PointAndPdf)
        return "it has no pdf: give a pdf function, or return the pdf with each sample (PdfSample)";
    return "";
}

}  // namespace

void WarpCase::validate_declaration(const Declaration& d) const {
    std::string problem;
    if (d.input && *d.input != info_.input)
        problem = fmt::format("its sample takes {} but .input is {}", input_name(*d.input), input_name(info_.input));
    else if (is_discrete() != (d.output_dimension == 0))
        problem = is_discrete() ? "its sample returns an index but its pdf takes a point"
                                : "its pdf takes an index but its sample returns a point";
    else if (is_discrete())
        problem = discrete_problem(info_, has_inverse(), d.has_eval);
    else
        problem = continuous_problem(*this, d.output_dimension, d.has_eval);
    if (!problem.empty()) throw std::invalid_argument("warp case " + name_ + ": " + problem);
}

}  // namespace warpcheck

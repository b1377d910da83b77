#include "validate/checks/shared/line_resolution.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace warpcheck {
namespace {

/// A fixed grid of inputs: 257 values across [0, 1) in 1D, 17 x 17 in 2D, the
/// same spread over the raw bits.
std::vector<WarpInput> pilot_inputs(InputKind kind) {
    const int n = input_dimension(kind) == 2 ? 17 : 257;
    std::vector<WarpInput> in;
    for (int i = 0; i < n; ++i) {
        const double t = (i + 0.5) / n;
        if (kind == InputKind::Uniform2D) {
            for (int j = 0; j < n; ++j) in.push_back({{static_cast<float>(t), static_cast<float>((j + 0.5) / n)}, 0});
        } else if (takes_bits(kind)) {
            const double range = kind == InputKind::Bits32 ? 0x1p32 : 0x1p64;
            in.push_back({{0.0f, 0.0f}, static_cast<uint64_t>(t * range)});
        } else {
            in.push_back({{static_cast<float>(t), 0.0f}, 0});
        }
    }
    return in;
}

double median_output(const WarpCase& warp) {
    const std::vector<WarpInput> in = pilot_inputs(warp.input_kind());
    std::vector<WarpOutput> out(in.size());
    warp.sample(in, out);
    std::vector<double> x;
    for (const WarpOutput& o : out)
        if (std::isfinite(o[0])) x.push_back(static_cast<double>(o[0]));
    if (x.empty()) return 0.0;
    std::nth_element(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(x.size() / 2), x.end());
    return x[x.size() / 2];
}

double inverse_density_at(const WarpCase& warp, double x) {
    const std::vector<WarpOutput> at = {{static_cast<float>(x), 0.0f, 0.0f}};
    std::vector<double> density(1);
    warp.pdf(at, density);
    const double s = 1.0 / density[0];
    return std::isfinite(s) && s > 0.0 ? s : 1.0;
}

}  // namespace

chi2::BinResolution line_resolution(const WarpCase& warp) {
    chi2::BinResolution r = warp.info().chi2_resolution;
    const chi2::Domain& d = warp.domain();
    if (!d.unbounded_line()) return r;
    if (d.is<chi2::RealLine>() && r.line_center == 0.0) r.line_center = median_output(warp);
    if (r.half_line_scale == 0.0) {
        const double anchor = d.is<chi2::HalfLine>() ? d.a() : d.is<chi2::LowerHalfLine>() ? d.b() : r.line_center;
        r.half_line_scale = inverse_density_at(warp, anchor);
        // A density unbounded at the anchor (Weibull with shape below 1: its
        // float value there is the largest float or infinite) gives no length
        // scale; where 1/density is below a thousandth of the median's
        // distance from the anchor, that distance is the scale (half the cells
        // then lie within it, as the map intends).
        if (!d.is<chi2::RealLine>()) {
            const double median = std::abs(median_output(warp) - anchor);
            if (std::isfinite(median) && median > 0.0 && r.half_line_scale < 1e-3 * median) r.half_line_scale = median;
        }
    }
    return r;
}

}  // namespace warpcheck

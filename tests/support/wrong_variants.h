// Wrong variants of the exponential and Trowbridge-Reitz warps, planted on
// purpose; shared by the tests that must catch them. `wrong` false gives the
// correct warp built the same way, so a test can check both directions.
#pragma once

#include <cmath>
#include <memory>
#include <numbers>

#include "sampling/exponential.h"
#include "sampling/trowbridge_reitz.h"
#include "validate/api/warp_case.h"

namespace warpcheck::testing {

/// D written with the classic typo: alpha / (pi cos^4 (alpha + tan^2)^2) instead
/// of alpha^2 / (pi cos^4 (alpha^2 + tan^2)^2). `wrong` false gives the right D.
inline double isotropic_D(double alpha, double z, bool wrong) {
    const double a = wrong ? alpha : alpha * alpha;
    const double c2 = z * z, tan2 = (1.0 - c2) / c2;
    return a / (std::numbers::pi * c2 * c2 * (a + tan2) * (a + tan2));
}

inline std::unique_ptr<WarpCase> tr_normals(float alpha, bool wrong) {
    WarpCaseInfo info;
    info.family = wrong ? "trowbridge_reitz_normals_alpha_not_squared" : "trowbridge_reitz_normals";
    info.params = {{"ax", alpha}, {"ay", alpha}};
    info.domain = chi2::Domain::hemisphere();
    // The marginal of cos(theta_m) as its author would derive it from D: 2 pi z D(z).
    MonotoneMarginal m;
    m.increasing = false;
    m.coordinate = [](const WarpOutput& o) { return static_cast<double>(o[2]); };
    m.pdf = [alpha, wrong](double z) { return z > 0.0 ? 2.0 * std::numbers::pi * z * isotropic_D(alpha, z, wrong) : 0.0; };
    info.views = {m};
    const TrowbridgeReitzNormals normals = TrowbridgeReitz(alpha).normals();
    return make_warp_case(
        info,
            warp_of([normals](Point2f u) { return normals.sample(u); })
                .with_pdf([alpha, wrong](Vector3f w) { return w.z > 0.0f ? isotropic_D(alpha, w.z, wrong) * w.z : 0.0; })
                .with_invert([normals](Vector3f w) { return normals.invert(w); }));
}

inline std::unique_ptr<WarpCase> trimmed(float c, float x_max, bool wrong) {
    WarpCaseInfo info;
    info.family = wrong ? "trimmed_exponential_untrimmed_norm" : "trimmed_exponential";
    info.params = {{"c", c}, {"x_max", x_max}};
    info.domain = chi2::Domain::interval(0.0, x_max);
    const TrimmedExponential t(c, x_max);
    return make_warp_case(
        info,
            warp_of([t](float u) { return t.sample(u); })
                .with_pdf([t, wrong](float x) {
                    // The bug: c exp(-c x), forgetting the 1 / (1 - exp(-c x_max)) of the trimming.
                    return wrong ? (x >= 0.0f && x <= t.x_max() ? t.rate() * std::exp(-t.rate() * x) : 0.0f) : t.pdf(x);
                })
                .with_invert([t](float x) { return t.invert(x); }));
}

inline std::unique_ptr<WarpCase> visible(float alpha, double theta_o_degrees, bool wrong) {
    WarpCaseInfo info;
    info.family = wrong ? "trowbridge_reitz_visible_abs_dot" : "trowbridge_reitz_visible";
    info.params = {{"ax", alpha}, {"ay", alpha}, {"theta_o", theta_o_degrees}};
    info.domain = chi2::Domain::hemisphere();
    const double t = theta_o_degrees * std::numbers::pi / 180.0;
    const TrowbridgeReitz tr(alpha);
    const auto vis = tr.visible_normals({static_cast<float>(std::sin(t)), 0.0f, static_cast<float>(std::cos(t))});
    return make_warp_case(
        info,
            warp_of([vis](Point2f u) { return vis.sample(u); })
                .with_pdf([vis, wrong](Vector3f w) {
                    if (!wrong) return vis.pdf(w);
                    // The bug: |wo.wm| lets back-facing normals into the density, which
                    // then integrates to more than 1 (the samples never go there).
                    const TrowbridgeReitz& d = vis.distribution();
                    return w.z >= 0.0f ? d.G1_over_cos(vis.wo()) * std::abs(dot(vis.wo(), w)) * d.D(w) : 0.0f;
                })
                .with_invert([vis](Vector3f w) { return vis.invert(w); }));
}

}  // namespace warpcheck::testing

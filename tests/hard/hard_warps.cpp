// hard_warps: the catalogue of correct-but-hard warps of issue 22, as a
// program built on warpcheck::main (a `validate` over these warps). `--all`
// runs the correct ones, which must pass on every seed; `--include-flawed`
// (or a twin's full name) runs the wrong twins, which must fail. run_hard.sh
// asserts both; hard_warps_fpr measures the false-failure rate over seeds.
#include "hard_warps.h"

#include <cmath>
#include <utility>

namespace hard {

warpcheck::MonotoneMarginal cos_theta_view(Vector3f axis, bool increasing, double lo,
                                           std::function<double(double)> pdf) {
    warpcheck::MonotoneMarginal view;
    view.input_coordinate = 0;
    view.increasing = increasing;
    view.lo = lo;
    view.hi = 1;
    view.label = "cos theta";
    // The angle's cosine, not the dot product of the float vectors: a float
    // axis (and a rotated float output) has a norm 1 +- a few 1e-8, so their
    // dot product at the lobe's peak is 1 - 9e-8 (hg_float[g=0.95] about the
    // 57 degree axis), which no sample can exceed, and the tabulated check's
    // reach rule counts the peak's 2.3e-5 of mass above it as unreachable. The
    // norms are the consistency check's business; clamped to 1 (rounding of
    // the double normalisation) into [-1, 1].
    const double a = std::sqrt(double{axis.x} * axis.x + double{axis.y} * axis.y + double{axis.z} * axis.z);
    view.coordinate = [axis, a](const warpcheck::WarpOutput& w) {
        const double dot = double{w[0]} * axis.x + double{w[1]} * axis.y + double{w[2]} * axis.z;
        const double norm = std::sqrt(double{w[0]} * w[0] + double{w[1]} * w[1] + double{w[2]} * w[2]);
        const double cos_theta = dot / (norm * a);
        return cos_theta > 1 ? 1.0 : cos_theta < -1 ? -1.0 : cos_theta;  // NaN stays NaN
    };
    view.pdf = std::move(pdf);
    return view;
}

warpcheck::MonotoneMarginal azimuth_view(const Frame& frame) {
    warpcheck::MonotoneMarginal view;
    view.input_coordinate = 1;
    view.lo = 0;
    view.hi = 2 * std::numbers::pi;
    view.label = "phi";
    view.coordinate = [frame](const warpcheck::WarpOutput& w) {
        const auto along = [&w](Vector3f e) { return double{w[0]} * e.x + double{w[1]} * e.y + double{w[2]} * e.z; };
        const double x = along(frame.x), y = along(frame.y);
        return x == 0 && y == 0 ? std::nan("") : warpcheck::chi2::exact_phi(x, y);  // NaN on the axis
    };
    view.pdf = [](double) { return 1 / (2 * std::numbers::pi); };
    return view;
}

void mark_twin(warpcheck::Registry& registry, const std::string& case_name, const std::string& checks,
               const std::string& why) {
    registry.mark_known_flaw(case_name, "wrong twin, caught by " + checks + ": " + why);
}

}  // namespace hard

void warpcheck_register(warpcheck::Registry& registry) {
    hard::register_float_pdf(registry);
    hard::register_quantised_outputs(registry);
    hard::register_supports(registry);
    hard::register_discontinuities(registry);
    hard::register_non_inversion(registry);
    hard::register_roundtrip_2d(registry);
    hard::register_chance_rules(registry);
    hard::register_verdict_words(registry);
    hard::register_misses(registry);
    hard::register_sharp_lobes(registry);
}

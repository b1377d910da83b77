#include "validate/trust/power_simulation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <thread>
#include <vector>

#include "chi2/binning.h"
#include "chi2/multiple_testing.h"
#include "sampling/pcg32.h"
#include "validate/checks/shared/power_level.h"
#include "validate/run/runner.h"
#include "validate/run/thread_pool.h"

namespace warpcheck {

double inverse_tilt(double u, double eps) {
    const double b = 1.0 - eps;
    return 2.0 * u / (b + std::sqrt(b * b + 4.0 * eps * u));
}

namespace {

/// What a tilted case is: the base's input, points, pdf and inverse; sample
/// returns the point alone.
WarpSignature tilted_signature(const WarpCase& base) {
    WarpSignature s = base.signature();
    s.returns = SampleReturns::Point;
    s.has_eval = false;
    return s;
}

class TiltedCase final : public WarpCase {
public:
    TiltedCase(const WarpCase& base, WarpCaseInfo info, int coordinate, double eps)
        : WarpCase(std::move(info), tilted_signature(base)), base_(base),
          coordinate_(static_cast<std::size_t>(coordinate)), eps_(eps) {}

    void sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const override {
        std::vector<WarpInput> tilted(in.begin(), in.end());
        for (WarpInput& w : tilted) {
            // Rounded down to a float, as the inputs themselves are, so that no
            // input reaches 1.
            const double t = inverse_tilt(w.u[coordinate_], eps_);
            float f = static_cast<float>(t);
            if (static_cast<double>(f) > t) f = std::nextafter(f, 0.0f);
            w.u[coordinate_] = f;
        }
        base_.sample(tilted, out);
    }
    void pdf(std::span<const WarpOutput> x, std::span<double> out) const override { base_.pdf(x, out); }
    void invert(std::span<const WarpOutput> x, std::span<WarpInput> out) const override { base_.invert(x, out); }

private:
    const WarpCase& base_;
    std::size_t coordinate_;
    double eps_;
};

CheckResult run_once(const WarpCase& warp, const Check& check, const RunOptions& options, ThreadPool& pool) {
    const CheckContext ctx(options, pool.executor(), job_stream(warp, check, options.seed));
    return check.run(warp, ctx);
}

}  // namespace

std::unique_ptr<WarpCase> tilted_case(const WarpCase& base, int coordinate, double eps) {
    if (coordinate < 0 || coordinate > 1) throw std::invalid_argument("tilted_case: coordinate must be 0 or 1");
    if (!(std::abs(eps) < 1.0)) throw std::invalid_argument("tilted_case: |eps| must be below 1");
    WarpCaseInfo info = base.info();
    info.family += "_tilted";
    info.params.push_back({coordinate == 0 ? "eps_u0" : "eps_u1", eps});
    // The base's lane form draws and warps untilted inputs itself: the tilted
    // case is sampled through its own sample(), which tilts u first.
    info.lanes = nullptr;
    return std::make_unique<TiltedCase>(base, std::move(info), coordinate, eps);
}

std::optional<int> driving_coordinate(const WarpCase& warp, int axis) {
    const InputKind kind = warp.input_kind();
    const int dims = kind == InputKind::Uniform2D ? 2 : kind == InputKind::Uniform1D ? 1 : 0;
    if (dims == 0 || warp.is_discrete()) return std::nullopt;
    const chi2::Binning binning(warp.domain());
    if (axis >= binning.parameter_dimension()) return std::nullopt;
    const auto parameter = [&](const WarpOutput& x) {
        return binning.parameters_of({x[0], x[1], x[2]})[static_cast<std::size_t>(axis)];
    };
    constexpr int kInputs = 256, kRedraws = 3;
    Pcg32 rng(0x5eed, 0x77);
    std::vector<WarpInput> in;
    for (int i = 0; i < kInputs; ++i) {
        WarpInput w{};
        w.u[0] = rng.next_float();
        w.u[1] = dims == 2 ? rng.next_float() : 0.0f;
        in.push_back(w);
        for (int r = 0; r < kRedraws && dims == 2; ++r) in.push_back(w);
    }
    for (int k = 0; k < dims; ++k) {
        std::vector<WarpInput> trial = in;
        for (std::size_t i = 0; i < trial.size(); ++i)
            if (i % (kRedraws + 1) != 0 && dims == 2) trial[i].u[static_cast<std::size_t>(1 - k)] = rng.next_float();
        std::vector<WarpOutput> out(trial.size());
        try {
            warp.sample(trial, out);
        } catch (...) {
            return std::nullopt;
        }
        std::vector<std::pair<float, double>> seen;  // (u_k, parameter)
        double lo = INFINITY, hi = -INFINITY;
        for (std::size_t i = 0; i < out.size(); ++i) {
            const double p = parameter(out[i]);
            if (!std::isfinite(p)) return std::nullopt;
            lo = std::min(lo, p), hi = std::max(hi, p);
            seen.push_back({trial[i].u[static_cast<std::size_t>(k)], p});
        }
        const double tolerance = 1e-6 * (hi - lo);
        bool alone = hi > lo;
        const std::size_t step = dims == 2 ? kRedraws + 1 : 1;
        for (std::size_t i = 0; alone && dims == 2 && i < seen.size(); i += step)
            for (std::size_t r = 1; r < step; ++r) alone = alone && std::abs(seen[i + r].second - seen[i].second) <= tolerance;
        if (!alone) continue;
        std::sort(seen.begin(), seen.end());
        bool up = true, down = true;
        for (std::size_t i = 1; i < seen.size(); ++i) {
            up = up && seen[i].second >= seen[i - 1].second - tolerance;
            down = down && seen[i].second <= seen[i - 1].second + tolerance;
        }
        if (up || down) return k;
    }
    return std::nullopt;
}

PowerSimulation simulate_stated_power(const WarpCase& base, const Check& check, int coordinate,
                                      const std::string& figure, const RunOptions& options, int runs,
                                      double scale) {
    const unsigned threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
    ThreadPool pool(threads);
    PowerSimulation s;
    s.case_name = base.name();
    s.check_name = check.name();
    s.figure = figure;
    s.stated_eps = run_once(base, check, options, pool).figure(figure).value_or(std::nan(""));
    if (!std::isfinite(s.stated_eps)) throw std::runtime_error(check.name() + " states no " + figure + " for " + base.name());
    s.eps = scale * s.stated_eps;
    s.level = chi2::sidak_level(options.alpha, kPlannedTestsPerRun);
    const std::unique_ptr<WarpCase> tilted = tilted_case(base, coordinate, s.eps);
    RunOptions o = options;
    for (int i = 0; i < runs; ++i) {
        o.seed = options.seed + static_cast<uint64_t>(i);
        const CheckResult r = run_once(*tilted, check, o, pool);
        s.detected += r.verdict != Verdict::Pass || !(r.p_value.value_or(std::nan("")) >= s.level);
        ++s.runs;
    }
    return s;
}

}  // namespace warpcheck

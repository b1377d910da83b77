#include "validate/checks/shared/float_probe.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <type_traits>
#include <variant>

#include "chi2/count_bounds.h"
#include "sampling/bsdf.h"  // Frame
#include "sampling/float_bits.h"
#include "validate/checks/check.h"

namespace warpcheck {

std::array<float, 3> probe_steps(const chi2::Domain& domain, const WarpOutput& x) {
    const chi2::Domain::Slack slack = domain.slack();
    const double extent[3] = {slack.x, slack.y, slack.x};  // a direction's z has the x slack (unit scale)
    std::array<float, 3> step{};
    for (std::size_t k = 0; k < 3; ++k) {
        const float scale = std::max(std::abs(x[k]), static_cast<float>(extent[k] / chi2::kDomainTolerance));
        step[k] = scale - next_float_down(scale);
    }
    return step;
}

std::vector<WarpOutput> probe_points(const chi2::Domain& domain, const WarpOutput& x) {
    const int dims = domain.point_dimension();
    const std::array<float, 3> step = probe_steps(domain, x);
    std::vector<WarpOutput> out;
    int directions = 1;
    for (int k = 0; k < dims; ++k) directions *= 3;
    for (int d = 0; d < directions; ++d) {
        std::array<int, 3> sign{};
        for (int k = 0, rest = d; k < dims; ++k, rest /= 3) sign[static_cast<std::size_t>(k)] = rest % 3 - 1;
        if (sign == std::array<int, 3>{}) continue;
        for (int j = 1; j <= kProbeUlps; ++j) {
            WarpOutput y = x;
            for (std::size_t k = 0; k < 3; ++k) y[k] += static_cast<float>(sign[k] * j) * step[k];
            out.push_back(y);
        }
    }
    return out;
}

std::vector<WarpOutput> float_neighbours(const WarpOutput& w, double step) {
    const Frame frame = Frame::around({w[0], w[1], w[2]});
    std::vector<WarpOutput> out;
    out.reserve(kFloatNeighbours);
    for (std::size_t k = 0; k < kFloatNeighbours; ++k) {
        const double angle = 2.0 * std::numbers::pi * static_cast<double>(k) / kFloatNeighbours;
        const double dt = step * std::cos(angle), db = step * std::sin(angle);
        const double v[3] = {w[0] + dt * frame.t.x + db * frame.b.x, w[1] + dt * frame.t.y + db * frame.b.y,
                             w[2] + dt * frame.t.z + db * frame.b.z};
        const double len = std::hypot(v[0], v[1], v[2]);
        out.push_back({static_cast<float>(v[0] / len), static_cast<float>(v[1] / len), static_cast<float>(v[2] / len)});
    }
    return out;
}

double EdgeBand::share() const {
    if (near == 0 || probed == 0) return 0.0;
    const double root = std::sqrt(static_cast<double>(near) + 1.0) + 3.5;
    return root * root / static_cast<double>(probed);
}

std::vector<WarpOutput> axis_probes(const chi2::Domain& domain, const WarpOutput& x) {
    const std::array<float, 3> step = probe_steps(domain, x);
    const double length_slack = domain.slack().x;
    std::vector<WarpOutput> probes;
    for (int k = 0; k < domain.point_dimension(); ++k)
        for (const float sign : {1.0f, -1.0f}) {
            WarpOutput y = x;
            y[static_cast<std::size_t>(k)] += sign * kProbeUlps * step[static_cast<std::size_t>(k)];
            const chi2::DomainPoint q = to_domain_point(y);
            const bool inside = std::visit(
                [&](const auto& kind) {
                    if constexpr (std::is_same_v<std::decay_t<decltype(kind)>, chi2::SphericalCap>)
                        return std::abs(std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]) - 1.0) <= length_slack &&
                               q[2] >= kind.z_min;
                    else
                        return kind.contains(q, chi2::DomainSlack{});
                },
                domain.shape());
            if (inside) probes.push_back(y);
        }
    return probes;
}

std::vector<WarpInput> inward_ladder(const WarpInput& u, InputKind kind) {
    if (kind != InputKind::Uniform1D && kind != InputKind::Uniform2D) return {};
    const int dims = input_dimension(kind);
    std::vector<WarpInput> out;
    for (int e = 24; e >= 3; e -= 3) {
        WarpInput v = u;
        for (int k = 0; k < dims; ++k) {
            float& c = v.u[static_cast<std::size_t>(k)];
            c = c < 0.5f ? c + std::ldexp(1.0f, -e) : c > 0.5f ? c - std::ldexp(1.0f, -e) : c;
        }
        out.push_back(v);
    }
    return out;
}

bool excused_in_the_limit(const chi2::Domain& domain, const WarpOutput& x, std::span<const WarpOutput> ladder,
                          std::span<const unsigned char> passes) {
    if (ladder.size() < 2 || passes.size() != ladder.size()) return false;
    std::vector<double> d(ladder.size());
    for (std::size_t k = 0; k < ladder.size(); ++k) {
        double d2 = 0.0;
        for (std::size_t c = 0; c < 3; ++c) {
            const double diff = static_cast<double>(ladder[k][c]) - static_cast<double>(x[c]);
            d2 += diff * diff;
        }
        d[k] = std::sqrt(d2);
        if (!std::isfinite(d[k])) return false;
    }
    const std::array<float, 3> step = probe_steps(domain, x);
    const double reach = kProbeUlps * static_cast<double>(std::max({step[0], step[1], step[2]}));
    // Closing in step by step, and closed at the nearest step.
    for (std::size_t k = 0; k + 1 < d.size(); ++k)
        if (!(d[k] <= d[k + 1] + reach)) return false;
    if (!(d[0] <= reach || d[0] <= 0.5 * d[1])) return false;
    // The witness: the farthest step, where the support is resolved, passes.
    // Nearer steps may fail as x does (rounded across a support thinner
    // than a float step there), and a pocket of the support that they find
    // is left to the random samples, which get no such excuse.
    return passes.back() != 0;
}

uint64_t rounded_across_edge_bound(uint64_t random_samples, const EdgeBand& band) {
    const double rate = std::max(kRoundedAcrossEdgeRate, band.share());
    return chi2::poisson_count_bound(static_cast<double>(random_samples) * rate, kConsistencyBoundTail);
}

}  // namespace warpcheck

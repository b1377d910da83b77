// A renderer that compiles as C++17 registers its warps in its own files
// through validate/api/register17.h alone; the program links warpcheck::main.
#include <cmath>

#include <validate/api/register17.h>

static_assert(__cplusplus == 201703L, "this file proves that registration compiles as C++17");

namespace {

// The logistic distribution on the whole real line, mean mu, scale s.
struct Logistic {
    float mu, s;
    float sample(float u) const {
        // u = 0 is taken as half the smallest input step, 2^-65: x stays finite.
        const double p = u > 0 ? double{u} : 0x1p-65;
        return static_cast<float>(mu + s * std::log(p / (1 - p)));
    }
    double pdf(float x) const {
        const double e = std::exp(-std::abs(x - mu) / s);  // symmetric, no overflow
        return e / (s * (1 + e) * (1 + e));
    }
    float invert(float x) const { return std::fmin(static_cast<float>(1 / (1 + std::exp(-(x - mu) / s))), 0x1.fffffep-1f); }
};

}  // namespace

void warpcheck_register(warpcheck::Registry& registry) {
    namespace w17 = warpcheck::cxx17;
    const Logistic warp{-3.0f, 0.25f};
    w17::CaseInfo info;
    info.family = "logistic_cxx17";
    info.params = {{"mu", -3}, {"s", 0.25}};
    info.description = "logistic distribution on the real line, registered from C++17";
    info.input = w17::Input::Uniform1D;
    info.domain = w17::Domain::real_line();
    w17::View x;  // truncated where 1e-4 of the mass lies beyond each end
    x.lo = -3 - 0.25 * std::log(1e4 - 1);
    x.hi = -3 + 0.25 * std::log(1e4 - 1);
    x.lower_tail_mass = x.tail_mass = 1e-4;
    x.label = "x";
    info.views = {x};
    w17::add_case(
        registry, info, [warp](const w17::WarpInput& u) { return w17::Point{warp.sample(u.u[0]), 0, 0}; },
        [warp](const w17::Point& p) { return warp.pdf(p[0]); },
        [warp](const w17::Point& p) { return w17::WarpInput{{warp.invert(p[0]), 0}, 0}; });
}

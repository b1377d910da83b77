// The same warp in double precision, each output rounded once to float: the
// other half of a float-vs-double pair (a renderer built with Float = double,
// or a reference implementation). Shirley and Chiu's concentric map lifted to
// the hemisphere, as sampling/hemisphere.h's CosineHemisphere computes it.
#include <cmath>
#include <cstddef>
#include <numbers>

void warp_double(const float* u, float* x, std::size_t n) {
    constexpr double kPi = std::numbers::pi;
    for (std::size_t i = 0; i < n; ++i) {
        const double a = 2.0 * u[2 * i] - 1.0, b = 2.0 * u[2 * i + 1] - 1.0;
        double dx = 0.0, dy = 0.0;
        if (a != 0.0 || b != 0.0) {
            const bool wedge = std::abs(a) > std::abs(b);
            const double r = wedge ? a : b;
            const double phi = wedge ? kPi / 4 * (b / a) : kPi / 2 - kPi / 4 * (a / b);
            dx = r * std::cos(phi), dy = r * std::sin(phi);
        }
        x[3 * i] = static_cast<float>(dx);
        x[3 * i + 1] = static_cast<float>(dy);
        x[3 * i + 2] = static_cast<float>(std::sqrt(std::fmax(0.0, 1.0 - dx * dx - dy * dy)));
    }
}

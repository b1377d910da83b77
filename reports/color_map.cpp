#include "reports/color_map.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

namespace warpcheck {
namespace {

struct Rgb {
    double r, g, b;
};

constexpr std::array<Rgb, 6> kSequential{{
    {0x44, 0x01, 0x54},
    {0x41, 0x44, 0x87},
    {0x2a, 0x78, 0x8e},
    {0x22, 0xa8, 0x84},
    {0x7a, 0xd1, 0x51},
    {0xfd, 0xe7, 0x25},
}};

constexpr std::array<Rgb, 7> kDiverging{{
    {0x21, 0x66, 0xac},
    {0x67, 0xa9, 0xcf},
    {0xd1, 0xe5, 0xf0},
    {0xf7, 0xf7, 0xf7},
    {0xfd, 0xdb, 0xc7},
    {0xef, 0x8a, 0x62},
    {0xb2, 0x18, 0x2b},
}};

template <std::size_t N>
Rgba interpolate(const std::array<Rgb, N>& anchors, double t) {
    t = std::clamp(std::isnan(t) ? 0.0 : t, 0.0, 1.0) * static_cast<double>(N - 1);
    const std::size_t i = std::min(static_cast<std::size_t>(t), N - 2);
    const double f = t - static_cast<double>(i);
    const auto mix = [&](double a, double b) { return static_cast<std::uint8_t>(std::lround(a + (b - a) * f)); };
    const Rgb& a = anchors[i];
    const Rgb& b = anchors[i + 1];
    return {mix(a.r, b.r), mix(a.g, b.g), mix(a.b, b.b), 255};
}

}  // namespace

Rgba color_at(ColorMap map, double t) {
    return map == ColorMap::Sequential ? interpolate(kSequential, t) : interpolate(kDiverging, t);
}

std::string hex(Rgba color) { return fmt::format("#{:02x}{:02x}{:02x}", color.r, color.g, color.b); }

std::string series_color(std::size_t i) {
    static constexpr std::array<const char*, 8> colors{
        "#1f6fd1",  // blue
        "#e0641a",  // orange
        "#2e9e5b",  // green
        "#c23b8e",  // magenta
        "#7a5af0",  // violet
        "#0f9bb0",  // teal
        "#9a7b12",  // ochre
        "#555e6b",  // slate
    };
    return colors[i % colors.size()];
}

}  // namespace warpcheck

// Colour maps for heatmaps and the colours of plot series.
//   sequential: dark violet -> blue -> green -> yellow, perceptually ordered
//               (the anchor colours of the viridis map), readable in greyscale;
//   diverging:  blue -> near-white -> red, for values about 0 (residuals).
#pragma once

#include <cstddef>
#include <string>

#include "reports/png.h"

namespace warpcheck {

enum class ColorMap { Sequential, Diverging };

/// The colour at t in [0, 1] (clamped) of a map.
Rgba color_at(ColorMap map, double t);

/// "#rrggbb".
std::string hex(Rgba color);

/// The colour of the i-th series of a plot: distinct hues that stay apart for
/// the colour-blind and in print.
std::string series_color(std::size_t i);

}  // namespace warpcheck

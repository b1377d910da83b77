// A minimal PNG encoder for heatmaps: 8-bit palette images, stored (not
// compressed) deflate blocks. A heatmap cell is one pixel and the browser scales
// the image up without smoothing, so a 64 x 128 heatmap costs about 8 KB
// (11 KB in base64) instead of the ~600 KB that one SVG <rect> per cell would.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace warpcheck {

struct Rgba {
    std::uint8_t r = 0, g = 0, b = 0, a = 255;
};

/// A PNG file of a width x height image of palette indices, given row by row
/// from the top. Palette entries with alpha < 255 are (partly) transparent.
std::string encode_palette_png(int width, int height, const std::vector<std::uint8_t>& indices,
                               const std::array<Rgba, 256>& palette);

/// Standard base64 (RFC 4648) with padding, for data: URLs.
std::string base64(std::string_view bytes);

}  // namespace warpcheck

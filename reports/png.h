// A minimal PNG encoder for heatmaps: 8-bit palette images compressed by zlib.
// A heatmap cell is one pixel and the browser scales the image up without
// smoothing, so a 64 x 128 heatmap costs a few KB instead of the ~600 KB that
// one SVG <rect> per cell would. Also zlib and base64 for the HTML report's
// packed evidence.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace warpcheck {

struct Rgba {
    std::uint8_t r = 0, g = 0, b = 0, a = 255;
};

/// A PNG file of a width x height image of palette indices, given row by row
/// from the top. The palette has 1 to 256 entries and every index must be
/// below its size; entries with alpha < 255 are (partly) transparent, and
/// putting them first keeps the file small (tRNS ends at the last of them).
std::string encode_palette_png(int width, int height, const std::vector<std::uint8_t>& indices,
                               const std::vector<Rgba>& palette);

/// A zlib stream (RFC 1950) of `bytes` at the best compression: what PNG's
/// IDAT holds and what a browser's DecompressionStream("deflate") reads.
std::string zlib_compress(std::string_view bytes);

/// Standard base64 (RFC 4648) with padding, for data: URLs.
std::string base64(std::string_view bytes);

}  // namespace warpcheck

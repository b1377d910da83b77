#include "reports/png.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include <zlib.h>

namespace warpcheck {
namespace {

std::uint32_t crc32_of(std::string_view bytes) {
    return static_cast<std::uint32_t>(::crc32(0L, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(bytes.size())));
}

void put_u32(std::string& out, std::uint32_t v) {
    out += static_cast<char>(v >> 24);
    out += static_cast<char>(v >> 16);
    out += static_cast<char>(v >> 8);
    out += static_cast<char>(v);
}

void put_chunk(std::string& out, std::string_view type, std::string_view data) {
    put_u32(out, static_cast<std::uint32_t>(data.size()));
    std::string typed(type);
    typed += data;
    out += typed;
    put_u32(out, crc32_of(typed));
}

}  // namespace

std::string encode_palette_png(int width, int height, const std::vector<std::uint8_t>& indices,
                               const std::vector<Rgba>& palette) {
    if (width <= 0 || height <= 0 || indices.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
        throw std::invalid_argument("encode_palette_png: size does not match the pixels");
    if (palette.empty() || palette.size() > 256 ||
        std::any_of(indices.begin(), indices.end(), [&](std::uint8_t i) { return i >= palette.size(); }))
        throw std::invalid_argument("encode_palette_png: the palette has 1 to 256 entries and covers every index");

    std::string png = "\x89PNG\r\n\x1a\n";
    std::string header;
    put_u32(header, static_cast<std::uint32_t>(width));
    put_u32(header, static_cast<std::uint32_t>(height));
    header += '\x08';  // bit depth
    header += '\x03';  // colour type: palette
    header += std::string(3, '\0');  // deflate, adaptive filtering, no interlace
    put_chunk(png, "IHDR", header);

    std::string plte, trns;
    for (const Rgba& c : palette) {
        plte += static_cast<char>(c.r);
        plte += static_cast<char>(c.g);
        plte += static_cast<char>(c.b);
        trns += static_cast<char>(c.a);
    }
    put_chunk(png, "PLTE", plte);
    while (!trns.empty() && static_cast<std::uint8_t>(trns.back()) == 255) trns.pop_back();  // absent entries are opaque
    if (!trns.empty()) put_chunk(png, "tRNS", trns);

    std::string raw;
    raw.reserve(indices.size() + static_cast<std::size_t>(height));
    for (int y = 0; y < height; ++y) {
        raw += '\0';  // filter: none
        const auto row = indices.begin() + static_cast<std::ptrdiff_t>(y) * width;
        raw.append(row, row + width);
    }
    put_chunk(png, "IDAT", zlib_compress(raw));
    put_chunk(png, "IEND", {});
    return png;
}

std::string zlib_compress(std::string_view bytes) {
    uLongf size = compressBound(static_cast<uLong>(bytes.size()));
    std::string out(size, '\0');
    const int status = compress2(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(bytes.data()),
                                 static_cast<uLong>(bytes.size()), Z_BEST_COMPRESSION);
    if (status != Z_OK) throw std::runtime_error("zlib_compress: zlib failed with status " + std::to_string(status));
    out.resize(size);
    return out;
}

std::string base64(std::string_view bytes) {
    static constexpr char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const std::uint32_t v = static_cast<std::uint32_t>(static_cast<std::uint8_t>(bytes[i])) << 16 |
                                static_cast<std::uint32_t>(static_cast<std::uint8_t>(bytes[i + 1])) << 8 |
                                static_cast<std::uint8_t>(bytes[i + 2]);
        out += digits[v >> 18 & 63];
        out += digits[v >> 12 & 63];
        out += digits[v >> 6 & 63];
        out += digits[v & 63];
    }
    if (i < bytes.size()) {
        std::uint32_t v = static_cast<std::uint32_t>(static_cast<std::uint8_t>(bytes[i])) << 16;
        if (i + 1 < bytes.size()) v |= static_cast<std::uint32_t>(static_cast<std::uint8_t>(bytes[i + 1])) << 8;
        out += digits[v >> 18 & 63];
        out += digits[v >> 12 & 63];
        out += i + 1 < bytes.size() ? digits[v >> 6 & 63] : '=';
        out += '=';
    }
    return out;
}

}  // namespace warpcheck

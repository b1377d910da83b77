#include "validate/samples/sample_file.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include <fmt/format.h>

#include "reports/atomic_file.h"

namespace warpcheck {

std::string_view element_name(ElementType type) {
    switch (type) {
        case ElementType::Float32: return "float32";
        case ElementType::Float64: return "float64";
        case ElementType::UInt32: return "uint32";
        case ElementType::UInt64: return "uint64";
    }
    return "?";
}

std::string NumericArray::describe() const {
    return one_dimensional ? fmt::format("{} array of shape ({},)", element_name(type), rows)
                           : fmt::format("{} array of shape ({}, {})", element_name(type), rows, cols);
}

namespace {

std::string read_whole_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw SampleFileError(fmt::format("cannot read '{}': {}", path, std::strerror(errno)));
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw SampleFileError(fmt::format("cannot read '{}': read error", path));
    return bytes;
}

/// The value of `key` in the header's Python dict literal, up to the next
/// top-level comma or the closing brace (a tuple stays whole).
std::string header_value(std::string_view header, std::string_view key, const std::string& name) {
    const std::string quoted = fmt::format("'{}'", key);
    std::size_t at = header.find(quoted);
    if (at == std::string_view::npos) throw SampleFileError(fmt::format("'{}': .npy header has no {}", name, quoted));
    at = header.find(':', at + quoted.size());
    if (at == std::string_view::npos) throw SampleFileError(fmt::format("'{}': .npy header is malformed", name));
    std::size_t end = at + 1;
    int depth = 0;
    for (; end < header.size(); ++end) {
        const char c = header[end];
        if (c == '(') ++depth;
        else if (c == ')') --depth;
        else if ((c == ',' || c == '}') && depth == 0) break;
    }
    std::string value(header.substr(at + 1, end - at - 1));
    value.erase(0, value.find_first_not_of(" \t"));
    value.erase(value.find_last_not_of(" \t") + 1);
    return value;
}

struct Descr {
    ElementType type;
    bool big_endian;
    std::size_t size;
};

Descr parse_descr(std::string value, const std::string& name) {
    if (value.size() >= 2 && (value.front() == '\'' || value.front() == '"')) value = value.substr(1, value.size() - 2);
    const std::string unsupported = fmt::format(
        "'{}': element type '{}' is not supported: give float32 or float64 samples (uint32 or uint64 raw-bit inputs)",
        name, value);
    if (value.size() != 3) throw SampleFileError(unsupported);
    const char order = value[0];
    const std::string kind = value.substr(1);
    Descr d{};
    d.big_endian = order == '>';
    if (order != '<' && order != '>' && order != '=' && order != '|') throw SampleFileError(unsupported);
    if (kind == "f4") d = {ElementType::Float32, d.big_endian, 4};
    else if (kind == "f8") d = {ElementType::Float64, d.big_endian, 8};
    else if (kind == "u4") d = {ElementType::UInt32, d.big_endian, 4};
    else if (kind == "u8") d = {ElementType::UInt64, d.big_endian, 8};
    else throw SampleFileError(unsupported);
    return d;
}

std::vector<std::size_t> parse_shape(const std::string& value, const std::string& name) {
    if (value.size() < 2 || value.front() != '(' || value.back() != ')')
        throw SampleFileError(fmt::format("'{}': .npy shape '{}' is malformed", name, value));
    std::vector<std::size_t> shape;
    std::stringstream in(value.substr(1, value.size() - 2));
    std::string part;
    while (std::getline(in, part, ',')) {
        part.erase(0, part.find_first_not_of(" \t"));
        part.erase(part.find_last_not_of(" \t") + 1);
        if (part.empty()) continue;
        if (part.find_first_not_of("0123456789") != std::string::npos || part.size() > 15)
            throw SampleFileError(fmt::format("'{}': .npy shape '{}' is malformed", name, value));
        shape.push_back(std::stoull(part));
    }
    return shape;
}

uint64_t load_word(const char* p, std::size_t size, bool big_endian) {
    unsigned char b[8] = {};
    std::memcpy(b, p, size);
    if (big_endian) std::reverse(b, b + size);
    uint64_t w = 0;
    for (std::size_t k = 0; k < size; ++k) w |= uint64_t{b[k]} << (8 * k);
    return w;
}

void store_element(NumericArray& a, std::size_t index, uint64_t word) {
    switch (a.type) {
        case ElementType::Float32: a.reals[index] = std::bit_cast<float>(static_cast<uint32_t>(word)); break;
        case ElementType::Float64: a.reals[index] = std::bit_cast<double>(word); break;
        case ElementType::UInt32:
        case ElementType::UInt64: a.integers[index] = word; break;
    }
}

void allocate(NumericArray& a) {
    if (a.is_real()) a.reals.assign(a.rows * a.cols, 0.0);
    else a.integers.assign(a.rows * a.cols, 0);
}

}  // namespace

NumericArray parse_npy(std::string_view bytes, const std::string& name) {
    constexpr std::string_view kMagic("\x93NUMPY", 6);
    if (bytes.size() < 10 || bytes.substr(0, 6) != kMagic)
        throw SampleFileError(fmt::format("'{}' is not a NumPy .npy file (no \\x93NUMPY magic)", name));
    const auto major = static_cast<unsigned char>(bytes[6]);
    const std::size_t length_size = major == 1 ? 2 : 4;
    if (major < 1 || major > 3) throw SampleFileError(fmt::format("'{}': .npy version {} is not supported", name, major));
    if (bytes.size() < 8 + length_size) throw SampleFileError(fmt::format("'{}': .npy header is cut short", name));
    const std::size_t header_length = load_word(bytes.data() + 8, length_size, false);
    const std::size_t data_start = 8 + length_size + header_length;
    if (bytes.size() < data_start) throw SampleFileError(fmt::format("'{}': .npy header is cut short", name));
    const std::string_view header = bytes.substr(8 + length_size, header_length);
    const Descr descr = parse_descr(header_value(header, "descr", name), name);
    const bool fortran = header_value(header, "fortran_order", name) == "True";
    const std::vector<std::size_t> shape = parse_shape(header_value(header, "shape", name), name);
    if (shape.empty() || shape.size() > 2)
        throw SampleFileError(fmt::format("'{}': an array of {} dimensions; samples are one row each: shape (n,) or (n, d)",
                                          name, shape.size()));
    NumericArray a;
    a.type = descr.type;
    a.rows = shape[0];
    a.cols = shape.size() == 2 ? shape[1] : 1;
    a.one_dimensional = shape.size() == 1;
    if (a.cols > 0 && a.rows > (bytes.size() - data_start) / descr.size / a.cols)
        throw SampleFileError(fmt::format("'{}' is cut short: its header says {} but it holds {} bytes of data", name,
                                          a.describe(), bytes.size() - data_start));
    allocate(a);
    const char* data = bytes.data() + data_start;
    for (std::size_t r = 0; r < a.rows; ++r)
        for (std::size_t c = 0; c < a.cols; ++c) {
            const std::size_t stored = fortran ? c * a.rows + r : r * a.cols + c;
            store_element(a, r * a.cols + c, load_word(data + stored * descr.size, descr.size, descr.big_endian));
        }
    return a;
}

NumericArray read_npy(const std::string& path) { return parse_npy(read_whole_file(path), path); }

RawLayout parse_raw_layout(std::string_view text) {
    RawLayout layout;
    const std::size_t comma = text.find(',');
    const std::string_view count = text.substr(0, comma);
    const std::string_view order = comma == std::string_view::npos ? "interleaved" : text.substr(comma + 1);
    if (count.size() != 1 || count[0] < '1' || count[0] > '3' || (order != "interleaved" && order != "planar"))
        throw SampleFileError(fmt::format("'{}' is not a raw layout: give the floats per sample, 1 to 3, and optionally "
                                          "',planar' (all x, then all y, ...) or ',interleaved' (x y z x y z ..., the default)",
                                          text));
    layout.columns = static_cast<std::size_t>(count[0] - '0');
    layout.planar = order == "planar";
    return layout;
}

NumericArray read_raw_float32(const std::string& path, RawLayout layout) {
    const std::string bytes = read_whole_file(path);
    const std::size_t sample_bytes = 4 * layout.columns;
    if (bytes.size() % sample_bytes != 0)
        throw SampleFileError(fmt::format("'{}' holds {} bytes, not a whole number of samples of {} float32", path,
                                          bytes.size(), layout.columns));
    NumericArray a;
    a.rows = bytes.size() / sample_bytes;
    a.cols = layout.columns;
    a.one_dimensional = layout.columns == 1;
    allocate(a);
    for (std::size_t r = 0; r < a.rows; ++r)
        for (std::size_t c = 0; c < a.cols; ++c) {
            const std::size_t stored = layout.planar ? c * a.rows + r : r * a.cols + c;
            store_element(a, r * a.cols + c, load_word(bytes.data() + 4 * stored, 4, false));
        }
    return a;
}

NumericArray read_sample_file(const std::string& path, const RawLayout* layout) {
    const bool npy = path.size() >= 4 && path.compare(path.size() - 4, 4, ".npy") == 0;
    if (npy) return read_npy(path);
    if (!layout)
        throw SampleFileError(fmt::format("'{}' is not a .npy file: for raw float32 samples give their layout "
                                          "(--raw-layout 3 or 3,planar)",
                                          path));
    return read_raw_float32(path, *layout);
}

std::string npy_bytes(const NumericArray& a) {
    const char* descr = a.type == ElementType::Float32   ? "<f4"
                        : a.type == ElementType::Float64 ? "<f8"
                        : a.type == ElementType::UInt32  ? "<u4"
                                                         : "<u8";
    const std::size_t size = a.type == ElementType::Float32 || a.type == ElementType::UInt32 ? 4 : 8;
    std::string header = a.one_dimensional
                             ? fmt::format("{{'descr': '{}', 'fortran_order': False, 'shape': ({},), }}", descr, a.rows)
                             : fmt::format("{{'descr': '{}', 'fortran_order': False, 'shape': ({}, {}), }}", descr,
                                           a.rows, a.cols);
    // Padded with spaces to a multiple of 64 bytes with the 10-byte preamble, ending in '\n'.
    const std::size_t total = (10 + header.size() + 1 + 63) / 64 * 64;
    header.append(total - 10 - header.size() - 1, ' ');
    header.push_back('\n');
    std::string out("\x93NUMPY\x01\x00", 8);
    out.push_back(static_cast<char>(header.size() & 0xff));
    out.push_back(static_cast<char>(header.size() >> 8));
    out += header;
    out.reserve(out.size() + a.rows * a.cols * size);
    for (std::size_t i = 0; i < a.rows * a.cols; ++i) {
        uint64_t w = 0;
        switch (a.type) {
            case ElementType::Float32: w = std::bit_cast<uint32_t>(static_cast<float>(a.reals[i])); break;
            case ElementType::Float64: w = std::bit_cast<uint64_t>(a.reals[i]); break;
            case ElementType::UInt32:
            case ElementType::UInt64: w = a.integers[i]; break;
        }
        for (std::size_t k = 0; k < size; ++k) out.push_back(static_cast<char>((w >> (8 * k)) & 0xff));
    }
    return out;
}

void write_npy(const std::string& path, const NumericArray& array) { write_file_atomically(path, npy_bytes(array)); }

}  // namespace warpcheck

// Arrays of samples and inputs as other programs write them: NumPy's .npy
// format (version 1-3, little- or big-endian float32, float64, uint32, uint64,
// one or two dimensions, C or Fortran order), or raw little-endian float32
// with a stated layout (so many floats per sample, interleaved as x y z x y z
// or planar as all x, then all y, then all z: the two ways a GPU kernel
// writes a buffer). What a renderer's other build, a GPU kernel or a Python
// script hands to `validate` (validate/samples/README.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace warpcheck {

/// A file or array of samples that cannot be read or has the wrong form:
/// the message names the file and what was expected.
struct SampleFileError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

enum class ElementType { Float32, Float64, UInt32, UInt64 };

/// "float32", "float64", "uint32", "uint64".
std::string_view element_name(ElementType type);

/// A two-dimensional array in C order (row by row), its elements as stored,
/// kept as 64-bit words: a float32 as its value widened to double, a float64 as
/// it is, an integer as it is. A one-dimensional array has one column and
/// `one_dimensional` set (shape (n,) rather than (n, 1)).
struct NumericArray {
    ElementType type = ElementType::Float32;
    std::size_t rows = 0, cols = 1;
    bool one_dimensional = false;
    std::vector<double> reals;      ///< Float32, Float64: rows * cols values
    std::vector<uint64_t> integers; ///< UInt32, UInt64: rows * cols values

    bool is_real() const { return type == ElementType::Float32 || type == ElementType::Float64; }
    double real(std::size_t row, std::size_t col) const { return reals[row * cols + col]; }
    uint64_t integer(std::size_t row, std::size_t col) const { return integers[row * cols + col]; }
    /// "float32 array of shape (1000000, 3)".
    std::string describe() const;
};

/// Reads a .npy file. Throws SampleFileError naming the file and the problem
/// (not a .npy file, an element type other than the four, more than two
/// dimensions, a file shorter than its header says).
NumericArray read_npy(const std::string& path);
/// Parses the bytes of a .npy file; `name` is used in messages.
NumericArray parse_npy(std::string_view bytes, const std::string& name);

/// The layout of a raw float32 file: `columns` floats per sample, interleaved
/// (x y z x y z ...) or planar (all x, then all y, ...).
struct RawLayout {
    std::size_t columns = 1;
    bool planar = false;
};
/// Reads "3", "3,interleaved" or "3,planar" (1 to 3 columns); throws
/// SampleFileError saying what is accepted.
RawLayout parse_raw_layout(std::string_view text);
/// Reads a raw little-endian float32 file of that layout: its size must be a
/// whole number of samples.
NumericArray read_raw_float32(const std::string& path, RawLayout layout);

/// A .npy file (by its name ending in .npy) or, with a layout, raw float32.
/// Without a layout a file that is not .npy is refused with the way to give one.
NumericArray read_sample_file(const std::string& path, const RawLayout* layout = nullptr);

/// The .npy bytes of an array (version 1.0, little-endian, C order).
std::string npy_bytes(const NumericArray& array);
/// Writes the array to a .npy file (atomically: complete or not at all).
void write_npy(const std::string& path, const NumericArray& array);

}  // namespace warpcheck

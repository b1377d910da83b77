#include "validate/samples/sample_arrays.h"

#include <cmath>

#include <fmt/format.h>

namespace warpcheck {

std::string input_kind_name(InputKind kind) {
    switch (kind) {
        case InputKind::Uniform1D: return "uniform 1D";
        case InputKind::Uniform2D: return "uniform 2D";
        case InputKind::Uniform3D: return "uniform 3D";
        case InputKind::Bits32: return "raw 32-bit";
        case InputKind::Bits64: return "raw 64-bit";
    }
    return "?";
}

namespace {

/// Whether the array has `cols` columns in one of the accepted shapes: (n, cols),
/// or (n,) for one column.
bool has_columns(const NumericArray& a, std::size_t cols) { return a.cols == cols; }

std::string expected_shape(std::size_t cols) {
    return cols == 1 ? "(n,) or (n, 1)" : fmt::format("(n, {})", cols);
}

}  // namespace

std::vector<WarpInput> inputs_of(const NumericArray& array, InputKind kind, const std::string& what) {
    std::vector<WarpInput> in(array.rows);
    if (takes_bits(kind)) {
        const ElementType want = kind == InputKind::Bits32 ? ElementType::UInt32 : ElementType::UInt64;
        if (array.type != want || !has_columns(array, 1))
            throw SampleFileError(fmt::format("{}: {} inputs are a {} array of shape (n,), not a {}", what,
                                              input_kind_name(kind), element_name(want), array.describe()));
        for (std::size_t i = 0; i < array.rows; ++i) in[i].bits = array.integer(i, 0);
        return in;
    }
    const auto dims = static_cast<std::size_t>(input_dimension(kind));
    if (array.type != ElementType::Float32 || !has_columns(array, dims))
        throw SampleFileError(fmt::format("{}: {} inputs are a float32 array of shape {}, not a {}", what,
                                          input_kind_name(kind), expected_shape(dims), array.describe()));
    for (std::size_t i = 0; i < array.rows; ++i)
        for (std::size_t c = 0; c < dims; ++c) {
            const double u = array.real(i, c);
            // An input outside [0, 1) (or NaN) is not one warpcheck draws, and not one a warp is made for.
            if (!(u >= 0.0 && u < 1.0))
                throw SampleFileError(fmt::format("{}: input {} coordinate {} is {}, outside [0, 1)", what, i, c, u));
            in[i].u[c] = static_cast<float>(u);
        }
    return in;
}

NumericArray array_of(std::span<const WarpInput> inputs, InputKind kind) {
    NumericArray a;
    a.rows = inputs.size();
    if (takes_bits(kind)) {
        a.type = kind == InputKind::Bits32 ? ElementType::UInt32 : ElementType::UInt64;
        a.one_dimensional = true;
        for (const WarpInput& in : inputs) a.integers.push_back(in.bits);
        return a;
    }
    a.cols = static_cast<std::size_t>(input_dimension(kind));
    a.one_dimensional = a.cols == 1;
    a.reals.reserve(a.rows * a.cols);
    for (const WarpInput& in : inputs)
        for (std::size_t c = 0; c < a.cols; ++c) a.reals.push_back(in.u[c]);
    return a;
}

std::vector<WarpOutput> outputs_of(const NumericArray& array, int dimension, const std::string& what,
                                   std::vector<double>* values) {
    const std::size_t dims = static_cast<std::size_t>(dimension), cols = dims + (values ? 1 : 0);
    if (!array.is_real() || !has_columns(array, cols))
        throw SampleFileError(fmt::format("{}: {} samples{} are a float32 or float64 array of shape {}, not a {}", what,
                                          dimension == 1 ? "1D" : fmt::format("{}D", dimension),
                                          values ? " with their returned value (the last column)" : "",
                                          expected_shape(cols), array.describe()));
    std::vector<WarpOutput> out(array.rows, WarpOutput{});
    if (values) values->resize(array.rows);
    for (std::size_t i = 0; i < array.rows; ++i) {
        for (std::size_t c = 0; c < dims; ++c) out[i][c] = static_cast<float>(array.real(i, c));
        if (values) (*values)[i] = array.real(i, dims);
    }
    return out;
}

NumericArray array_of(std::span<const WarpOutput> outputs, int dimension) {
    NumericArray a;
    a.rows = outputs.size();
    a.cols = static_cast<std::size_t>(dimension);
    a.one_dimensional = dimension == 1;
    a.reals.reserve(a.rows * a.cols);
    for (const WarpOutput& o : outputs)
        for (std::size_t c = 0; c < a.cols; ++c) a.reals.push_back(o[c]);
    return a;
}

}  // namespace warpcheck

// Arrays as a warp's inputs and outputs: what shape and element type each
// input kind and each domain takes, checked with a message that says what was
// expected and what came.
//
//   inputs:  uniform 1D (n,) or (n, 1); uniform 2D (n, 2); uniform 3D (n, 3),
//            float32 (float64 is refused: an input is a float, and a double
//            input rounded would not be the input that was warped); raw bits
//            uint32 or uint64 (n,). No NaN, every uniform in [0, 1).
//   outputs: (n,) or (n, 1) on a line, (n, 2) in the plane, (n, 3) on the
//            sphere, float32 or float64 (rounded to float32, as warps return
//            floats); with `with_value`, one column more: the value sample
//            returned with the point (its pdf or weight). NaN is kept: the
//            checks fail it.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "validate/api/warp_case.h"
#include "validate/samples/sample_file.h"

namespace warpcheck {

/// "uniform 2D", "raw 32-bit", ...
std::string input_kind_name(InputKind kind);

/// The inputs of an array, checked against the kind; `what` names the array in messages.
std::vector<WarpInput> inputs_of(const NumericArray& array, InputKind kind, const std::string& what);
/// The array of inputs (float32 (n, d), or uint32/uint64 (n,)).
NumericArray array_of(std::span<const WarpInput> inputs, InputKind kind);

/// Outputs of `dimension` coordinates (and their values, when `values` is not null).
std::vector<WarpOutput> outputs_of(const NumericArray& array, int dimension, const std::string& what,
                                   std::vector<double>* values = nullptr);
/// The array of outputs, float32 (n, dimension) (or (n,) for one coordinate).
NumericArray array_of(std::span<const WarpOutput> outputs, int dimension);

}  // namespace warpcheck

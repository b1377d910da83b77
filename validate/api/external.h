// Validating your own warps: link warpcheck::main and define
//
//     void warpcheck_register(warpcheck::Registry& registry) { registry.add_case(...); }
//
// and your program is a `validate` for your warps, with the same options,
// checks and reports (the way linking gtest_main gives a test program its main).
// The built-in checks are registered for you; the built-in warps are not.
//
// A renderer's float sampler of raw random bits (u32 -> float, or u64 -> float
// over a stated subrange) gets the exhaustive check's fast path, as the
// built-in ones do, through make_u32_float_case / make_u64_float_case: its
// sampler is inlined into a vectorised block loop instead of being called
// through the batch interface, monotone or not.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "validate/api/case_grid.h"
#include "validate/api/exhaustive_sweep.h"
#include "validate/api/float_template_warp.h"
#include "validate/api/light_case.h"
#include "validate/api/positional_cases.h"
#include "validate/api/registry.h"
#include "validate/api/warp_case.h"

/// Defined by the program that links warpcheck::main: adds its warp cases to
/// the registry.
void warpcheck_register(warpcheck::Registry& registry);

namespace warpcheck {

/// What a float sampler claims about its order: a monotone sampler's step
/// down is a failure of the exhaustive check; otherwise steps down are counted
/// and the outputs recounted exactly (chi2/float_sweep.h: sorting, or windows
/// of radix-partitioned counts within 1 GiB).
enum class Monotone : bool { NotClaimed = false, Claimed = true };

/// Which inputs of a u64 -> float sampler the exhaustive check enumerates:
/// u = (i << shift) | low_bits for every i < 2^(64 - shift), with 32 <= shift
/// < 64 (at most 2^32 inputs). The default sweeps the high 32 bits with the
/// low 32 bits zero, which is every input of a sampler that reads only its
/// high bits.
struct U64Subrange {
    int shift = 32;
    uint64_t low_bits = 0;
};

namespace detail {

/// A case whose float sampler the exhaustive check sweeps over every u32
/// input: `fn` (and `borders`, when not empty) is the sampler in blocks.
inline std::unique_ptr<WarpCase> u32_sweep(std::unique_ptr<WarpCase> inner, FloatBlockFn fn, Monotone monotone,
                                           FloatBordersFn borders = {}) {
    auto swept = std::make_unique<SweepableWarpCase>(std::move(inner), std::move(fn), uint64_t{1} << 32,
                                                     "all 2^32 inputs", monotone == Monotone::Claimed,
                                                     std::move(borders));
    validate_case(*swept);
    return swept;
}

/// A case whose u64 float sampler the exhaustive check sweeps over
/// `subrange`: `fn` is the sampler on the subrange's i-th input, in blocks.
inline std::unique_ptr<WarpCase> u64_sweep(std::unique_ptr<WarpCase> inner, FloatBlockFn fn, U64Subrange subrange,
                                           Monotone monotone) {
    if (subrange.shift < 32 || subrange.shift > 63 || (subrange.low_bits >> subrange.shift) != 0)
        throw declaration_error("warp case " + inner->name(),
                                {"its U64Subrange needs 32 <= shift < 64 and low_bits < 2^shift, not shift " +
                                 std::to_string(subrange.shift) + " and low_bits " +
                                 std::to_string(subrange.low_bits)});
    const int bits = 64 - subrange.shift;
    std::string grid = "u = (i << " + std::to_string(subrange.shift) + ") | " + std::to_string(subrange.low_bits) +
                       " for every i < 2^" + std::to_string(bits);
    auto swept = std::make_unique<SweepableWarpCase>(std::move(inner), std::move(fn), uint64_t{1} << bits,
                                                     std::move(grid), monotone == Monotone::Claimed);
    validate_case(*swept);
    return swept;
}

/// Whether W's sample takes `Bits` and returns a float.
template <typename W, typename Bits>
constexpr bool samples_float_from = std::is_same_v<typename WarpTypesOf<W>::In, Bits> &&
                                    std::is_same_v<typename WarpTypesOf<W>::Result, float>;

}  // namespace detail

/// A case for a u32 -> float sampler on an interval domain [a, b): a warp
/// object (or Warp of callables) whose `sample(uint32_t) -> float` has a
/// `pdf(float)` and, optionally, `invert(float) -> uint32_t`, as for
/// make_warp_case. Every check that applies runs on it; the exhaustive one
/// sweeps all 2^32 inputs through a vectorised loop with `sample` inlined.
template <WarpObject W>
std::unique_ptr<WarpCase> make_u32_float_case(WarpCaseInfo info, Monotone monotone, W warp) {
    static_assert(detail::samples_float_from<W, uint32_t>, "make_u32_float_case: sample must be uint32_t -> float");
    auto call = [warp](uint32_t u) -> float { return warp.sample(u); };
    return detail::u32_sweep(make_warp_case(std::move(info), std::move(warp)), u32_block_fn(call), monotone,
                             u32_borders_fn(call));
}

/// A case for a u64 -> float sampler, as make_u32_float_case (sample(uint64_t)
/// -> float), whose exhaustive sweep enumerates `subrange`.
template <WarpObject W>
std::unique_ptr<WarpCase> make_u64_float_case(WarpCaseInfo info, U64Subrange subrange, Monotone monotone, W warp) {
    static_assert(detail::samples_float_from<W, uint64_t>, "make_u64_float_case: sample must be uint64_t -> float");
    auto call = [warp](uint64_t u) -> float { return warp.sample(u); };
    return detail::u64_sweep(make_warp_case(std::move(info), std::move(warp)),
                             u64_block_fn(call, subrange.shift, subrange.low_bits), subrange, monotone);
}

// Deprecated: 0.1's float-sampler cases from callables (validate/api/positional_cases.h).

template <typename Sample, typename Pdf>
[[deprecated("make_u32_float_case(info, monotone, sample, pdf) is deprecated (validate/api/CHANGELOG.md): use "
             "make_u32_float_case(info, monotone, warp_of(sample).with_pdf(pdf)), or a warp object")]]
std::unique_ptr<WarpCase> make_u32_float_case(WarpCaseInfo info, Monotone monotone, Sample sample, Pdf pdf) {
    return make_u32_float_case(std::move(info), monotone, warp_of(std::move(sample)).with_pdf(std::move(pdf)));
}

template <typename Sample, typename Pdf, typename Invert>
[[deprecated("make_u32_float_case(info, monotone, sample, pdf, invert) is deprecated (validate/api/CHANGELOG.md): "
             "use make_u32_float_case(info, monotone, warp_of(sample).with_pdf(pdf).with_invert(invert))")]]
std::unique_ptr<WarpCase> make_u32_float_case(WarpCaseInfo info, Monotone monotone, Sample sample, Pdf pdf,
                                              Invert invert) {
    return make_u32_float_case(std::move(info), monotone,
                               warp_of(std::move(sample)).with_pdf(std::move(pdf)).with_invert(std::move(invert)));
}

template <typename Sample, typename Pdf>
[[deprecated("make_u64_float_case(info, subrange, monotone, sample, pdf) is deprecated (validate/api/CHANGELOG.md): "
             "use make_u64_float_case(info, subrange, monotone, warp_of(sample).with_pdf(pdf))")]]
std::unique_ptr<WarpCase> make_u64_float_case(WarpCaseInfo info, U64Subrange subrange, Monotone monotone,
                                              Sample sample, Pdf pdf) {
    return make_u64_float_case(std::move(info), subrange, monotone,
                               warp_of(std::move(sample)).with_pdf(std::move(pdf)));
}

template <typename Sample, typename Pdf, typename Invert>
[[deprecated("make_u64_float_case(info, subrange, monotone, sample, pdf, invert) is deprecated "
             "(validate/api/CHANGELOG.md): use make_u64_float_case(info, subrange, monotone, "
             "warp_of(sample).with_pdf(pdf).with_invert(invert))")]]
std::unique_ptr<WarpCase> make_u64_float_case(WarpCaseInfo info, U64Subrange subrange, Monotone monotone,
                                              Sample sample, Pdf pdf, Invert invert) {
    return make_u64_float_case(std::move(info), subrange, monotone,
                               warp_of(std::move(sample)).with_pdf(std::move(pdf)).with_invert(std::move(invert)));
}

}  // namespace warpcheck

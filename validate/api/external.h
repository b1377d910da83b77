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

inline void require_interval(const WarpCaseInfo& info, const char* what) {
    if (!info.domain.is<chi2::Interval>())
        throw std::invalid_argument(std::string(what) + ": a float sampler's domain must be an interval [a, b)");
}

}  // namespace detail

/// A case for a u32 -> float sampler on the interval info.domain (info.input is
/// set to Bits32): `sample(uint32_t) -> float` and `pdf(float)`, plus
/// optionally `invert(float) -> uint32_t`, as for make_warp_case. Every check
/// that applies runs on it; the exhaustive one sweeps all 2^32 inputs through
/// a vectorised loop with `sample` inlined (pass a lambda or function object;
/// a plain function pointer works but is called per input).
template <typename Sample, typename Pdf, typename... Invert>
std::unique_ptr<WarpCase> make_u32_float_case(WarpCaseInfo info, Monotone monotone, Sample sample, Pdf pdf,
                                              Invert... invert) {
    static_assert(sizeof...(Invert) <= 1, "at most one inverse");
    detail::require_interval(info, "make_u32_float_case");
    info.input = InputKind::Bits32;
    auto call = [sample](uint32_t u) -> float { return sample(u); };
    auto inner = make_warp_case(std::move(info), call, std::move(pdf), std::move(invert)...);
    return std::make_unique<SweepableWarpCase>(std::move(inner), u32_block_fn(call), uint64_t{1} << 32,
                                               "all 2^32 inputs", monotone == Monotone::Claimed,
                                               u32_borders_fn(call));
}

/// A case for a u64 -> float sampler, as make_u32_float_case (info.input is set
/// to Bits64), whose exhaustive sweep enumerates `subrange`.
template <typename Sample, typename Pdf, typename... Invert>
std::unique_ptr<WarpCase> make_u64_float_case(WarpCaseInfo info, U64Subrange subrange, Monotone monotone,
                                              Sample sample, Pdf pdf, Invert... invert) {
    static_assert(sizeof...(Invert) <= 1, "at most one inverse");
    detail::require_interval(info, "make_u64_float_case");
    if (subrange.shift < 32 || subrange.shift > 63 || (subrange.low_bits >> subrange.shift) != 0)
        throw std::invalid_argument("make_u64_float_case: needs 32 <= shift < 64 and low_bits < 2^shift");
    info.input = InputKind::Bits64;
    auto call = [sample](uint64_t u) -> float { return sample(u); };
    auto inner = make_warp_case(std::move(info), call, std::move(pdf), std::move(invert)...);
    const int bits = 64 - subrange.shift;
    std::string grid = "u = (i << " + std::to_string(subrange.shift) + ") | " + std::to_string(subrange.low_bits) +
                       " for every i < 2^" + std::to_string(bits);
    return std::make_unique<SweepableWarpCase>(std::move(inner), u64_block_fn(call, subrange.shift, subrange.low_bits),
                                               uint64_t{1} << bits, std::move(grid), monotone == Monotone::Claimed);
}

}  // namespace warpcheck

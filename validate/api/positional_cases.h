// Deprecated: the positional forms of warpcheck 0.1, kept for one release so
// that a registration written against them still compiles, with a warning
// that names the form replacing each (validate/api/CHANGELOG.md). Each makes
// the same case as the named form it forwards to: warp_of(sample) with its
// parts given by name, so that eval and pdf (one type) can no longer take
// each other's place. Included by validate/api/external.h; removed in 0.3.
#pragma once

#include <concepts>
#include <cstdint>
#include <memory>
#include <utility>

#include "validate/api/exhaustive_sweep.h"
#include "validate/api/warp_case.h"

namespace warpcheck {
namespace detail {

/// A callable that 0.1's make_warp_case(info, sample) took: sample alone,
/// invocable with one of the inputs, and not a warp object.
template <typename S>
concept PositionalSample =
    !WarpObject<S> && (std::invocable<const S&, float> || std::invocable<const S&, Point2f> ||
                       std::invocable<const S&, uint32_t> || std::invocable<const S&, uint64_t>);

}  // namespace detail

template <typename Sample, typename Pdf, typename Invert>
[[deprecated("make_warp_case(info, sample, pdf, invert) is deprecated (validate/api/CHANGELOG.md): use "
             "make_warp_case(info, warp_of(sample).with_pdf(pdf).with_invert(invert)), or a warp object")]]
std::unique_ptr<WarpCase> make_warp_case(WarpCaseInfo info, Sample sample, Pdf pdf, Invert invert) {
    return make_warp_case(std::move(info),
                          warp_of(std::move(sample)).with_pdf(std::move(pdf)).with_invert(std::move(invert)));
}

template <typename Sample, typename Pdf>
[[deprecated("make_warp_case(info, sample, pdf) is deprecated (validate/api/CHANGELOG.md): use "
             "make_warp_case(info, warp_of(sample).with_pdf(pdf)), or a warp object")]]
std::unique_ptr<WarpCase> make_warp_case(WarpCaseInfo info, Sample sample, Pdf pdf) {
    return make_warp_case(std::move(info), warp_of(std::move(sample)).with_pdf(std::move(pdf)));
}

template <detail::PositionalSample Sample>
[[deprecated("make_warp_case(info, sample) with a callable is deprecated (validate/api/CHANGELOG.md): use "
             "make_warp_case(info, warp_of(sample)), or a warp object")]]
std::unique_ptr<WarpCase> make_warp_case(WarpCaseInfo info, Sample sample) {
    return make_warp_case(std::move(info), warp_of(std::move(sample)));
}

template <typename Sample, typename Eval, typename Pdf>
[[deprecated("make_weighted_case(info, sample, eval, pdf) is deprecated (validate/api/CHANGELOG.md): use "
             "make_warp_case(info, warp_of(sample).with_eval(eval).with_pdf(pdf)), or a warp object")]]
std::unique_ptr<WarpCase> make_weighted_case(WarpCaseInfo info, Sample sample, Eval eval, Pdf pdf) {
    return make_warp_case(std::move(info), warp_of(std::move(sample)).with_eval(std::move(eval)).with_pdf(std::move(pdf)));
}

}  // namespace warpcheck

// BatchPdfs from a density of one point, for the chi2 library's tests.
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <utility>

#include "chi2/chi2_test.h"

namespace warpcheck::chi2::test_pdfs {

/// The batch form of a pointwise density f: out[i] = f(x[i]).
inline BatchPdf pointwise(std::function<double(const DomainPoint&)> f) {
    return [f = std::move(f)](std::span<const DomainPoint> x, std::span<double> out) {
        for (std::size_t i = 0; i < x.size(); ++i) out[i] = f(x[i]);
    };
}

/// The density as a float warp's pdf sees it: each coordinate of the point
/// rounded to float before f is evaluated.
inline BatchPdf float_pointwise(std::function<double(const DomainPoint&)> f) {
    return [f = std::move(f)](std::span<const DomainPoint> x, std::span<double> out) {
        for (std::size_t i = 0; i < x.size(); ++i)
            out[i] = f({static_cast<float>(x[i][0]), static_cast<float>(x[i][1]), static_cast<float>(x[i][2])});
    };
}

}  // namespace warpcheck::chi2::test_pdfs

// What the known-bad BSDFs of bsdf_flawed.cpp are made of, for the tests that
// vary them (tests/support/bsdf_twins.h).
#pragma once

#include <memory>
#include <utility>

#include "validate/api/bsdf_case.h"

namespace warpcheck {

/// A BSDF case that samples wi as `sampler` does while f(), pdf() and each
/// sample's f and pdf are `bsdf`'s at that wi: every weight agrees with f()
/// and pdf(), and only where the samples go is wrong (a sampler fed another
/// roughness than its pdf). The lobes are `bsdf`'s.
template <BsdfObject Bsdf, BsdfObject Sampler>
std::unique_ptr<WarpCase> sampled_by(WarpCaseInfo info, Vector3f wo, Bsdf bsdf, Sampler sampler) {
    const auto sample = [bsdf, sampler](Vector3f w, float uc, Point2f u) {
        BsdfSample s = sampler.sample(w, uc, u);
        if (s.pdf > 0.0f) {
            s.f = bsdf.f(w, s.wi);
            s.pdf = bsdf.pdf(w, s.wi);
        }
        return s;
    };
    return make_bsdf_case(std::move(info), {.wo = wo, .lobes = bsdf.flags()},
                          bsdf_of(sample)
                              .with_f([bsdf](Vector3f a, Vector3f b) { return bsdf.f(a, b); })
                              .with_pdf([bsdf](Vector3f a, Vector3f b) { return bsdf.pdf(a, b); }));
}

}  // namespace warpcheck

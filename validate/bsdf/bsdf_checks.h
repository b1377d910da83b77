// The checks of BSDF and phase-function cases (validate/bsdf/bsdf_case.h).
// register_builtin_checks adds them; each takes BSDF cases only.
#pragma once

#include <memory>

#include "validate/check.h"

namespace warpcheck::bsdf {

/// "bsdf_chi2": the continuous lobes' wi over the sphere against pdf(wo, .)
/// (chi-square), and the pdf's integral against the share of draws that landed.
std::unique_ptr<Check> make_bsdf_chi2_check();
/// "bsdf_weight": every sample's weight f |cos theta_i| / pdf against f() and
/// pdf() at its wi; wi a unit vector on the side its flags say; no sample
/// where pdf or f is 0.
std::unique_ptr<Check> make_bsdf_weight_check();

}  // namespace warpcheck::bsdf

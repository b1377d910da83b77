// The checks of BSDF and phase-function cases (validate/api/bsdf_case.h).
// register_builtin_checks adds them; each takes BSDF cases only.
#pragma once

#include <memory>

#include "validate/checks/check.h"

namespace warpcheck::bsdf {

/// "bsdf_chi2": the continuous lobes' wi over the sphere against pdf(wo, .)
/// (chi-square), and the pdf's integral against the share of draws that landed.
std::unique_ptr<Check> make_bsdf_chi2_check();
/// "bsdf_unbinned": the continuous lobes' phi_i and cos theta_i against their
/// CDFs from pdf(wo, .) (Kuiper, Anderson-Darling; float-aware, as "unbinned").
std::unique_ptr<Check> make_bsdf_unbinned_check();
/// "bsdf_weight": every sample's weight f |cos theta_i| / pdf against f() and
/// pdf() at its wi; wi a unit vector on the side its flags say; no sample
/// where pdf or f is 0.
std::unique_ptr<Check> make_bsdf_weight_check();
/// "bsdf_delta": each delta lobe's share of draws against its claimed
/// probability (binomial), its direction (mirror, Snell) and its eta.
std::unique_ptr<Check> make_bsdf_delta_check();
/// "bsdf_albedo": the mean weight against the directional albedo (t-test) and
/// the energy albedo at most 1.
std::unique_ptr<Check> make_bsdf_albedo_check();
/// "bsdf_energy" (not a default check; --fuzz runs it): the mean energy weight
/// of the samples at most 1, bsdf_albedo's rule without its quadrature.
std::unique_ptr<Check> make_bsdf_energy_check();
/// "bsdf_expectation": a stochastic BSDF (BsdfClaims::stochastic) in
/// expectation: its sampled weights per cell of the sphere against the
/// integral of its estimated f |cos|, energy at most 1, and its MIS pdf
/// positive wherever it samples.
std::unique_ptr<Check> make_bsdf_expectation_check();
/// "bsdf_spectral": a spectral BSDF's channel case (make_spectral_bsdf_case):
/// every sample's secondary channels' f and pdf against f() and pdf() there
/// (a pdf of 0: the channel terminated).
std::unique_ptr<Check> make_bsdf_spectral_check();
/// "bsdf_reciprocity": f(wo, wi) = f(wi, wo) (the eta^2 rule across an
/// interface), where the case claims it.
std::unique_ptr<Check> make_bsdf_reciprocity_check();

}  // namespace warpcheck::bsdf

// The checks of what only a light seen from a reference point has
// (validate/api/light_case.h). Its direction distribution is tested by the
// warp checks (chi2, unbinned, consistency, sample_pdf, roundtrip), which
// take a light case as a warp on the sphere that returns its pdf.
//
// "light_radiance": every sample's returned L against the light's own
// intersection L(ref, wi) (a sample that misses the light, or returns another
// radiance, fails); samples behind the reference surface are counted and named.
// "light_support": pdf(ref, w) > 0 exactly where L(ref, w) > 0, probed over
// the sphere and around the light: a lit direction of pdf 0 is never sampled
// (bias), a dark one of pdf > 0 is mass the pdf claims where the light is not.
// "light_irradiance": the estimator's mean L |cos theta_i| / pdf against the
// integral of L |cos theta_i| over the sphere (t-test).
//
// MIS cases (MisCase: a BSDF and lights seen from one shading point) are
// tested as the one-sample model by the warp checks (chi2, consistency,
// sample_pdf: the pdfs the MIS sum uses against the densities the samplers
// draw from), and here:
// "mis_weights": at every sampled direction the strategies' weights sum to 1.
// "mis_estimator": the multi-sample MIS estimator's mean against the integral
// of f L |cos theta_i| (t-test).
#pragma once

#include <memory>

#include "validate/checks/check.h"

namespace warpcheck::light {

std::unique_ptr<Check> make_light_radiance_check();
std::unique_ptr<Check> make_light_support_check();
std::unique_ptr<Check> make_light_irradiance_check();
std::unique_ptr<Check> make_mis_weights_check();
std::unique_ptr<Check> make_mis_estimator_check();

}  // namespace warpcheck::light

// Microfacet pieces that the rough BSDFs share, on a Trowbridge-Reitz
// distribution (sampling/trowbridge_reitz.h): Smith's height-correlated
// masking-shadowing and the visible-normal density, in a form that holds for
// wo on either side of the surface (the distribution is seen from the side wo
// is on; normals wm point up, z >= 0).
#pragma once

#include <cmath>

#include "sampling/trowbridge_reitz.h"
#include "sampling/vector.h"

namespace warpcheck {

/// Smith's height-correlated masking-shadowing G2(wo, wi) = 1 / (1 + Lambda(wo)
/// + Lambda(wi)) (Heitz 2014): symmetric in its arguments, 0 at the horizon.
inline float smith_g2(const TrowbridgeReitz& tr, Vector3f wo, Vector3f wi) {
    return 1.0f / (1.0f + tr.lambda(wo) + tr.lambda(wi));
}

/// The density of the normals visible from w (wm up), per solid angle of wm:
/// G1(w) |w.wm| D(wm) / |cos theta_w|. For w below the surface this is the
/// density seen from -w, which TrowbridgeReitzVisibleNormals samples; callers
/// discard back-facing normals (w.wm of the wrong sign) themselves.
inline float visible_normal_pdf(const TrowbridgeReitz& tr, Vector3f w, Vector3f wm) {
    return tr.G1_over_cos(w) * std::abs(dot(w, wm)) * tr.D(wm);
}

/// Whether a sampled normal has a side: the visible-normal warp maps inputs on
/// the square's edge to normals on the horizon (wm.z = 0), a set of measure 0
/// whose half vector, recomputed from the rounded wi, may come out on either
/// side; samplers give up on those (no sample) rather than return a wi whose
/// f and pdf, recomputed, are 0.
inline bool has_side(Vector3f wm) { return wm.z > 0.0f; }

/// wm turned to the upper side (z >= 0).
inline Vector3f face_up(Vector3f wm) { return wm.z < 0.0f ? -1.0f * wm : wm; }

}  // namespace warpcheck

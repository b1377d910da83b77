// The kinds of case a registry holds, read off a case: what a renderer can
// register (from C++20 or C++17) and what the checks tell apart. The C++17
// parity test (tests/validate/api/test_register17_parity.cpp) registers one of
// each kind through validate/api/register17.h: a kind added here without a
// C++17 form fails it.
#pragma once

#include <array>
#include <string_view>

#include "validate/api/bsdf_case.h"
#include "validate/api/exhaustive_sweep.h"
#include "validate/api/light_case.h"
#include "validate/api/warp_case.h"

namespace warpcheck {

enum class CaseKind {
    Warp,           ///< a continuous warp (make_warp_case)
    Discrete,       ///< a choice among categories (sample returns an index)
    FloatSweep,     ///< a float sampler of raw bits on the exhaustive check's fast path
    Bsdf,           ///< a BSDF seen from one wo (make_bsdf_case)
    PhaseFunction,  ///< a phase function seen from one wo (make_phase_case)
    SpectralBsdf,   ///< one hero channel of a spectral BSDF (make_spectral_bsdf_case)
    Light,          ///< a light seen from one reference point (make_light_case)
    Mis,            ///< a BSDF and lights combined by MIS (make_mis_case)
};

/// Every kind, in declaration order.
inline constexpr std::array<CaseKind, 8> kCaseKinds = {CaseKind::Warp,          CaseKind::Discrete,
                                                       CaseKind::FloatSweep,    CaseKind::Bsdf,
                                                       CaseKind::PhaseFunction, CaseKind::SpectralBsdf,
                                                       CaseKind::Light,         CaseKind::Mis};

inline std::string_view to_string(CaseKind kind) {
    switch (kind) {
        case CaseKind::Warp: return "warp";
        case CaseKind::Discrete: return "discrete";
        case CaseKind::FloatSweep: return "float sweep";
        case CaseKind::Bsdf: return "BSDF";
        case CaseKind::PhaseFunction: return "phase function";
        case CaseKind::SpectralBsdf: return "spectral BSDF";
        case CaseKind::Light: return "light";
        case CaseKind::Mis: return "MIS";
    }
    return "unknown";
}

/// The kind of a case: the most specific one it is.
inline CaseKind case_kind(const WarpCase& warp) {
    if (as_mis(warp)) return CaseKind::Mis;
    if (as_light(warp)) return CaseKind::Light;
    if (as_spectral(warp)) return CaseKind::SpectralBsdf;
    if (const BsdfCase* b = as_bsdf(warp)) return b->phase_function() ? CaseKind::PhaseFunction : CaseKind::Bsdf;
    if (dynamic_cast<const SweepableCase*>(&warp)) return CaseKind::FloatSweep;
    if (warp.is_discrete()) return CaseKind::Discrete;
    return CaseKind::Warp;
}

}  // namespace warpcheck

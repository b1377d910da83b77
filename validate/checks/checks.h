// Factories of the checks that ship with warpcheck; register_builtin_checks adds them all.
#pragma once

#include <memory>

#include "validate/check.h"

namespace warpcheck {

/// "roundtrip": invert(sample(u)) == u over a seeded stream plus edge inputs.
std::unique_ptr<Check> make_roundtrip_check();
/// "consistency": every sample lies in the domain and has a finite, positive pdf.
std::unique_ptr<Check> make_consistency_check();
/// "chi2": Pearson chi-square test of samples against the pdf integrated over cells.
std::unique_ptr<Check> make_chi2_check();

}  // namespace warpcheck

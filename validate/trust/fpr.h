// The false-positive-rate tool as a function, so that a program with its own
// warps measures them as warpcheck_fpr measures the built-in ones: the same
// options, the same seeds, the same exact (Clopper-Pearson) 95% interval.
//
//     int main(int argc, char** argv) {
//         return warpcheck::fpr_main(argc, argv, {"my_warps_fpr", "...", &warpcheck_register});
//     }
#pragma once

#include "validate/api/registry.h"

namespace warpcheck {

/// Which warps a false-positive-rate program measures, and its name.
struct FprProgram {
    const char* name = "warpcheck_fpr";  ///< in --help and in messages
    const char* description = "Measures the false-positive rate of warpcheck's default suite over many seeds";
    /// Adds the cases (the built-in checks are registered first, so it may
    /// mark a known flaw on one check). Cases marked as known flaws are left out.
    void (*register_cases)(Registry&) = register_builtin_cases;
    /// Offers --power-check, which simulates the stated tilts of the selected rows.
    bool power_check = false;
};

/// Runs the selected default checks of the program's cases over --runs seeds
/// and prints the fraction of runs with a failure (or an error) with its exact
/// 95% interval, against the family-wise --alpha. Returns 0 when alpha lies in
/// the interval, 1 when not, 2 for bad usage or a registration that throws.
int fpr_main(int argc, char** argv, const FprProgram& program);

}  // namespace warpcheck

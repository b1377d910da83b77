// The `validate` command line, usable by any program that fills a Registry:
// the built-in `validate` and programs that validate their own warps.
#pragma once

#include "validate/api/registry.h"

namespace warpcheck {

/// Exit statuses of run_cli.
enum ExitStatus : int {
    kExitPass = 0,   ///< every selected check passed
    kExitFail = 1,   ///< a check failed or could not run
    kExitUsage = 2,  ///< bad command line, unknown warp or check, unwritable output
};

/// Parses the command line, runs the selected checks, prints the table and
/// writes the requested reports. Returns an ExitStatus.
int run_cli(int argc, char** argv, const Registry& registry);

}  // namespace warpcheck

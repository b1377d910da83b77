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

/// Called first in main: re-executes the program (once) with glibc's malloc
/// asked to back its heap with transparent huge pages
/// (GLIBC_TUNABLES=glibc.malloc.hugetlb=1), where the kernel gives them only
/// on request (the `madvise` mode) and glibc can be asked (2.35 and later).
/// Each job runs in a fresh worker process whose memory is faulted in anew: in
/// 4 KiB pages the kernel's faults were a sixth of validate --all's time on a
/// virtual machine. Does nothing when GLIBC_TUNABLES already names the setting
/// (`glibc.malloc.hugetlb=0` turns it off), under AddressSanitizer, or when the
/// exec fails; no result depends on it.
void prefer_huge_pages(char** argv);

/// Parses the command line, runs the selected checks, prints the table and
/// writes the requested reports. Returns an ExitStatus.
int run_cli(int argc, char** argv, const Registry& registry);

}  // namespace warpcheck

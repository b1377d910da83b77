// The GoogleTest adapter's private parts (warpcheck_gtest.h is what a test
// includes): the settings a test runs with and the test names of a suite's
// jobs. Private, so that the installed adapter header needs none of the
// runner's headers.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "validate/checks/check.h"
#include "validate/run/job.h"

namespace warpcheck::gtest {

/// How the checks run inside a test.
struct Settings {
    RunOptions run;  ///< seed, samples, alpha and time budget, as in `validate`
    /// WARPCHECK_MEMORY_LIMIT: what `validate --memory-limit` takes (MiB the
    /// workers share; 0: none); unset, the machine's default.
    std::optional<uint64_t> memory_limit_mib;
    std::string evidence_dir = "warpcheck-evidence";  ///< where failing cases' HTML goes
};

/// The defaults with the WARPCHECK_* variables applied; throws
/// std::invalid_argument naming a variable whose value is not valid.
Settings settings_from_environment();

/// Where a failing test's HTML evidence goes: WARPCHECK_EVIDENCE_DIR (or
/// warpcheck-evidence) / gtest / <test suite> / <stem>.html, the test suite's
/// name with letters and digits kept and every other character '_'
/// ("warpcheck/MyWarps" gives warpcheck_MyWarps; none outside a test). In its
/// own folder, so that the ctest integration (ctest/<prefix>/) and other test
/// programs never write the same file. A stem too long for a file name (255
/// bytes with ".html") keeps its start, then '_' and 16 hex digits of a hash
/// of the stem, then its last "__<check>".
std::filesystem::path evidence_path(const Settings& settings, const std::string& test_suite, const std::string& stem);

/// The test names of a suite's jobs, in order: "<case>__<check>", each name
/// with its letters and digits kept and every other character '_' (trailing
/// ones dropped): power[n=4] and chi2 give power_n_4__chi2. Cases whose names
/// differ only in other characters (a[x=1.5] and a[x=1_5]) would share a test
/// name: each of them then carries 8 hex digits of a hash of its full name,
/// a_x_1_5_<8 hex digits>__chi2, so names stay unique, and a case without such
/// a twin keeps its plain name.
std::vector<std::string> job_test_names(const std::vector<Job>& jobs);

}  // namespace warpcheck::gtest

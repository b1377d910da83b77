// Runs a shell command and captures its exit status and output (stdout and stderr).
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace warpcheck::testing {

struct CommandResult {
    int status = -1;  ///< exit status, or -1 if the command did not exit normally
    std::string output;
};

inline CommandResult run_command(const std::string& command) {
    CommandResult result;
    FILE* pipe = popen((command + " 2>&1").c_str(), "r");
    if (!pipe) return result;
    std::array<char, 4096> buffer{};
    std::size_t n;
    while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
    const int raw = pclose(pipe);
    if (WIFEXITED(raw)) result.status = WEXITSTATUS(raw);
    return result;
}

/// The validate executable built with the tests, followed by `args`.
inline CommandResult run_validate(const std::string& args) {
    return run_command(std::string(WARPCHECK_VALIDATE_EXE) + " " + args);
}

}  // namespace warpcheck::testing

// Sets an environment variable for the life of a scope, for the GoogleTest
// adapter's tests.
#pragma once

#include <cstdlib>
#include <string>

namespace warpcheck::gtest_adapter_tests {

/// Sets `name` to `value` and unsets it at the end of the scope.
class ScopedEnv {
public:
    ScopedEnv(const char* name, const std::string& value) : name_(name) { ::setenv(name, value.c_str(), 1); }
    ~ScopedEnv() { ::unsetenv(name_); }
    ScopedEnv(const ScopedEnv&) = delete;
    ScopedEnv& operator=(const ScopedEnv&) = delete;

private:
    const char* name_;
};

}  // namespace warpcheck::gtest_adapter_tests

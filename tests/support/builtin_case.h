// A built-in case by its full name, as `validate` registers it: tests check the
// production registration instead of a copy of it. The flawed demonstration
// cases (register_flawed_interval_cases) are included.
#pragma once

#include <stdexcept>
#include <string>

#include "validate/api/registry.h"

namespace warpcheck::testing {

inline const WarpCase& builtin_case(const std::string& name) {
    static const Registry registry = [] {
        Registry r;
        register_builtin_cases(r);
        register_flawed_interval_cases(r);
        return r;
    }();
    const WarpCase* c = registry.find_case(name);
    if (!c) throw std::runtime_error("no built-in case " + name);
    return *c;
}

}  // namespace warpcheck::testing

// Validating your own warps: link warpcheck::main and define
//
//     void warpcheck_register(warpcheck::Registry& registry) { registry.add_case(...); }
//
// and your program is a `validate` for your warps, with the same options,
// checks and reports (the way linking gtest_main gives a test program its main).
// The built-in checks are registered for you; the built-in warps are not.
#pragma once

#include "validate/case_grid.h"
#include "validate/registry.h"

/// Defined by the program that links warpcheck::main: adds its warp cases (and
/// any checks of its own) to the registry.
void warpcheck_register(warpcheck::Registry& registry);

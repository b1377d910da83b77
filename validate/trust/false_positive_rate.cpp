// warpcheck_fpr: measures how often the default suite fails on the built-in
// warps (validate/trust/fpr.h says how, and how a program measures its own warps).
#include "validate/trust/fpr.h"

int main(int argc, char** argv) {
    return warpcheck::fpr_main(argc, argv, {.register_cases = warpcheck::register_builtin_cases, .power_check = true});
}

// `validate`: runs warpcheck's checks on the warps that ship with it.
#include <exception>
#include <iostream>

#include "validate/cli/cli.h"
#include "validate/api/registry.h"

int main(int argc, char** argv) {
    warpcheck::prefer_huge_pages(argv);  // may re-execute this program, before anything runs
    warpcheck::Registry registry;
    try {
        warpcheck::register_builtin_cases(registry);
        warpcheck::register_builtin_checks(registry);
        warpcheck::register_flawed_interval_cases(registry);
        warpcheck::register_flawed_bsdf_cases(registry);
        warpcheck::register_flawed_light_cases(registry);
    } catch (const std::exception& e) {
        std::cerr << "validate: could not register the built-in warps: " << e.what() << "\n";
        return warpcheck::kExitUsage;
    } catch (...) {  // registration is foreign code: anything it throws is a clear error, not std::terminate
        std::cerr << "validate: could not register the built-in warps: an exception that is not a std::exception\n";
        return warpcheck::kExitUsage;
    }
    return warpcheck::run_cli(argc, argv, registry);
}

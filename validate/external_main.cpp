// main() of warpcheck::main: the validate command over the program's own warps.
#include <exception>
#include <iostream>

#include "validate/cli.h"
#include "validate/external.h"

int main(int argc, char** argv) {
    warpcheck::Registry registry;
    try {
        warpcheck::register_builtin_checks(registry);
        warpcheck_register(registry);
    } catch (const std::exception& e) {
        std::cerr << "validate: could not register the warps: " << e.what() << "\n";
        return warpcheck::kExitUsage;
    } catch (...) {  // registration is foreign code: anything it throws is a clear error, not std::terminate
        std::cerr << "validate: could not register the warps: an exception that is not a std::exception\n";
        return warpcheck::kExitUsage;
    }
    return warpcheck::run_cli(argc, argv, registry);
}

// main() of warpcheck::main: the validate command over the program's own warps.
#include <exception>
#include <filesystem>
#include <string>
#include <iostream>

#include "validate/cli/cli.h"
#include "validate/api/external.h"

int main(int argc, char** argv) {
    warpcheck::prefer_huge_pages(argv);  // may re-execute this program, before anything runs
    // Messages name the program as it was run: it is the renderer's, not `validate`.
    const std::string program =
        argc > 0 && argv[0] && *argv[0] ? std::filesystem::path(argv[0]).filename().string() : "validate";
    warpcheck::Registry registry;
    try {
        warpcheck::register_builtin_checks(registry);
        warpcheck_register(registry);
    } catch (const std::exception& e) {
        std::cerr << program << ": could not register the warps: " << e.what() << "\n";
        return warpcheck::kExitUsage;
    } catch (...) {  // registration is foreign code: anything it throws is a clear error, not std::terminate
        std::cerr << program << ": could not register the warps: an exception that is not a std::exception\n";
        return warpcheck::kExitUsage;
    }
    return warpcheck::run_cli(argc, argv, registry);
}

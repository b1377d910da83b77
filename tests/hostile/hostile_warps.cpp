// A program of hostile warps, linked with warpcheck::main the way a renderer's
// own program is: healthy cases next to warps that crash, abort, exit, spin,
// sleep or allocate without bound. run_hostile.sh asserts that each of the six
// costs one ERROR row naming its cause and that the run and its reports finish.
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <memory>
#include <vector>

#include <validate/external.h>

namespace {

struct UnitInterval {  // the identity warp on [0,1): healthy
    float sample(float u) const { return u; }
    float pdf(float x) const { return x >= 0 && x <= 1 ? 1.0f : 0.0f; }
    float invert(float x) const { return x; }
};

void add_healthy(warpcheck::Registry& registry, const char* family) {
    registry.add_case(warpcheck::make_warp_case({.family = family,
                                                 .params = {},
                                                 .description = "identity on [0,1)",
                                                 .input = warpcheck::InputKind::Uniform1D,
                                                 .domain = warpcheck::chi2::Domain::interval(0, 1)},
                                                UnitInterval{}));
}

template <class Misbehave>
void add(warpcheck::Registry& registry, const char* family, Misbehave misbehave) {
    registry.add_case(warpcheck::make_warp_case(
        {.family = family,
         .params = {},
         .description = "hostile: see tests/hostile/hostile_warps.cpp",
         .input = warpcheck::InputKind::Uniform1D,
         .domain = warpcheck::chi2::Domain::interval(0, 1)},
        [misbehave](float u) {
            misbehave();
            return u;
        },
        [](float x) { return UnitInterval{}.pdf(x); }, [](float x) { return x; }));
}

}  // namespace

void warpcheck_register(warpcheck::Registry& registry) {
    add_healthy(registry, "healthy_a");
    add(registry, "hostile_segfault", [] { std::raise(SIGSEGV); });
    add(registry, "hostile_abort", [] { std::abort(); });
    add(registry, "hostile_exit", [] { std::exit(0); });
    add(registry, "hostile_busy_loop", [] {
        volatile unsigned long spins = 0;
        for (;;) spins = spins + 1;
    });
    add(registry, "hostile_sleep", [] {
        for (;;) pause();
    });
    // Without touching the pages: the limit is on address space (RLIMIT_AS),
    // and zeroing 512 MiB costs ~0.25 s of system time, a quarter of the 1 s
    // CPU budget, which a busy machine once stretched past it (the row then
    // said "over its CPU time budget" instead of "ran out of memory").
    add(registry, "hostile_allocate", [] {
        static std::vector<std::unique_ptr<char[]>> hoard;
        for (;;) hoard.push_back(std::make_unique_for_overwrite<char[]>(std::size_t{16} << 20));
    });
    add_healthy(registry, "healthy_b");
}

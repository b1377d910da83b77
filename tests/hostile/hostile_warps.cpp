// A program of hostile warps, linked with warpcheck::main the way a renderer's
// own program is: healthy cases next to warps that crash, abort, exit, spin,
// sleep, stop, allocate, print, change directory, or start processes that
// outlive them (a child in the worker's process group, a daemon in a session
// of its own). run_hostile.sh runs them in scenarios and asserts that each
// costs at most its own row, that nothing they started outlives its check or a
// killed run, and that the tool's own output stays its own.
//
// Environment (all optional):
//   HOSTILE_PIDS=DIR   every process a hostile warp starts (and the worker it
//                      runs in) is recorded as an empty file DIR/<pid>
//   HOSTILE_CHDIR=DIR  hostile_chdir changes the working directory to DIR
//   HOSTILE_SIGNAL_IN_FSYNC=N  fsync() raises signal N first: a signal that
//                      arrives while a report's temporary file is being written
#include <signal.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <validate/api/external.h>

// Defined here, it replaces the C library's for this program (the report
// writer's fsync among them).
extern "C" int fsync(int fd) {
    if (const char* sig = std::getenv("HOSTILE_SIGNAL_IN_FSYNC")) std::raise(std::atoi(sig));
    return static_cast<int>(syscall(SYS_fsync, fd));
}

namespace {

struct UnitInterval {  // the identity warp on [0,1): healthy
    float sample(float u) const { return u; }
    float pdf(float x) const { return x >= 0 && x <= 1 ? 1.0f : 0.0f; }
    float invert(float x) const { return x; }
};

void record_pid(pid_t pid) {
    const char* dir = std::getenv("HOSTILE_PIDS");
    if (dir) std::ofstream(std::string(dir) + "/" + std::to_string(pid));
}

[[noreturn]] void spin() {
    volatile unsigned long spins = 0;
    for (;;) spins = spins + 1;
}

[[noreturn]] void sleep_forever() {
    for (;;) pause();
}

/// A child in the worker's process group that holds the worker's pipes and
/// never exits (spinning or asleep).
void start_child(bool spinning) {
    const pid_t child = fork();
    if (child == 0) spinning ? spin() : sleep_forever();
    record_pid(child);
}

/// A daemon: a grandchild in a session of its own (fork, setsid, fork), left
/// to the worker when its parent exits, holding the worker's pipes forever.
void start_daemon(bool spinning) {
    int ends[2];
    if (pipe(ends) != 0) return;
    const pid_t child = fork();
    if (child == 0) {
        setsid();
        if (fork() == 0) {
            const pid_t self = getpid();
            (void)!write(ends[1], &self, sizeof self);
            spinning ? spin() : sleep_forever();
        }
        _exit(0);
    }
    pid_t daemon = 0;
    if (read(ends[0], &daemon, sizeof daemon) == sizeof daemon) record_pid(daemon);
    waitpid(child, nullptr, 0);
    close(ends[0]);
    close(ends[1]);
}

/// Whether `pid` is gone: no such process, or a zombie (dead, not yet collected).
bool gone(pid_t pid) {
    std::string text;
    try {
        std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
        text.assign(std::istreambuf_iterator<char>(stat), {});
    } catch (const std::ios_base::failure&) {
        // The process went between the open and the read: libstdc++'s filebuf
        // throws on the read's ESRCH ("No such process"), which made this
        // check an ERROR row once in a few CI runs.
        return true;
    }
    const auto paren = text.rfind(')');
    return paren == std::string::npos || text.compare(paren + 1, 3, " Z ") == 0;
}

/// Aborts, naming it, if a process recorded in HOSTILE_PIDS (by a check that
/// ran before) is still there 2 s from now.
void require_recorded_processes_gone() {
    const char* dir = std::getenv("HOSTILE_PIDS");
    if (!dir) return;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        const pid_t pid = std::atoi(entry.path().filename().c_str());
        while (!gone(pid) && std::chrono::steady_clock::now() < deadline)
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        if (gone(pid)) continue;
        std::fprintf(stderr, "process %d, started by an earlier check, is still running\n", static_cast<int>(pid));
        std::abort();
    }
}

void add_healthy(warpcheck::Registry& registry, const char* family, std::vector<warpcheck::Parameter> params = {}) {
    registry.add_case(warpcheck::make_warp_case({.family = family,
                                                 .params = std::move(params),
                                                 .description = "identity on [0,1)",
                                                 .domain = warpcheck::chi2::Domain::interval(0, 1)},
                                                UnitInterval{}));
}

/// A case whose sample() calls `misbehave` on every call.
template <class Misbehave>
void add(warpcheck::Registry& registry, const std::string& family, Misbehave misbehave) {
    registry.add_case(warpcheck::make_warp_case(
        {.family = family,
         .params = {},
         .description = "hostile: see tests/hostile/hostile_warps.cpp",
         .domain = warpcheck::chi2::Domain::interval(0, 1)},
        warpcheck::warp_of([misbehave](float u) {
                               misbehave();
                               return u;
                           })
            .with_pdf([](float x) { return UnitInterval{}.pdf(x); })
            .with_invert([](float x) { return x; })));
}

/// A case whose sample() calls `act` once per process (the first call in each
/// worker), then behaves.
template <class Act>
void add_once(warpcheck::Registry& registry, const std::string& family, Act act) {
    add(registry, family, [act] {
        static bool done = false;
        if (!std::exchange(done, true)) act();
    });
}

void add_crashing(warpcheck::Registry& registry) {
    add(registry, "hostile_segfault", [] { std::raise(SIGSEGV); });
    add(registry, "hostile_abort", [] { std::abort(); });
    add(registry, "hostile_exit", [] { std::exit(0); });
    add_once(registry, "hostile_busy_loop", [] {
        record_pid(getpid());
        spin();
    });
    add(registry, "hostile_sleep", [] { sleep_forever(); });
    add_once(registry, "hostile_stop", [] {
        record_pid(getpid());
        for (;;) std::raise(SIGSTOP);
    });
    // Without touching the pages: the limit is on address space (RLIMIT_AS),
    // and zeroing 512 MiB costs ~0.25 s of system time, a quarter of the 1 s
    // CPU budget, which a busy machine once stretched past it (the row then
    // said "over its CPU time budget" instead of "ran out of memory").
    add(registry, "hostile_allocate", [] {
        static std::vector<std::unique_ptr<char[]>> hoard;
        for (;;) hoard.push_back(std::make_unique_for_overwrite<char[]>(std::size_t{16} << 20));
    });
    // 700 MiB of address space, kept for the whole check: within a 1024 MiB
    // budget for one worker, over the 512 MiB share of each of two.
    add_once(registry, "hostile_reserve_700", [] {
        static auto reserve = std::make_unique_for_overwrite<char[]>(std::size_t{700} << 20);
    });
}

void add_lingering(warpcheck::Registry& registry) {
    add_once(registry, "hostile_child_holds_pipes", [] { start_child(false); });
    add_once(registry, "hostile_daemon_holds_pipes", [] { start_daemon(false); });
    // For a run killed midway: a spinning child of a sleeping worker, and a
    // sleeping daemon of a sleeping worker. (Two spinning processes in all,
    // with hostile_busy_loop: enough to show that a spinning process goes, few
    // enough not to starve the other tests on a 2-core machine.)
    add_once(registry, "hostile_child_spins", [] {
        record_pid(getpid());
        start_child(true);
        sleep_forever();
    });
    add_once(registry, "hostile_daemon_sleeps", [] {
        record_pid(getpid());
        start_daemon(false);
        sleep_forever();
    });
    // Registered after those above: with one worker at a time it runs after them.
    add_once(registry, "hostile_zz_checks_reaped", require_recorded_processes_gone);
}

void add_impolite(warpcheck::Registry& registry) {
    add_once(registry, "hostile_prints", [] {
        std::printf("hostile_prints: a line on stdout (printf)\n");
        std::cout << "hostile_prints: a line on stdout (std::cout)" << std::endl;
        std::fprintf(stderr, "hostile_prints: a line on stderr\n");
    });
    add_once(registry, "hostile_chdir", [] {
        if (const char* dir = std::getenv("HOSTILE_CHDIR")) (void)!chdir(dir);
    });
    // A name that would clear the screen and retitle the terminal, on a warp
    // whose inverse is wrong (so it also has a failure message and a rerun command).
    registry.add_case(warpcheck::make_warp_case({.family = "hostile_name\x1b[2J\x1b]0;owned\x07\r\n",
                                                 .params = {},
                                                 .description = "identity on [0,1), inverse halved",
                                                 .domain = warpcheck::chi2::Domain::interval(0, 1)},
                                                warpcheck::warp_of([](float u) { return u; })
                                                    .with_pdf([](float x) { return UnitInterval{}.pdf(x); })
                                                    .with_invert([](float x) { return 0.5f * x; })));
}

/// A sphere light 4 away at theta 30, seen from the origin (normal +z): the
/// misbehaving lights are made of it.
struct Sphere {
    warpcheck::Vector3f c{2.0f, 0.0f, 3.4641016f};
    float omc_max() const { return 1.0f / 16.0f / (1.0f + std::sqrt(1.0f - 1.0f / 16.0f)); }
    bool hits(warpcheck::Vector3f wi) const {
        const float b = c.x * wi.x + c.y * wi.y + c.z * wi.z;
        return b > 0 && 16.0f - b * b <= 1.0f;
    }
    warpcheck::LightSample sample(warpcheck::Vector3f, warpcheck::Point2f u) const {
        // Around the axis a = c / 4 = (1/2, 0, sqrt(3)/2), with t = (sqrt(3)/2, 0, -1/2) and b = (0, 1, 0).
        const float omc = u.x * omc_max(), st = std::sqrt(omc * (2 - omc)), phi = 6.2831853f * u.y;
        const float x = st * std::cos(phi), y = st * std::sin(phi), z = 1 - omc;
        return {{0.8660254f * x + 0.5f * z, y, -0.5f * x + 0.8660254f * z}, 1 / (6.2831853f * omc_max()), 2.0f, 3.0f};
    }
    float pdf(warpcheck::Vector3f, warpcheck::Vector3f wi) const { return hits(wi) ? 1 / (6.2831853f * omc_max()) : 0.0f; }
    float L(warpcheck::Vector3f, warpcheck::Vector3f wi) const { return hits(wi) ? 2.0f : 0.0f; }
};

/// Its own intersection throws.
struct ThrowingLight : Sphere {
    float L(warpcheck::Vector3f, warpcheck::Vector3f) const { throw std::runtime_error("hostile: no light here"); }
};

/// Its samples return a NaN pdf for a tenth of the inputs.
struct NanPdfLight : Sphere {
    warpcheck::LightSample sample(warpcheck::Vector3f ref, warpcheck::Point2f u) const {
        warpcheck::LightSample s = Sphere::sample(ref, u);
        if (u.x < 0.1f) s.pdf = std::nanf("");
        return s;
    }
};

struct Diffuse {
    warpcheck::BsdfFlags flags() const { return warpcheck::BsdfFlags::Reflection | warpcheck::BsdfFlags::Continuous; }
    float f(warpcheck::Vector3f wo, warpcheck::Vector3f wi) const { return wo.z * wi.z > 0 ? 0.5f / 3.1415927f : 0.0f; }
    float pdf(warpcheck::Vector3f wo, warpcheck::Vector3f wi) const {
        return wo.z * wi.z > 0 ? std::abs(wi.z) / 3.1415927f : 0.0f;
    }
    warpcheck::BsdfSample sample(warpcheck::Vector3f wo, float, warpcheck::Point2f u) const {
        const float r = std::sqrt(u.x), phi = 6.2831853f * u.y;
        const warpcheck::Vector3f wi{r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1 - u.x))};
        const float p = pdf(wo, wi);
        if (!(p > 0)) return {};
        return {wi, f(wo, wi), p, flags()};
    }
};

void add_lights(warpcheck::Registry& registry) {
    constexpr warpcheck::LightClaims at{.ref = {0, 0, 0}, .normal = {0, 0, 1}};
    registry.add_case(warpcheck::make_light_case({.family = "hostile_light_throws"}, at, ThrowingLight{}));
    registry.add_case(warpcheck::make_light_case({.family = "hostile_light_nan_pdf"}, at, NanPdfLight{}));
    // An MIS sum whose light pdf is NaN on half the sphere.
    warpcheck::MisClaims claims;
    claims.pdfs.lights.push_back([](warpcheck::Vector3f ref, warpcheck::Vector3f wi) {
        return wi.y > 0 ? std::nanf("") : Sphere{}.pdf(ref, wi);
    });
    registry.add_case(warpcheck::make_mis_case(
        {.family = "hostile_mis_nan_pdf"}, std::move(claims),
        warpcheck::make_bsdf_case({.family = "diffuse"}, {.wo = warpcheck::bsdf_direction(40, 180)}, Diffuse{}),
        warpcheck::make_light_case({.family = "sphere"}, at, Sphere{})));
}

}  // namespace

void warpcheck_register(warpcheck::Registry& registry) {
    add_healthy(registry, "healthy_a");
    add_crashing(registry);
    add_lingering(registry);
    add_impolite(registry);
    add_healthy(registry, "healthy_params", {{"a", 1}});
    add_healthy(registry, "healthy_params", {{"a", 1}, {"b", 3}});
    add_healthy(registry, "healthy_b");
    add_lights(registry);
}

#include "reports/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>

#include <fmt/format.h>

#include "reports/outputs.h"

namespace warpcheck {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& path, const std::string& reason) {
    throw ReportError(fmt::format("cannot write {}: {}", path, reason));
}

fs::path folder_of(const fs::path& target) { return target.has_parent_path() ? target.parent_path() : fs::path("."); }

/// The longest file name `folder` takes (NAME_MAX, 255 on Linux file systems).
std::size_t longest_name(const fs::path& folder) {
    const long most = ::pathconf(folder.c_str(), _PC_NAME_MAX);
    return most > 0 ? static_cast<std::size_t>(most) : 255;
}

/// A name in the target's folder that no other writer uses: hidden, with the
/// process id and a per-process counter. The target's name is cut short where
/// the whole would be longer than the folder allows, so that every name the
/// folder takes has a temporary name.
fs::path temporary_path_for(const fs::path& target) {
    static std::atomic<unsigned> counter{0};
    const fs::path folder = folder_of(target);
    const std::string suffix = fmt::format(".tmp-{}-{}", ::getpid(), counter++);
    std::string name = target.filename().string();
    const std::size_t room = longest_name(folder) - 1 - suffix.size();
    if (name.size() > room) name.resize(room);
    return folder / ("." + name + suffix);
}

// The temporary file being written, for the signal handler: a fixed buffer,
// since a handler may not allocate. One write at a time is in progress.
std::array<char, 4096> g_temporary_name{};
std::atomic<bool> g_temporary_active{false};

extern "C" void remove_temporary_and_reraise(int sig) {
    if (g_temporary_active.load()) ::unlink(g_temporary_name.data());
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

/// Closes and deletes the temporary file unless released.
struct TemporaryFile {
    fs::path path;
    int fd = -1;
    bool keep = false;
    explicit TemporaryFile(fs::path p) : path(std::move(p)) {
        const std::string& name = path.native();
        if (name.size() < g_temporary_name.size()) {
            std::memcpy(g_temporary_name.data(), name.c_str(), name.size() + 1);
            g_temporary_active = true;
        }
    }
    ~TemporaryFile() {
        g_temporary_active = false;
        if (fd >= 0) ::close(fd);
        if (!keep) {
            std::error_code ignored;
            fs::remove(path, ignored);
        }
    }
};

/// Follows symbolic links one at a time, so that a dangling link leads to the
/// file it would create.
fs::path follow_links(fs::path p) {
    std::error_code ec;
    for (int hops = 0; hops < 40 && fs::is_symlink(fs::symlink_status(p, ec)); ++hops) {
        const fs::path next = fs::read_symlink(p, ec);
        if (ec) break;
        p = next.is_absolute() ? next : p.parent_path() / next;
    }
    return p;
}

/// Whether `p` is still a symbolic link after follow_links: the links loop,
/// or are more than it follows.
bool is_link(const fs::path& p) {
    std::error_code ec;
    return fs::is_symlink(fs::symlink_status(p, ec));
}

/// The process id in a temporary name of `target` (temporary_path_for:
/// ".NAME.tmp-PID-N", NAME cut short where the whole is the longest name the
/// folder takes), or 0 if `name` is not one.
pid_t temporary_owner(const std::string& name, const fs::path& target) {
    const std::size_t tmp = name.rfind(".tmp-");
    if (tmp == std::string::npos || tmp < 1 || name[0] != '.') return 0;
    const std::string stem = name.substr(1, tmp - 1), own = target.filename().string();
    const bool cut_short = name.size() == longest_name(folder_of(target)) && own.starts_with(stem);
    if (stem.empty() || (stem != own && !cut_short)) return 0;
    const std::string rest = name.substr(tmp + 5);  // PID-N
    const std::size_t dash = rest.find('-');
    if (dash == 0 || dash == std::string::npos || dash + 1 == rest.size() ||
        rest.find_first_not_of("0123456789-") != std::string::npos || rest.find('-', dash + 1) != std::string::npos ||
        dash > 9)
        return 0;
    return static_cast<pid_t>(std::stol(rest.substr(0, dash)));
}

/// Removes the temporary files of `target` that writers killed before they
/// could (SIGKILL, a power cut) left behind: those whose process is gone and
/// that nothing wrote to for a minute (a writer in another PID namespace, on a
/// shared folder, looks gone to this one). A live process's, and every other
/// file, stay.
void remove_stale_temporaries(const fs::path& target) {
    std::error_code ec;
    const auto stale_before = fs::file_time_type::clock::now() - std::chrono::minutes(1);
    for (fs::directory_iterator it(folder_of(target), ec), end; !ec && it != end; it.increment(ec)) {
        const pid_t pid = temporary_owner(it->path().filename().string(), target);
        if (pid <= 0 || pid == ::getpid()) continue;
        if (::kill(pid, 0) == 0 || errno != ESRCH) continue;  // alive, or not ours to know
        std::error_code failed;
        if (!fs::is_regular_file(fs::symlink_status(it->path(), failed)) || failed) continue;
        const auto written = fs::last_write_time(it->path(), failed);
        if (!failed && written < stale_before) fs::remove(it->path(), failed);
    }
}

}  // namespace

std::string resolved_output_path(const std::string& path) {
    std::error_code ec;
    const fs::path p = follow_links(fs::absolute(path, ec));
    const fs::path canonical = fs::weakly_canonical(p, ec);
    return (ec ? p : canonical).lexically_normal().string();
}

std::string output_path_problem(const std::string& path) {
    if (path.empty()) return "empty path";
    const fs::path target = follow_links(fs::path(path));
    struct stat st {};
    if (::stat(target.c_str(), &st) == 0) {
        if (S_ISDIR(st.st_mode)) return "it is a directory";
        if (!S_ISREG(st.st_mode)) return "it is not a regular file (a device, FIFO or socket)";
    } else if (errno == ELOOP || is_link(target)) {
        return "its symbolic links form a loop (or are too many to follow)";
    }
    const fs::path dir = folder_of(target);
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return "folder " + dir.string() + " does not exist";
    if (::access(dir.c_str(), W_OK) != 0) return "folder " + dir.string() + " is not writable";
    if (target.filename().string().size() > longest_name(dir))
        return fmt::format("the name is longer than the {} bytes its folder allows", longest_name(dir));
    // The write makes a temporary file beside the target first: make one now
    // (and remove it), so that what would stop it shows before the run.
    const fs::path probe = temporary_path_for(target);
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd < 0) return fmt::format("cannot create a file in {}: {}", dir.string(), std::strerror(errno));
    ::close(fd);
    ::unlink(probe.c_str());
    return {};
}

void remove_temporary_files_on_signals() {
    // Every signal whose default action ends the process and that a user or a
    // terminal sends: Ctrl-C, kill, a closed terminal, Ctrl-\. One that is
    // ignored (nohup, a background job of a script) stays ignored.
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) {
        struct sigaction action {}, previous {};
        action.sa_handler = remove_temporary_and_reraise;
        sigemptyset(&action.sa_mask);
        if (sigaction(sig, &action, &previous) == 0 && previous.sa_handler == SIG_IGN)
            sigaction(sig, &previous, nullptr);
    }
}

void write_file_atomically(const std::string& path, std::string_view contents) {
    if (path.empty()) fail(path, "empty path");
    if (!fs::path(path).has_filename()) fail(path, "not a file name");
    // Through a symbolic link to its target: the link is the user's, and stays.
    const fs::path target = follow_links(fs::path(path));
    std::error_code ec;
    // A loop of links: writing would replace one of them with a regular file.
    if (is_link(target)) fail(path, "its symbolic links form a loop (or are too many to follow)");
    if (fs::is_directory(target, ec)) fail(path, "is a directory");
    struct stat existing {};
    const bool exists = ::stat(target.c_str(), &existing) == 0;
    if (exists && !S_ISREG(existing.st_mode)) fail(path, "not a regular file (a device, FIFO or socket)");

    TemporaryFile temporary{temporary_path_for(target)};
    temporary.fd = ::open(temporary.path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (temporary.fd < 0) {
        temporary.keep = true;  // nothing was created
        fail(path, std::strerror(errno));
    }
    // A file replaced keeps its permissions (a report kept private stays private).
    if (exists && ::fchmod(temporary.fd, existing.st_mode & 07777) != 0) fail(path, std::strerror(errno));
    const char* data = contents.data();
    std::size_t left = contents.size();
    while (left > 0) {
        const ssize_t written = ::write(temporary.fd, data, left);
        if (written < 0) {
            if (errno == EINTR) continue;
            fail(path, std::strerror(errno));
        }
        data += written;
        left -= static_cast<std::size_t>(written);
    }
    // The contents must be on disk before the name points at them, or a crash
    // right after the rename could leave an empty file behind.
    if (::fsync(temporary.fd) != 0) fail(path, std::strerror(errno));
    const int fd = temporary.fd;
    temporary.fd = -1;
    if (::close(fd) != 0) fail(path, std::strerror(errno));

    fs::rename(temporary.path, target, ec);
    if (ec) fail(path, ec.message());
    temporary.keep = true;
    remove_stale_temporaries(target);
}

}  // namespace warpcheck

#include "reports/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

#include <fmt/format.h>

#include "reports/outputs.h"

namespace warpcheck {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& path, const std::string& reason) {
    throw ReportError(fmt::format("cannot write {}: {}", path, reason));
}

/// A name in the target's folder that no other writer uses: hidden, with the
/// process id and a per-process counter.
fs::path temporary_path_for(const fs::path& target) {
    static std::atomic<unsigned> counter{0};
    fs::path folder = target.parent_path();
    if (folder.empty()) folder = ".";
    return folder / fmt::format(".{}.tmp-{}-{}", target.filename().string(), ::getpid(), counter++);
}

/// Closes and deletes the temporary file unless released.
struct TemporaryFile {
    fs::path path;
    int fd = -1;
    bool keep = false;
    ~TemporaryFile() {
        if (fd >= 0) ::close(fd);
        if (!keep) {
            std::error_code ignored;
            fs::remove(path, ignored);
        }
    }
};

}  // namespace

void write_file_atomically(const std::string& path, std::string_view contents) {
    if (path.empty()) fail(path, "empty path");
    const fs::path target(path);
    if (!target.has_filename()) fail(path, "not a file name");
    std::error_code ec;
    if (fs::is_directory(target, ec)) fail(path, "is a directory");

    TemporaryFile temporary{temporary_path_for(target)};
    temporary.fd = ::open(temporary.path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (temporary.fd < 0) {
        temporary.keep = true;  // nothing was created
        fail(path, std::strerror(errno));
    }
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
}

}  // namespace warpcheck

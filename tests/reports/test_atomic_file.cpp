#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "reports/atomic_file.h"
#include "reports/outputs.h"
#include "support/temp_dir.h"

namespace warpcheck {
namespace {

using ::testing::HasSubstr;
using namespace warpcheck::testing;
namespace fs = std::filesystem;

std::size_t entries(const fs::path& folder) {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(folder), fs::directory_iterator()));
}

TEST(AtomicFile, WritesAndReplaces) {
    TempDir dir;
    const std::string path = dir.file("out.txt");
    write_file_atomically(path, "first");
    EXPECT_EQ(read_file(path), "first");
    write_file_atomically(path, "second, longer");
    EXPECT_EQ(read_file(path), "second, longer");
    write_file_atomically(path, "");
    EXPECT_EQ(read_file(path), "");
    EXPECT_EQ(entries(dir.path()), 1u) << "no temporary file is left behind";
}

TEST(AtomicFile, WritesARelativePath) {
    TempDir dir;
    const fs::path before = fs::current_path();
    fs::current_path(dir.path());
    write_file_atomically("relative.txt", "x");
    fs::current_path(before);
    EXPECT_EQ(read_file(dir.file("relative.txt")), "x");
}

TEST(AtomicFile, MissingFolderIsAClearError) {
    TempDir dir;
    const std::string path = dir.file("missing/out.txt");
    try {
        write_file_atomically(path, "x");
        FAIL() << "no error";
    } catch (const ReportError& e) {
        EXPECT_EQ(std::string(e.what()), "cannot write " + path + ": No such file or directory");
    }
}

TEST(AtomicFile, FileAsFolderIsAClearError) {
    TempDir dir;
    write_file_atomically(dir.file("plain"), "x");
    EXPECT_THROW(write_file_atomically(dir.file("plain/out.txt"), "x"), ReportError);
}

TEST(AtomicFile, FailureLeavesTheTargetAsItWas) {
    // A folder where the file should go: nothing can replace it; what is in it
    // stays, and no temporary file is left next to it.
    TempDir dir;
    const fs::path target = dir.path() / "report.html";
    fs::create_directory(target);
    write_file_atomically((target / "inside.txt").string(), "kept");
    try {
        write_file_atomically(target.string(), "new contents");
        FAIL() << "no error";
    } catch (const ReportError& e) {
        EXPECT_THAT(e.what(), HasSubstr("cannot write " + target.string() + ": "));
    }
    EXPECT_TRUE(fs::is_directory(target));
    EXPECT_EQ(read_file((target / "inside.txt").string()), "kept");
    EXPECT_EQ(entries(dir.path()), 1u);
}

TEST(AtomicFile, SymlinkIsWrittenThroughAndKept) {
    TempDir dir;
    const fs::path target = dir.path() / "target.txt", link = dir.path() / "link.txt";
    write_file_atomically(target.string(), "old");
    fs::create_symlink("target.txt", link);  // relative, as users make them
    write_file_atomically(link.string(), "new");
    EXPECT_TRUE(fs::is_symlink(link));
    EXPECT_EQ(read_file(target.string()), "new");
    EXPECT_EQ(resolved_output_path(link.string()), resolved_output_path(target.string()));
    // A dangling link creates the file it points at.
    fs::create_symlink("made.txt", dir.path() / "dangling.txt");
    write_file_atomically((dir.path() / "dangling.txt").string(), "made");
    EXPECT_EQ(read_file((dir.path() / "made.txt").string()), "made");
    EXPECT_TRUE(fs::is_symlink(dir.path() / "dangling.txt"));
}

// A loop of links given as an output: refused by the check before a run and
// by the write, the links left as they were (it was replaced by a regular file).
TEST(AtomicFile, ALoopOfSymlinksIsRefused) {
    TempDir dir;
    const fs::path a = dir.path() / "a.json", b = dir.path() / "b.json";
    fs::create_symlink("b.json", a);
    fs::create_symlink("a.json", b);
    EXPECT_THAT(output_path_problem(a.string()), HasSubstr("symbolic links form a loop"));
    try {
        write_file_atomically(a.string(), "x");
        FAIL() << "a loop of links was written";
    } catch (const ReportError& e) {
        EXPECT_THAT(e.what(), HasSubstr("symbolic links form a loop"));
    }
    EXPECT_TRUE(fs::is_symlink(a));
    EXPECT_TRUE(fs::is_symlink(b));
    EXPECT_EQ(entries(dir.path()), 2u);
}

/// The id of a process that has ended (a child, reaped).
pid_t ended_process() {
    const pid_t child = ::fork();
    if (child == 0) ::_exit(0);
    int status = 0;
    ::waitpid(child, &status, 0);
    return child;
}

// A writer killed mid-write (SIGKILL) leaves its temporary file; the next
// write of the same file removes it, once its writer is gone and it is a
// minute old. A live writer's, a fresh one's and other files stay.
TEST(AtomicFile, StaleTemporaryFilesOfEndedWritersAreRemoved) {
    TempDir dir;
    const fs::path target = dir.path() / "r.json";
    const auto old = fs::file_time_type::clock::now() - std::chrono::hours(1);
    const auto temporary = [&](pid_t pid, int n, bool stale) {
        const fs::path p = dir.path() / (".r.json.tmp-" + std::to_string(pid) + "-" + std::to_string(n));
        write_file_atomically(dir.file("scratch"), "");
        fs::rename(dir.path() / "scratch", p);
        if (stale) fs::last_write_time(p, old);
        return p;
    };
    const pid_t ended = ended_process();
    const fs::path dead = temporary(ended, 0, true), fresh = temporary(ended, 1, false),
                   alive = temporary(::getppid(), 2, true);
    const fs::path other = dir.path() / (".other.json.tmp-" + std::to_string(ended) + "-0");
    fs::copy_file(dead, other);
    fs::last_write_time(other, old);
    write_file_atomically(target.string(), "results");
    EXPECT_FALSE(fs::exists(dead)) << "the ended writer's temporary file stays";
    EXPECT_TRUE(fs::exists(fresh)) << "a temporary file written to within the minute is removed";
    EXPECT_TRUE(fs::exists(alive)) << "a live writer's temporary file is removed";
    EXPECT_TRUE(fs::exists(other)) << "another file's temporary file is removed";
    EXPECT_EQ(read_file(target.string()), "results");
}

TEST(AtomicFile, ReplacedFileKeepsItsPermissions) {
    TempDir dir;
    const std::string path = dir.file("private.json");
    write_file_atomically(path, "a");
    ASSERT_EQ(::chmod(path.c_str(), 0600), 0);
    write_file_atomically(path, "b");
    struct stat st {};
    ASSERT_EQ(::stat(path.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0600u);
    EXPECT_EQ(read_file(path), "b");
}

TEST(AtomicFile, SpecialFilesAreRefused) {
    TempDir dir;
    const std::string fifo = dir.file("fifo");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    EXPECT_THAT(output_path_problem(fifo), HasSubstr("not a regular file"));
    EXPECT_THROW(write_file_atomically(fifo, "x"), ReportError);
    EXPECT_THAT(output_path_problem("/dev/null"), HasSubstr("not a regular file"));
    EXPECT_THAT(output_path_problem(dir.path().string()), HasSubstr("directory"));
    EXPECT_THAT(output_path_problem(dir.file("missing/x")), HasSubstr("does not exist"));
    EXPECT_EQ(output_path_problem(dir.file("fine.json")), "");
    EXPECT_EQ(entries(dir.path()), 1u);
}

// Every name the folder takes can be written, its temporary name too (a name
// of 243 to 255 bytes once passed the check and failed after the run), and a
// longer one is refused by the check, before any run.
TEST(AtomicFile, LongNamesAreWrittenOrRefusedByTheCheck) {
    TempDir dir;
    for (std::size_t length : {200u, 243u, 250u, 255u}) {
        const std::string path = dir.file(std::string(length - 5, 'a') + ".json");
        EXPECT_EQ(output_path_problem(path), "") << length;
        EXPECT_NO_THROW(write_file_atomically(path, "x")) << length;
        EXPECT_EQ(read_file(path), "x") << length;
        fs::remove(path);
    }
    EXPECT_THAT(output_path_problem(dir.file(std::string(256, 'a'))), HasSubstr("longer than the 255 bytes"));
    EXPECT_EQ(entries(dir.path()), 0u) << "the check leaves no file behind";
}

TEST(AtomicFile, EmptyPathIsAnError) { EXPECT_THROW(write_file_atomically("", "x"), ReportError); }

}  // namespace
}  // namespace warpcheck

#include <filesystem>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "reports/atomic_file.h"
#include "reports/outputs.h"
#include "tests/reports/temp_dir.h"

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

TEST(AtomicFile, EmptyPathIsAnError) { EXPECT_THROW(write_file_atomically("", "x"), ReportError); }

}  // namespace
}  // namespace warpcheck

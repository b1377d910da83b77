// Writing a file so that a reader never sees half of it: the contents go to a
// temporary file in the target's folder, which is flushed to disk and then
// renamed over the target in one step.
#pragma once

#include <string>
#include <string_view>

namespace warpcheck {

/// Replaces the file at `path` with `contents` atomically. A symbolic link is
/// followed: its target is replaced and the link stays (a loop of links is
/// refused). An existing file keeps its permissions. On any failure the target
/// is left as it was, the temporary file is removed, and ReportError
/// (reports/outputs.h) is thrown: "cannot write <path>: <reason>" (a device,
/// FIFO or socket is refused). After a write, the temporary files of `path`
/// that killed writers left (".NAME.tmp-PID-N" of a process that is gone,
/// untouched for a minute) are removed.
void write_file_atomically(const std::string& path, std::string_view contents);

/// Where a write to `path` lands: the path with its symbolic links followed
/// (also a dangling link's target), made absolute.
std::string resolved_output_path(const std::string& path);

/// Empty if `path` could be written by write_file_atomically (its folder exists
/// and is writable; it is not a folder, device, FIFO, socket or loop of
/// symbolic links), else why not.
std::string output_path_problem(const std::string& path);

/// Installs SIGINT, SIGTERM, SIGHUP and SIGQUIT handlers that remove the
/// temporary file of a write in progress before the process ends as the signal
/// says. A signal that is ignored (nohup) stays ignored.
void remove_temporary_files_on_signals();

}  // namespace warpcheck

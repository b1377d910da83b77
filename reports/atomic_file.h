// Writing a file so that a reader never sees half of it: the contents go to a
// temporary file in the target's folder, which is flushed to disk and then
// renamed over the target in one step.
#pragma once

#include <string>
#include <string_view>

namespace warpcheck {

/// Replaces the file at `path` with `contents` atomically. On any failure the
/// target is left as it was, the temporary file is removed, and ReportError
/// (reports/outputs.h) is thrown: "cannot write <path>: <reason>".
void write_file_atomically(const std::string& path, std::string_view contents);

}  // namespace warpcheck

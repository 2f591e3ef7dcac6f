// Whole-file writes that never leave a half-written file behind.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace spt {

/// Writes `bytes` to a temporary file next to `path`, then renames it over `path`, so readers
/// see either the old file or the complete new one. On failure the temporary file is removed
/// and std::runtime_error is thrown naming `path` and the OS error.
void write_file_atomically(const std::string& path, const std::string& bytes);

/// Several files (path, bytes): all are written to temporary files first and renamed only
/// when every write succeeded, so one failure leaves every existing target untouched.
void write_files_atomically(const std::vector<std::pair<std::string, std::string>>& files);

}  // namespace spt

// Whole-file writes that never leave a half-written file behind.
#pragma once
#include <string>

namespace spt {

/// Writes `bytes` to a temporary file next to `path`, then renames it over `path`, so readers
/// see either the old file or the complete new one. On failure the temporary file is removed
/// and std::runtime_error is thrown naming `path` and the OS error.
void write_file_atomically(const std::string& path, const std::string& bytes);

}  // namespace spt

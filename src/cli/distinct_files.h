// No file given for two roles: an output that is also the checkpoint, the checkpoint being
// resumed, a part being merged or another output would be destroyed by the write.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace spt {

/// True when the two paths name one file: equal after resolving the current directory, "..",
/// and symbolic links (of the file or of any folder above it), or hard links of one file.
bool same_file(const std::string& a, const std::string& b);

/// A file and what the command does with it ("-o", "--checkpoint", "a part", ...).
struct FileRole {
    std::string path;
    std::string role;
    bool written = false;  ///< the command writes it (else reads it)
};

/// Throws UsageError when a written file is also another role's file (written or read),
/// naming both roles. Reading one file twice, or writing and then reading back the same
/// checkpoint (--checkpoint X --resume X), is allowed: `allowed` lists such pairs of roles.
void check_distinct_files(const std::vector<FileRole>& files,
                          const std::vector<std::pair<std::string, std::string>>& allowed = {});

}  // namespace spt

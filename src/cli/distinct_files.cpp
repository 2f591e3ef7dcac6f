#include "cli/distinct_files.h"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "cli/options.h"

namespace spt {

bool same_file(const std::string& a, const std::string& b) {
    namespace fs = std::filesystem;
    std::error_code ea, eb;
    const fs::path ca = fs::weakly_canonical(fs::absolute(a, ea), ea);
    const fs::path cb = fs::weakly_canonical(fs::absolute(b, eb), eb);
    if (!ea && !eb && ca == cb) return true;
    std::error_code e;
    return fs::exists(a, e) && fs::exists(b, e) && fs::equivalent(a, b, e) && !e;
}

void check_distinct_files(const std::vector<FileRole>& files,
                          const std::vector<std::pair<std::string, std::string>>& allowed) {
    const auto permitted = [&](const std::string& r, const std::string& s) {
        return std::any_of(allowed.begin(), allowed.end(), [&](const auto& p) {
            return (p.first == r && p.second == s) || (p.first == s && p.second == r);
        });
    };
    for (std::size_t i = 0; i < files.size(); ++i)
        for (std::size_t j = i + 1; j < files.size(); ++j) {
            const FileRole &a = files[i], &b = files[j];
            if (!a.written && !b.written) continue;
            if (permitted(a.role, b.role) || !same_file(a.path, b.path)) continue;
            throw UsageError(a.role + " '" + a.path + "' is the same file as " + b.role + " '" + b.path + "'" +
                             ": one file cannot be both (writing one would destroy the other); expected "
                             "different files");
        }
}

}  // namespace spt

// The partial-name rule (pure string work: the file system is not consulted).
#include "cli/output_names.h"

namespace spt {

std::string partial_output_name(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    const std::size_t name_start = slash == std::string::npos ? 0 : slash + 1;
    const std::size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || dot < name_start) return path + ".partial";
    return path.substr(0, dot) + ".partial" + path.substr(dot);
}

std::vector<std::string> partial_output_names(const std::vector<std::string>& paths) {
    std::vector<std::string> names;
    names.reserve(paths.size());
    for (const std::string& p : paths) names.push_back(partial_output_name(p));
    return names;
}

}  // namespace spt

// Where an unfinished image goes: beside the output, under a name that says it is unfinished.
#pragma once
#include <string>
#include <vector>

namespace spt {

/// The name of the unfinished image of output `path`: ".partial" inserted before the
/// extension, the part of the file name from its last dot (the part the image format is read
/// from, so the format is kept): "a/b.png" -> "a/b.partial.png", "x.tar.exr" ->
/// "x.tar.partial.exr", "dir.d/b" -> "dir.d/b.partial" (no extension: appended).
std::string partial_output_name(const std::string& path);

/// partial_output_name of each path, in order.
std::vector<std::string> partial_output_names(const std::vector<std::string>& paths);

}  // namespace spt

// Scene files: JSON (scenes/README.md documents every key) → a finalized Scene. Every defect
// is reported as one LocatedError "file:line:column: what is wrong; expected what".
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/json.h"
#include "scene/scene.h"

namespace spt {

/// Reads a file that a scene refers to (a PLY mesh) by its path relative to the scene file.
/// On success fills `contents` and `display_name` (the name used in messages); on failure
/// returns false with `error` saying why.
using RelativeFileReader = std::function<bool(const std::string& relative_path, std::string& contents,
                                              std::string& display_name, std::string& error)>;

/// Parses and checks a scene; `origin` names the text in messages. Throws LocatedError.
Scene load_scene_text(std::string_view text, const std::string& origin, const std::string& scene_name,
                      SpectralResolution resolution, const RelativeFileReader& read_relative);

/// Loads a scene file from disk; meshes are found relative to its folder. Throws LocatedError.
Scene load_scene_file(const std::string& path, SpectralResolution resolution);

/// Names of the scenes compiled into the program (scenes/*.json), the default "cornell" first.
std::vector<std::string> builtin_scene_names();

/// A built-in scene by name (loaded from its embedded file), or nullopt if there is none.
std::optional<Scene> load_builtin_scene(const std::string& name, SpectralResolution resolution);

}  // namespace spt

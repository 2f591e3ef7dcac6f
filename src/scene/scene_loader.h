// Scene files → a finalized Scene: the file's format picks a reader (scene_readers()), which
// produces a SceneDescription; scene/scene_builder.h builds the Scene from it. Every defect is
// reported as one LocatedError "file:line:column: what is wrong; expected what". Defined in
// scene_readers.cpp.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scene/scene.h"
#include "scene/scene_description.h"

namespace spt {

/// A scene file format: its name in messages, the file name ending that selects it, and its
/// reader (text, origin for messages, scene name → description; throws LocatedError).
struct SceneReader {
    const char* format;
    const char* extension;
    SceneDescription (*read)(std::string_view text, const std::string& origin, const std::string& scene_name);
};

/// Every format the program reads, one row each; the first is used for names without a
/// listed ending.
const std::vector<SceneReader>& scene_readers();

/// Parses and checks a scene; `origin` names the text in messages and its ending picks the
/// reader. Throws LocatedError.
Scene load_scene_text(std::string_view text, const std::string& origin, const std::string& scene_name,
                      SpectralResolution resolution, const RelativeFileReader& read_relative);

/// Loads a scene file from disk; meshes are found relative to its folder. Throws LocatedError.
Scene load_scene_file(const std::string& path, SpectralResolution resolution);

/// Names of the scenes compiled into the program (scenes/*.json), the default "cornell" first.
std::vector<std::string> builtin_scene_names();

/// A built-in scene by name (loaded from its embedded file), or nullopt if there is none.
std::optional<Scene> load_builtin_scene(const std::string& name, SpectralResolution resolution);

}  // namespace spt

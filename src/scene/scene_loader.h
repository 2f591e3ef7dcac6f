// Scene files → a finalized Scene: the file's format picks a reader (scene_readers()), which
// produces a SceneDescription; scene/scene_builder.h builds the Scene from it. Every defect is
// reported as one LocatedError "file:line:column: what is wrong; expected what". Defined in
// scene_readers.cpp.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "scene/scene.h"
#include "scene/scene_description.h"

namespace spt {

/// A scene file format: its name in messages, the file name ending that selects it, and its
/// reader (text, origin for messages, scene name, the reader of the files it refers to →
/// description; throws LocatedError).
struct SceneReader {
    const char* format;
    const char* extension;
    SceneDescription (*read)(std::string_view text, const std::string& origin, const std::string& scene_name,
                             const RelativeFileReader& read_relative);
};

/// Every format the program reads, one row each; the first is used for names without a
/// listed ending.
const std::vector<SceneReader>& scene_readers();

/// Every file a scene was read from, once each: the scene text first (under `origin`), then
/// each mesh, texture and grid it loads (under its display name), with the FNV-1a hash of its
/// bytes (what checkpoints and partial films fingerprint).
using InputFiles = std::vector<std::pair<std::string, std::uint64_t>>;

/// Parses and checks a scene; `origin` names the text in messages and its ending picks the
/// reader. Fills `input_files` when given. Throws LocatedError.
Scene load_scene_text(std::string_view text, const std::string& origin, const std::string& scene_name,
                      SpectralResolution resolution, const RelativeFileReader& read_relative,
                      InputFiles* input_files = nullptr);

/// Loads a scene file from disk; meshes are found relative to its folder. Throws LocatedError.
Scene load_scene_file(const std::string& path, SpectralResolution resolution, InputFiles* input_files = nullptr);

/// A scene's description, unbuilt, with the reader of the files it names and the folder those
/// are relative to on disk (empty for a built-in scene, whose files are compiled in).
struct SceneSource {
    SceneDescription description;
    RelativeFileReader read_relative;
    std::string folder;
};

/// The description of SCENE as the command line names it: a built-in scene's name or a scene
/// file's path; nullopt when it is neither a built-in name nor an existing file. Throws
/// LocatedError for a file that cannot be read or parsed.
std::optional<SceneSource> read_scene_source(const std::string& scene);

/// The scene rendered when the command line names none: a built-in scene's name.
inline constexpr char kDefaultScene[] = "cornell";

/// Names of the scenes compiled into the program (scenes/*.json), kDefaultScene first.
std::vector<std::string> builtin_scene_names();

/// A built-in scene by name (loaded from its embedded file), or nullopt if there is none.
std::optional<Scene> load_builtin_scene(const std::string& name, SpectralResolution resolution,
                                        InputFiles* input_files = nullptr);

}  // namespace spt

// Scenes built into the program, chosen by name on the command line.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace spt {

/// Names of the built-in scenes, the default ("cornell") first.
std::vector<std::string> builtin_scene_names();

/// The named built-in scene (finalized), or nullopt for an unknown name.
std::optional<Scene> make_builtin_scene(const std::string& name, SpectralResolution resolution);

}  // namespace spt

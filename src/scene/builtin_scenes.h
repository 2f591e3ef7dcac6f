// Scenes built into the program (the files scenes/*.json, embedded at build time), chosen by
// name on the command line.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "scene/scene_loader.h"

namespace spt {

/// The named built-in scene (finalized), or nullopt for an unknown name. Names are listed by
/// builtin_scene_names() (scene_loader.h).
std::optional<Scene> make_builtin_scene(const std::string& name, SpectralResolution resolution);

}  // namespace spt

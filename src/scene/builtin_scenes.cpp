// Built-in scenes are the scene files in scenes/, compiled into the program.
#include "scene/builtin_scenes.h"

#include "scene/scene_loader.h"

namespace spt {

std::optional<Scene> make_builtin_scene(const std::string& name, SpectralResolution res) {
    return load_builtin_scene(name, res);
}

}  // namespace spt

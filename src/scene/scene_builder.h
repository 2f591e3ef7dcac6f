// The one step from a scene description to a Scene, for every file format: each entity's
// parameters are checked and turned into the renderer's types, the scene is finalized. Every
// defect is reported as one LocatedError "file:line:column: what is wrong; expected what" at
// the position the description recorded.
#pragma once
#include "scene/scene.h"
#include "scene/scene_description.h"

namespace spt {

/// The finalized Scene that `description` describes; files it names (meshes, images, grids)
/// are read through `read_relative`. Throws LocatedError.
Scene build_scene(const SceneDescription& description, SpectralResolution resolution,
                  const RelativeFileReader& read_relative);

}  // namespace spt

// The typed description of a render (render/checkpoint.h) built from the command line's
// settings and the scene's files, and the render settings read back from one (for merging).
#pragma once
#include <cstdint>
#include <string>

#include "cli/options.h"
#include "render/checkpoint.h"
#include "render/renderer.h"
#include "scene/scene_loader.h"
#include "spectral/observer.h"

namespace spt {

/// Identifies this build of the program: the FNV-1a hash of its executable's bytes (two
/// builds of one source with other compilers or flags may round differently).
std::uint64_t program_build_id();

/// What a checkpoint or partial film of this render records: the settings that change the
/// image, every file the scene read, the sensor curves (`sensor`: null for CIE 1931) and the
/// build.
RenderDescription describe_render(const Options& options, const RenderSettings& settings,
                                  const InputFiles& scene_files, const Observer* sensor);

/// The render settings a description records (what the merged image's metadata reports).
RenderSettings settings_of(const RenderDescription& render);

}  // namespace spt

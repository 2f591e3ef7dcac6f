// A scene description written as a pbrt-v4 scene file (`pathtracer SCENE --export-pbrt
// out.pbrt`). It is written from the description (what the files said), not from the built
// Scene, so named materials, textures and meshes stay named and PLY meshes stay files.
//
// Spectra are written as pbrt-v4 "spectrum" tables of the exact source (every 5 nm over
// 360–830 nm); a light's spectrum carries "scale" = its luminance, because pbrt-v4 normalises
// light spectra to luminance 1 before scaling them. The camera is mirrored (`Scale -1 1 1`
// before LookAt) because pbrt-v4's camera space is left-handed: the image's right is up ×
// forward there, forward × up here. Anything pbrt-v4 cannot express (media, motion, thin
// films, a layered plastic's exact model, infinite planes) is a `#` comment line at its place
// in the output, with the closest pbrt-v4 form where there is one: never dropped silently.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "scene/scene_description.h"

namespace spt {

struct PbrtExportSettings {
    /// Where the .pbrt file will be written: files it refers to are named relative to its
    /// folder, and the Film's output name is its name with ".exr".
    std::string output_path;
    /// Folder on disk that the description's relative file names (meshes, images) are in;
    /// empty when they are not on disk (a built-in scene): then they are read through
    /// `read_relative` and written beside the output.
    std::string scene_folder;
    RelativeFileReader read_relative;
};

struct PbrtExport {
    std::string text;  ///< the pbrt-v4 file
    /// Files to write with it (path, bytes): meshes and images not reachable on disk, copied
    /// beside the output under their own names.
    std::vector<std::pair<std::string, std::string>> files;
};

/// The pbrt-v4 form of `description`. Throws LocatedError for a value the description's own
/// checks would refuse (a malformed spectrum), std::runtime_error for a file it names that
/// cannot be read.
PbrtExport export_pbrt(const SceneDescription& description, const PbrtExportSettings& settings);

/// pbrt-v4's "fov" (the field of view of the image's shorter axis, degrees) of a camera whose
/// vertical field of view is `vfov_degrees` on a width × height image.
double pbrt_fov_degrees(double vfov_degrees, int width, int height);

}  // namespace spt

// pbrt-v4 scene files as a reader: the directives (pbrt-v4's file format documentation) are
// followed with pbrt-v4's graphics state (current transform, attributes, named materials, area
// lights, object instances) and turned into the same SceneDescription the JSON reader makes, so
// the builder and every check after it are the JSON format's. Each value keeps the position it
// was written at, in the file (the scene file or an Include) that wrote it.
//
// pbrt-v4's conventions are kept: its left-handed camera space and `fov` of the shorter image
// axis; RGB values as pbrt-v4 turns them into spectra (a reflectance bounded by 1, an illuminant
// times the D65 white); light spectra normalised to luminance 1 before `scale`, as pbrt-v4's
// lights do; area lights one-sided unless `twosided`; `remaproughness`; its defaults (a 1280×720
// film, 16 samples, maxdepth 5, a diffuse 0.5 material, copper for a conductor).
//
// What this renderer cannot express is never dropped silently: each unsupported directive,
// parameter or type is a warning naming it at its file:line:column (SceneDescription::warnings;
// --strict makes them errors), and a type replaced by the nearest one this renderer has says
// what it was replaced by.
#pragma once
#include <string>
#include <string_view>

#include "scene/scene_description.h"

namespace spt {

/// The description a pbrt-v4 scene text gives. `origin` names the text in messages (the first
/// entry of the file table), `name` is the scene's name; Include/Import and other files are
/// read through `read_relative`. Throws LocatedError.
SceneDescription read_pbrt_scene(std::string_view text, const std::string& origin, const std::string& name,
                                 const RelativeFileReader& read_relative);

}  // namespace spt

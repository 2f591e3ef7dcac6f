// The JSON scene format (scenes/README.md documents every key) as a reader: text → a
// SceneDescription whose values keep the positions where the JSON text wrote them, so every
// later check names file:line:column in the file. It checks only the JSON itself; what the
// keys mean is the create functions' business (scene/scene_builder.h).
#pragma once
#include <cstdint>
#include <string>
#include <string_view>

#include "scene/scene_description.h"

namespace spt {

/// Deepest nesting of arrays and objects a JSON text may have.
inline constexpr int kMaxJsonDepth = 64;

/// The description a JSON scene text gives; `origin` names the text in messages (the first
/// entry of the description's file table), `name` is the scene's name. Throws LocatedError on
/// malformed JSON.
SceneDescription read_json_scene(std::string_view text, const std::string& origin, const std::string& name);

/// A JSON text as a parameter value (objects become dictionaries, arrays lists), each value
/// and key at its line:column in file `file` of the description's file table; `origin` names
/// the text in messages. Throws LocatedError on malformed JSON.
ParamValue read_json_value(std::string_view text, const std::string& origin, std::uint32_t file = 0);

}  // namespace spt

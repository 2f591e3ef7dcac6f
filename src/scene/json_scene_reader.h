// The JSON scene format (scenes/README.md documents every key) as a reader: text → a
// SceneDescription whose values keep the positions of the JSON values, so every later check
// names file:line:column in the file. It checks only the JSON itself; what the keys mean is
// the create functions' business (scene/scene_builder.h).
#pragma once
#include <cstdint>
#include <string>
#include <string_view>

#include "io/json.h"
#include "scene/scene_description.h"

namespace spt {

/// The description a JSON scene text gives; `origin` names the text in messages (the first
/// entry of the description's file table), `name` is the scene's name. Throws LocatedError on
/// malformed JSON.
SceneDescription read_json_scene(std::string_view text, const std::string& origin, const std::string& name);

/// A JSON value as a parameter value (objects become dictionaries, arrays lists), positions
/// kept, each naming `file` of the description's file table.
ParamValue param_value_from_json(const JsonValue& v, std::uint32_t file = 0);

}  // namespace spt

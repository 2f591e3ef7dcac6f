// JSON → SceneDescription: a copy of the value tree with its positions.
#include "scene/json_scene_reader.h"

namespace spt {

ParamValue param_value_from_json(const JsonValue& v, std::uint32_t file) {
    const SourcePos pos = SourcePos::in_file(v.pos(), file);
    switch (v.type()) {
        case JsonValue::Type::Null: return ParamValue::null(pos);
        case JsonValue::Type::Bool: return ParamValue::boolean(v.as_bool(), pos);
        case JsonValue::Type::Number: return ParamValue::number(v.as_number(), pos);
        case JsonValue::Type::String: return ParamValue::string(v.as_string(), pos);
        case JsonValue::Type::Array: {
            std::vector<ParamValue> items;
            items.reserve(v.items().size());
            for (const JsonValue& x : v.items()) items.push_back(param_value_from_json(x, file));
            return ParamValue::list(std::move(items), pos);
        }
        case JsonValue::Type::Object: {
            ParamValue d = ParamValue::dict(pos);  // keys unique: parse_json checked them
            for (std::size_t i = 0; i < v.members().size(); ++i)
                d.add(v.members()[i].first, param_value_from_json(v.members()[i].second, file),
                      SourcePos::in_file(v.key_pos(i), file));
            return d;
        }
    }
    return ParamValue();
}

SceneDescription read_json_scene(std::string_view text, const std::string& origin, const std::string& name) {
    SceneDescription d;
    d.name = name;
    d.root = param_value_from_json(parse_json(text, origin), d.add_file(origin));
    return d;
}

}  // namespace spt

// A scene as its file said it, owned by no file format: each entity (the camera, a material, a
// texture, a medium, a shape, a light) is a parameter bag, a ParamValue dictionary of named,
// typed values, each remembering where it was written so that every check made while the
// scene is built names file:line:column of the file the user wrote. A reader (JSON today:
// scene/json_scene_reader.h) only produces a SceneDescription; scene/scene_builder.h turns any
// description into a Scene by calling each type's create function; tests build descriptions
// in code with the builders below.
//
// The value kinds are the ones the create functions' vocabulary is written in: a spectrum is
// a number, an [r, g, b] list or a dictionary with "type"; a texture reference is the
// dictionary {"texture": NAME}; a point is a list of three numbers. A reader of a format with
// its own typed parameters ("rgb Kd [...]", "texture Kd") translates them to these forms.
#pragma once
#include <cstddef>
#include <functional>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/vec3.h"
#include "io/json.h"  // TextPos, LocatedError: a position in a text and the error that names it

namespace spt {

class ParamValue {
public:
    enum class Kind { Null, Bool, Number, String, List, Dict };

    ParamValue() = default;
    static ParamValue null(TextPos pos = {});
    static ParamValue boolean(bool b, TextPos pos = {});
    static ParamValue number(double x, TextPos pos = {});
    static ParamValue string(std::string s, TextPos pos = {});
    static ParamValue list(std::vector<ParamValue> items, TextPos pos = {});
    /// A list of numbers (a point, a colour, a transform's scale).
    static ParamValue numbers(std::initializer_list<double> xs, TextPos pos = {});
    static ParamValue vec3(const Vec3& v, TextPos pos = {});
    /// An empty dictionary; fill it with set().
    static ParamValue dict(TextPos pos = {});
    /// A dictionary from (key, value) pairs in order.
    static ParamValue dict(std::initializer_list<std::pair<std::string, ParamValue>> members, TextPos pos = {});

    /// Adds (or replaces) the member `key` of a dictionary; `key_pos` is where the key was
    /// written (messages about an unknown key point there). Returns *this.
    ParamValue& set(std::string key, ParamValue value, TextPos key_pos = {});
    /// Adds the member `key`, which the dictionary must not have yet (a reader that has
    /// checked the keys are unique). Returns *this.
    ParamValue& add(std::string key, ParamValue value, TextPos key_pos = {});
    /// Appends to a list. Returns *this.
    ParamValue& push(ParamValue value);

    Kind kind() const { return m_kind; }
    TextPos pos() const { return m_pos; }
    bool is_bool() const { return m_kind == Kind::Bool; }
    bool is_number() const { return m_kind == Kind::Number; }
    bool is_string() const { return m_kind == Kind::String; }
    bool is_array() const { return m_kind == Kind::List; }
    bool is_object() const { return m_kind == Kind::Dict; }

    bool as_bool() const { return m_bool; }
    double as_number() const { return m_number; }
    const std::string& as_string() const { return m_string; }
    /// Elements of a list.
    const std::vector<ParamValue>& items() const { return m_items; }
    /// Members of a dictionary, in the order written (keys are unique).
    const std::vector<std::pair<std::string, ParamValue>>& members() const { return m_members; }
    /// Position of the i-th member's key.
    TextPos key_pos(std::size_t i) const { return m_key_positions[i]; }
    /// Member by key, or nullptr; marks it read (see unread_keys).
    const ParamValue* find(std::string_view key) const;
    /// Keys of a dictionary that no find() has asked for, in the order written.
    std::vector<std::string> unread_keys() const;

    /// Name of a kind for messages ("a number", "an object", ...).
    static const char* kind_name(Kind k);

private:
    Kind m_kind = Kind::Null;
    TextPos m_pos;
    bool m_bool = false;
    double m_number = 0;
    std::string m_string;
    std::vector<ParamValue> m_items;
    std::vector<std::pair<std::string, ParamValue>> m_members;
    std::vector<TextPos> m_key_positions;
    mutable std::vector<bool> m_read;
};

/// Reads a file that a scene refers to (a PLY mesh, an image, a density grid) by its path
/// relative to the scene file. On success fills `contents` and `display_name` (the name used in
/// messages); on failure returns false with `error` saying why.
using RelativeFileReader = std::function<bool(const std::string& relative_path, std::string& contents,
                                              std::string& display_name, std::string& error)>;

/// A whole scene: `origin` names the text in messages, `name` is the scene's name, and `root`
/// is the dictionary of its sections ("camera", "image", "integrator", "background",
/// "textures", "materials", "media", "medium", "shapes", "lights"; scenes/README.md).
struct SceneDescription {
    std::string origin;
    std::string name;
    ParamValue root = ParamValue::dict();
};

}  // namespace spt

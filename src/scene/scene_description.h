// A scene as its files said it, owned by no file format: each entity (the camera, a material, a
// texture, a medium, a shape, a light) is a parameter bag, a ParamValue dictionary of named,
// typed values, each remembering where it was written (SourcePos: which of the description's
// files, and line:column in it) so that every check made while the scene is built names
// file:line:column of the file the user wrote, also when a scene spans several files. A reader (JSON today:
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
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/vec3.h"
#include "io/located_error.h"

namespace spt {

/// Where a value was written: line and column (as TextPos) in the file `file`, an index into
/// the description's file table (SceneDescription::files; 0 is the scene file itself).
struct SourcePos {
    int line = 1, column = 1;
    std::uint32_t file = 0;

    /// The position `at` in file `file`.
    static SourcePos in_file(TextPos at, std::uint32_t file) { return {at.line, at.column, file}; }
    /// Line and column alone, for an error naming the file separately.
    TextPos text_pos() const { return {line, column}; }
};

class ParamValue {
public:
    enum class Kind { Null, Bool, Number, String, List, Dict };

    ParamValue() = default;
    static ParamValue null(SourcePos pos = {});
    static ParamValue boolean(bool b, SourcePos pos = {});
    static ParamValue number(double x, SourcePos pos = {});
    static ParamValue string(std::string s, SourcePos pos = {});
    static ParamValue list(std::vector<ParamValue> items, SourcePos pos = {});
    /// A list of numbers (a point, a colour, a transform's scale).
    static ParamValue numbers(std::initializer_list<double> xs, SourcePos pos = {});
    static ParamValue vec3(const Vec3& v, SourcePos pos = {});
    /// An empty dictionary; fill it with set().
    static ParamValue dict(SourcePos pos = {});
    /// A dictionary from (key, value) pairs in order.
    static ParamValue dict(std::initializer_list<std::pair<std::string, ParamValue>> members, SourcePos pos = {});

    /// Adds (or replaces) the member `key` of a dictionary; `key_pos` is where the key was
    /// written (messages about an unknown key point there), by default where the value was.
    /// Returns *this.
    ParamValue& set(std::string key, ParamValue value, std::optional<SourcePos> key_pos = std::nullopt);
    /// Adds the member `key`, which the dictionary must not have yet (a reader that has
    /// checked the keys are unique). Returns *this.
    ParamValue& add(std::string key, ParamValue value, SourcePos key_pos = {});
    /// Appends to a list. Returns *this.
    ParamValue& push(ParamValue value);

    Kind kind() const { return m_kind; }
    SourcePos pos() const { return m_pos; }
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
    SourcePos key_pos(std::size_t i) const { return m_key_positions[i]; }
    /// Member by key, or nullptr. Marks the member read and records `key` as one the reading
    /// code asks for (present or not): a key nothing reads is unknown (ParamChecker::all_read).
    const ParamValue* find(std::string_view key) const;
    /// Member by key, or nullptr, without marking it read: for code that looks at a key only
    /// to refuse it or to tell forms apart, which must not make the key acceptable.
    const ParamValue* peek(std::string_view key) const;
    /// Whether the i-th member has been read by find().
    bool was_read(std::size_t i) const { return m_read[i]; }
    /// Keys of a dictionary that no find() has asked for, in the order written.
    std::vector<std::string> unread_keys() const;
    /// Every key find() has asked for, present or not, in the order first asked: the keys the
    /// code that read this dictionary accepts.
    const std::vector<std::string>& asked_keys() const { return m_asked; }

    /// Name of a kind for messages ("a number", "an object", ...).
    static const char* kind_name(Kind k);

private:
    Kind m_kind = Kind::Null;
    SourcePos m_pos;
    bool m_bool = false;
    double m_number = 0;
    std::string m_string;
    std::vector<ParamValue> m_items;
    std::vector<std::pair<std::string, ParamValue>> m_members;
    std::vector<SourcePos> m_key_positions;
    mutable std::vector<bool> m_read;
    mutable std::vector<std::string> m_asked;
};

/// Reads a file that a scene refers to (a PLY mesh, an image, a density grid) by its path
/// relative to the scene file. On success fills `contents` and `display_name` (the name used in
/// messages); on failure returns false with `error` saying why.
using RelativeFileReader = std::function<bool(const std::string& relative_path, std::string& contents,
                                              std::string& display_name, std::string& error)>;

/// The names of the files a description was read from, in messages; SourcePos::file indexes it.
using SourceFiles = std::vector<std::string>;

/// A whole scene: `files` names the texts its values came from (the scene file first), `name`
/// is the scene's name, and `root` is the dictionary of its sections ("camera", "image",
/// "integrator", "background", "textures", "materials", "media", "medium", "shapes", "lights";
/// scenes/README.md).
struct SceneDescription {
    SourceFiles files;
    std::string name;
    ParamValue root = ParamValue::dict();
    /// What the reader could not map exactly, each "file:line:column: what" (a pbrt-v4
    /// parameter this renderer does not support, a type replaced by the nearest one).
    std::vector<std::string> warnings;

    /// Adds a file to the table (once: a name already there keeps its index); returns the
    /// index its values' SourcePos::file carries.
    std::uint32_t add_file(const std::string& file_name);
};

}  // namespace spt

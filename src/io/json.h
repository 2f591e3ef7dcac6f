// A strict JSON reader (RFC 8259) whose values remember where they start in the text, so that
// every later check can name file:line:column. No NaN/Infinity, no comments, no trailing
// commas or garbage, no duplicate keys, nesting at most kMaxDepth deep.
#pragma once
#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace spt {

/// Position in a text: 1-based line and column (columns count bytes).
struct TextPos {
    int line = 1, column = 1;
};

/// An error located in a named text; what() is "origin:line:column: message".
class LocatedError : public std::runtime_error {
public:
    LocatedError(const std::string& origin, TextPos pos, const std::string& message)
        : std::runtime_error(origin + ":" + std::to_string(pos.line) + ":" +
                             std::to_string(pos.column) + ": " + message),
          m_origin(origin), m_pos(pos), m_message(message) {}
    const std::string& origin() const { return m_origin; }
    TextPos pos() const { return m_pos; }
    const std::string& message() const { return m_message; }

private:
    std::string m_origin;
    TextPos m_pos;
    std::string m_message;
};

class JsonValue {
public:
    enum class Type { Null, Bool, Number, String, Array, Object };
    static constexpr int kMaxDepth = 64;

    Type type() const { return m_type; }
    TextPos pos() const { return m_pos; }
    bool is_number() const { return m_type == Type::Number; }
    bool is_string() const { return m_type == Type::String; }
    bool is_array() const { return m_type == Type::Array; }
    bool is_object() const { return m_type == Type::Object; }

    bool as_bool() const { return m_bool; }
    double as_number() const { return m_number; }
    const std::string& as_string() const { return m_string; }
    /// Elements of an array.
    const std::vector<JsonValue>& items() const { return m_items; }
    /// Members of an object, in file order (keys are unique).
    const std::vector<std::pair<std::string, JsonValue>>& members() const { return m_members; }
    /// Position of the i-th member's key (its opening quote).
    TextPos key_pos(std::size_t i) const { return m_key_positions[i]; }
    /// Member by key, or nullptr.
    const JsonValue* find(std::string_view key) const;

    /// Name of a type for messages ("a number", "an object", ...).
    static const char* type_name(Type t);

private:
    friend class JsonParser;
    Type m_type = Type::Null;
    TextPos m_pos;
    bool m_bool = false;
    double m_number = 0;
    std::string m_string;
    std::vector<JsonValue> m_items;
    std::vector<std::pair<std::string, JsonValue>> m_members;
    std::vector<TextPos> m_key_positions;
};

/// Parses a whole document; throws LocatedError naming `origin` on any defect.
JsonValue parse_json(std::string_view text, const std::string& origin);

}  // namespace spt

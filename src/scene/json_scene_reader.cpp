// The JSON scene format as a reader: a strict JSON parser (RFC 8259: no NaN/Infinity, no
// comments, no trailing commas or garbage, no duplicate keys, nesting at most kMaxJsonDepth
// deep) that makes the description's values directly, each at the position where it starts.
#include "scene/json_scene_reader.h"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace spt {

namespace {

/// Recursive descent over the text, each value made where it is parsed, at its position.
class JsonParser {
public:
    JsonParser(std::string_view text, const std::string& origin, std::uint32_t file)
        : m_text(text), m_origin(origin), m_file(file) {}

    ParamValue parse_document() {
        skip_space();
        if (at_end()) fail("the file is empty; expected a JSON value");
        ParamValue root = parse_value(0);
        skip_space();
        if (!at_end()) fail("unexpected " + describe_here() + " after the end of the JSON value; expected the end of the file");
        return root;
    }

private:
    std::string_view m_text;
    const std::string& m_origin;
    std::uint32_t m_file;  ///< the text's index in the description's file table
    std::size_t m_i = 0;
    int m_line = 1;
    std::size_t m_line_start = 0;

    bool at_end() const { return m_i >= m_text.size(); }
    char peek() const { return m_text[m_i]; }
    TextPos here() const { return {m_line, static_cast<int>(m_i - m_line_start) + 1}; }

    [[noreturn]] void fail(const std::string& message) const { fail_at(here(), message); }
    [[noreturn]] void fail_at(TextPos pos, const std::string& message) const {
        throw LocatedError(m_origin, pos, message);
    }

    /// The character at the cursor, printable, for messages.
    std::string describe_here() const {
        if (at_end()) return "end of file";
        const unsigned char c = static_cast<unsigned char>(peek());
        if (c >= 0x20 && c < 0x7f) return std::string("'") + static_cast<char>(c) + "'";
        char buf[16];
        std::snprintf(buf, sizeof buf, "byte 0x%02x", c);
        return buf;
    }

    void skip_space() {
        while (!at_end()) {
            const char c = peek();
            if (c == '\n') {
                ++m_i, ++m_line, m_line_start = m_i;
            } else if (c == ' ' || c == '\t' || c == '\r') {
                ++m_i;
            } else {
                break;
            }
        }
    }

    SourcePos source_pos(TextPos at) const { return SourcePos::in_file(at, m_file); }

    ParamValue parse_value(int depth) {
        if (depth >= kMaxJsonDepth)
            fail("nesting deeper than " + std::to_string(kMaxJsonDepth) + " levels; expected a flatter document");
        if (at_end()) fail("unexpected end of file; expected a value");
        const SourcePos pos = source_pos(here());
        const char c = peek();
        if (c == '{') return parse_object(pos, depth);
        if (c == '[') return parse_array(pos, depth);
        if (c == '"') return ParamValue::string(parse_string(), pos);
        if (c == '-' || (c >= '0' && c <= '9')) return ParamValue::number(parse_number(), pos);
        if (match_word("true")) return ParamValue::boolean(true, pos);
        if (match_word("false")) return ParamValue::boolean(false, pos);
        if (match_word("null")) return ParamValue::null(pos);
        if (m_text.substr(m_i, 3) == "NaN" || m_text.substr(m_i, 8) == "Infinity")
            fail("NaN and Infinity are not JSON numbers; expected a finite number");
        fail("unexpected " + describe_here() + "; expected a value (number, string, array, object, true, false or null)");
    }

    bool match_word(std::string_view word) {
        if (m_text.substr(m_i, word.size()) != word) return false;
        m_i += word.size();
        return true;
    }

    void expect(char c, const char* what) {
        skip_space();
        if (at_end() || peek() != c) fail("unexpected " + describe_here() + "; expected " + what);
        ++m_i;
    }

    ParamValue parse_object(SourcePos pos, int depth) {
        ParamValue v = ParamValue::dict(pos);
        ++m_i;  // '{'
        skip_space();
        if (!at_end() && peek() == '}') {
            ++m_i;
            return v;
        }
        while (true) {
            skip_space();
            if (at_end() || peek() != '"')
                fail("unexpected " + describe_here() + "; expected a key in double quotes");
            const TextPos key_pos = here();
            std::string key = parse_string();
            if (v.peek(key)) fail_at(key_pos, "duplicate key \"" + key + "\"; expected each key once per object");
            expect(':', "':' after the key");
            skip_space();
            ParamValue member = parse_value(depth + 1);
            v.add(std::move(key), std::move(member), source_pos(key_pos));
            skip_space();
            if (at_end()) fail("unexpected end of file; expected ',' or '}'");
            if (peek() == ',') {
                ++m_i;
                skip_space();
                if (!at_end() && peek() == '}') fail("trailing comma; expected another key");
                continue;
            }
            if (peek() == '}') {
                ++m_i;
                return v;
            }
            fail("unexpected " + describe_here() + "; expected ',' or '}'");
        }
    }

    ParamValue parse_array(SourcePos pos, int depth) {
        ParamValue v = ParamValue::list({}, pos);
        ++m_i;  // '['
        skip_space();
        if (!at_end() && peek() == ']') {
            ++m_i;
            return v;
        }
        while (true) {
            skip_space();
            v.push(parse_value(depth + 1));
            skip_space();
            if (at_end()) fail("unexpected end of file; expected ',' or ']'");
            if (peek() == ',') {
                ++m_i;
                skip_space();
                if (!at_end() && peek() == ']') fail("trailing comma; expected another value");
                continue;
            }
            if (peek() == ']') {
                ++m_i;
                return v;
            }
            fail("unexpected " + describe_here() + "; expected ',' or ']'");
        }
    }

    unsigned parse_hex4() {
        unsigned u = 0;
        for (int k = 0; k < 4; ++k) {
            if (at_end()) fail("unexpected end of file in a \\u escape; expected 4 hex digits");
            const char c = peek();
            u <<= 4;
            if (c >= '0' && c <= '9') u |= unsigned(c - '0');
            else if (c >= 'a' && c <= 'f') u |= unsigned(c - 'a' + 10);
            else if (c >= 'A' && c <= 'F') u |= unsigned(c - 'A' + 10);
            else fail("unexpected " + describe_here() + " in a \\u escape; expected a hex digit");
            ++m_i;
        }
        return u;
    }

    static void append_utf8(std::string& out, std::uint32_t cp) {
        if (cp < 0x80) {
            out += static_cast<char>(cp);
        } else if (cp < 0x800) {
            out += static_cast<char>(0xc0 | (cp >> 6));
            out += static_cast<char>(0x80 | (cp & 0x3f));
        } else if (cp < 0x10000) {
            out += static_cast<char>(0xe0 | (cp >> 12));
            out += static_cast<char>(0x80 | ((cp >> 6) & 0x3f));
            out += static_cast<char>(0x80 | (cp & 0x3f));
        } else {
            out += static_cast<char>(0xf0 | (cp >> 18));
            out += static_cast<char>(0x80 | ((cp >> 12) & 0x3f));
            out += static_cast<char>(0x80 | ((cp >> 6) & 0x3f));
            out += static_cast<char>(0x80 | (cp & 0x3f));
        }
    }

    std::string parse_string() {
        const TextPos start = here();
        ++m_i;  // opening quote
        std::string out;
        while (true) {
            if (at_end()) fail_at(start, "string never closed; expected a closing '\"'");
            const unsigned char c = static_cast<unsigned char>(peek());
            if (c == '"') {
                ++m_i;
                return out;
            }
            if (c < 0x20)
                fail("control character (" + describe_here() + ") inside a string; expected it escaped");
            if (c != '\\') {
                out += static_cast<char>(c);
                ++m_i;
                continue;
            }
            ++m_i;
            if (at_end()) fail("unexpected end of file after '\\'; expected an escape");
            const char e = peek();
            ++m_i;
            switch (e) {
                case '"': out += '"'; break;
                case '\\': out += '\\'; break;
                case '/': out += '/'; break;
                case 'b': out += '\b'; break;
                case 'f': out += '\f'; break;
                case 'n': out += '\n'; break;
                case 'r': out += '\r'; break;
                case 't': out += '\t'; break;
                case 'u': {
                    std::uint32_t cp = parse_hex4();
                    if (cp >= 0xd800 && cp < 0xdc00) {  // high surrogate: a low one must follow
                        if (m_text.substr(m_i, 2) != "\\u") fail("lone UTF-16 surrogate; expected a \\u low surrogate");
                        m_i += 2;
                        const std::uint32_t lo = parse_hex4();
                        if (lo < 0xdc00 || lo >= 0xe000) fail("invalid UTF-16 surrogate pair; expected a low surrogate");
                        cp = 0x10000 + ((cp - 0xd800) << 10) + (lo - 0xdc00);
                    } else if (cp >= 0xdc00 && cp < 0xe000) {
                        fail("lone UTF-16 low surrogate; expected a valid code point");
                    }
                    append_utf8(out, cp);
                    break;
                }
                default:
                    --m_i;
                    fail("unknown escape '\\" + std::string(1, e) + "'; expected one of \\\" \\\\ \\/ \\b \\f \\n \\r \\t \\uXXXX");
            }
        }
    }

    double parse_number() {
        const std::size_t start = m_i;
        const TextPos pos = here();
        auto digits = [&] {
            std::size_t n = 0;
            while (!at_end() && peek() >= '0' && peek() <= '9') ++m_i, ++n;
            return n;
        };
        if (peek() == '-') ++m_i;
        if (at_end()) fail("unexpected end of file in a number; expected a digit");
        if (peek() == '0') {
            ++m_i;
            if (!at_end() && peek() >= '0' && peek() <= '9')
                fail_at(pos, "number with a leading zero; expected JSON number syntax");
        } else if (digits() == 0) {
            if (m_text.substr(m_i, 8) == "Infinity")
                fail_at(pos, "-Infinity is not a JSON number; expected a finite number");
            fail("unexpected " + describe_here() + " in a number; expected a digit");
        }
        if (!at_end() && peek() == '.') {
            ++m_i;
            if (digits() == 0) fail("unexpected " + describe_here() + " after '.'; expected a digit");
        }
        if (!at_end() && (peek() == 'e' || peek() == 'E')) {
            ++m_i;
            if (!at_end() && (peek() == '+' || peek() == '-')) ++m_i;
            if (digits() == 0) fail("unexpected " + describe_here() + " in an exponent; expected a digit");
        }
        const char* first = m_text.data() + start;
        const char* last = m_text.data() + m_i;
        double value = 0;
        const auto [ptr, ec] = std::from_chars(first, last, value);
        if (ec == std::errc::result_out_of_range) {
            // Underflow is harmless (the value is 0 for every purpose here); overflow is not.
            bool negative_exponent = false;
            for (const char* q = first; q < last; ++q)
                if ((*q == 'e' || *q == 'E') && q + 1 < last && q[1] == '-') negative_exponent = true;
            if (negative_exponent) return 0.0;
            fail_at(pos, "number " + std::string(first, last) + " is too large; expected a finite number of magnitude below 1.8e308");
        }
        if (ec != std::errc() || ptr != last || !std::isfinite(value))
            fail_at(pos, "malformed number '" + std::string(first, last) + "'; expected JSON number syntax");
        return value;
    }
};

}  // namespace

ParamValue read_json_value(std::string_view text, const std::string& origin, std::uint32_t file) {
    return JsonParser(text, origin, file).parse_document();
}

SceneDescription read_json_scene(std::string_view text, const std::string& origin, const std::string& name) {
    SceneDescription d;
    d.name = name;
    d.root = read_json_value(text, origin, d.add_file(origin));
    return d;
}

}  // namespace spt

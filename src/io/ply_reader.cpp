// PLY parsing: the header describes elements and their properties; the body is read either as
// whitespace-separated ASCII tokens or as packed little-endian binary records.
#include "io/ply_reader.h"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <optional>

#include "io/located_error.h"

namespace spt {

namespace {

enum class ScalarType { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };

std::optional<ScalarType> scalar_type(std::string_view name) {
    if (name == "char" || name == "int8") return ScalarType::Int8;
    if (name == "uchar" || name == "uint8") return ScalarType::Uint8;
    if (name == "short" || name == "int16") return ScalarType::Int16;
    if (name == "ushort" || name == "uint16") return ScalarType::Uint16;
    if (name == "int" || name == "int32") return ScalarType::Int32;
    if (name == "uint" || name == "uint32") return ScalarType::Uint32;
    if (name == "float" || name == "float32") return ScalarType::Float32;
    if (name == "double" || name == "float64") return ScalarType::Float64;
    return std::nullopt;
}

std::size_t type_size(ScalarType t) {
    switch (t) {
        case ScalarType::Int8: case ScalarType::Uint8: return 1;
        case ScalarType::Int16: case ScalarType::Uint16: return 2;
        case ScalarType::Int32: case ScalarType::Uint32: case ScalarType::Float32: return 4;
        case ScalarType::Float64: return 8;
    }
    return 1;
}

bool is_integer_type(ScalarType t) { return t != ScalarType::Float32 && t != ScalarType::Float64; }

/// Range of an integer type, as doubles (exact for every type here).
std::pair<double, double> integer_range(ScalarType t) {
    switch (t) {
        case ScalarType::Int8: return {-128.0, 127.0};
        case ScalarType::Uint8: return {0.0, 255.0};
        case ScalarType::Int16: return {-32768.0, 32767.0};
        case ScalarType::Uint16: return {0.0, 65535.0};
        case ScalarType::Int32: return {-2147483648.0, 2147483647.0};
        case ScalarType::Uint32: return {0.0, 4294967295.0};
        default: return {0.0, 0.0};
    }
}

struct Property {
    std::string name;
    ScalarType type = ScalarType::Float32;
    bool is_list = false;
    ScalarType count_type = ScalarType::Uint8;
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> properties;
    int line = 0;
};

/// Splits a header line into words.
std::vector<std::string_view> words(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
        const std::size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
        if (i > start) out.push_back(line.substr(start, i - start));
    }
    return out;
}

/// Reads the body value by value, either as ASCII tokens or as binary records.
class BodyReader {
public:
    BodyReader(std::string_view bytes, std::size_t start, bool binary, int line, const std::string& origin)
        : m_bytes(bytes), m_i(start), m_binary(binary), m_line(line), m_line_start(start), m_origin(origin) {}

    std::size_t remaining() const { return m_bytes.size() - m_i; }
    /// Whether `count` values of type t can still follow (each ASCII value takes ≥ 1 byte).
    bool can_hold(double count, ScalarType t) const {
        return count <= double(remaining()) / double(m_binary ? type_size(t) : 1);
    }

    /// Position for messages: the token's line and column in ASCII; in binary the first body
    /// line, with the byte offset given in the message by fail().
    TextPos pos() const { return {m_line, static_cast<int>(m_i - m_line_start) + 1}; }

    [[noreturn]] void fail(const std::string& message) const { fail_at(pos(), message); }
    [[noreturn]] void fail_at(TextPos p, const std::string& message) const {
        if (m_binary)
            throw LocatedError(m_origin, {p.line, 1},
                               message + " (binary data, byte " + std::to_string(m_i) + " of the file)");
        throw LocatedError(m_origin, p, message);
    }

    double read(ScalarType t, const char* what) {
        return m_binary ? read_binary(t, what) : read_ascii(t, what);
    }

    /// Start of the token about to be read (ASCII), for messages about its value.
    TextPos next_pos() {
        if (!m_binary) skip_space();
        return pos();
    }

    /// In ASCII, anything but whitespace after the last element is an error.
    void expect_end() {
        if (m_binary) {
            if (m_i != m_bytes.size())
                fail(std::to_string(m_bytes.size() - m_i) + " bytes after the last element; expected the end of the file");
            return;
        }
        skip_space();
        if (m_i != m_bytes.size()) fail("unexpected data after the last element; expected the end of the file");
    }

private:
    std::string_view m_bytes;
    std::size_t m_i;
    bool m_binary;
    int m_line;
    std::size_t m_line_start;
    const std::string& m_origin;

    void skip_space() {
        while (m_i < m_bytes.size()) {
            const char c = m_bytes[m_i];
            if (c == '\n') ++m_i, ++m_line, m_line_start = m_i;
            else if (c == ' ' || c == '\t' || c == '\r') ++m_i;
            else break;
        }
    }

    double read_ascii(ScalarType t, const char* what) {
        skip_space();
        if (m_i >= m_bytes.size()) fail(std::string("unexpected end of file; expected ") + what);
        const std::size_t start = m_i;
        while (m_i < m_bytes.size() && !std::strchr(" \t\r\n", m_bytes[m_i])) ++m_i;
        const std::string_view token = m_bytes.substr(start, m_i - start);
        const TextPos p{m_line, static_cast<int>(start - m_line_start) + 1};
        double v = 0;
        const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
        if (ec != std::errc() || ptr != token.data() + token.size())
            fail_at(p, "'" + std::string(token.substr(0, 40)) + "' is not a number; expected " + what);
        if (!std::isfinite(v)) fail_at(p, std::string(what) + " is not finite; expected a finite number");
        if (is_integer_type(t)) {
            if (v != std::floor(v))
                fail_at(p, std::string(what) + " " + std::string(token.substr(0, 40)) + " is not an integer; expected an integer");
            const auto [lo, hi] = integer_range(t);
            if (v < lo || v > hi)
                fail_at(p, std::string(what) + " " + std::string(token.substr(0, 40)) +
                               " does not fit its declared integer type; expected a value from " +
                               std::to_string(static_cast<long long>(lo)) + " to " + std::to_string(static_cast<long long>(hi)));
        }
        return v;
    }

    double read_binary(ScalarType t, const char* what) {
        const std::size_t n = type_size(t);
        if (remaining() < n) fail(std::string("file ends inside ") + what + "; expected " + std::to_string(n) + " more bytes");
        std::uint64_t bits = 0;
        for (std::size_t k = 0; k < n; ++k)
            bits |= std::uint64_t(static_cast<unsigned char>(m_bytes[m_i + k])) << (8 * k);
        m_i += n;
        switch (t) {
            case ScalarType::Int8: return static_cast<std::int8_t>(bits);
            case ScalarType::Uint8: return static_cast<std::uint8_t>(bits);
            case ScalarType::Int16: return static_cast<std::int16_t>(bits);
            case ScalarType::Uint16: return static_cast<std::uint16_t>(bits);
            case ScalarType::Int32: return static_cast<std::int32_t>(bits);
            case ScalarType::Uint32: return static_cast<std::uint32_t>(bits);
            case ScalarType::Float32: return std::bit_cast<float>(static_cast<std::uint32_t>(bits));
            case ScalarType::Float64: return std::bit_cast<double>(bits);
        }
        return 0;
    }
};

[[noreturn]] void header_error(const std::string& origin, int line, const std::string& message) {
    throw LocatedError(origin, {line, 1}, message);
}

}  // namespace

PlyMesh parse_ply(std::string_view bytes, const std::string& origin) {
    // ---------------------------- Header ----------------------------
    std::size_t i = 0;
    int line_no = 0;
    auto next_line = [&]() -> std::optional<std::string_view> {
        if (i >= bytes.size()) return std::nullopt;
        const std::size_t end = bytes.find('\n', i);
        const std::size_t stop = end == std::string_view::npos ? bytes.size() : end;
        std::string_view line = bytes.substr(i, stop - i);
        i = end == std::string_view::npos ? bytes.size() : end + 1;
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        return line;
    };

    auto magic = next_line();
    if (!magic || *magic != "ply") header_error(origin, 1, "not a PLY file; expected the first line to be 'ply'");
    bool binary = false, format_seen = false;
    std::vector<Element> elements;
    bool header_done = false;
    while (!header_done) {
        const auto line = next_line();
        if (!line) header_error(origin, line_no + 1, "file ends inside the header; expected 'end_header'");
        for (char c : *line)
            if (static_cast<unsigned char>(c) < 0x20 && c != '\t')
                header_error(origin, line_no, "control character in the header; expected ASCII text");
        const auto w = words(*line);
        if (w.empty()) continue;
        if (w[0] == "comment" || w[0] == "obj_info") continue;
        if (w[0] == "format") {
            if (w.size() != 3 || w[2] != "1.0")
                header_error(origin, line_no, "malformed format line; expected 'format ascii 1.0' or 'format binary_little_endian 1.0'");
            if (w[1] == "ascii") binary = false;
            else if (w[1] == "binary_little_endian") binary = true;
            else if (w[1] == "binary_big_endian") header_error(origin, line_no, "binary_big_endian PLY is not supported; expected ascii or binary_little_endian");
            else header_error(origin, line_no, "unknown PLY format '" + std::string(w[1]) + "'; expected ascii or binary_little_endian");
            format_seen = true;
        } else if (w[0] == "element") {
            if (w.size() != 3) header_error(origin, line_no, "malformed element line; expected 'element NAME COUNT'");
            Element e;
            e.name = std::string(w[1]);
            e.line = line_no;
            const auto [ptr, ec] = std::from_chars(w[2].data(), w[2].data() + w[2].size(), e.count);
            if (ec != std::errc() || ptr != w[2].data() + w[2].size() || e.count > 0xffffffffull)
                header_error(origin, line_no, "element count '" + std::string(w[2].substr(0, 40)) + "' is not an integer from 0 to 4294967295");
            for (const Element& other : elements)
                if (other.name == e.name) header_error(origin, line_no, "element '" + e.name + "' declared twice; expected it once");
            elements.push_back(std::move(e));
        } else if (w[0] == "property") {
            if (elements.empty()) header_error(origin, line_no, "property before any element; expected 'element' first");
            Property p;
            if (w.size() == 5 && w[1] == "list") {
                const auto ct = scalar_type(w[2]);
                const auto it = scalar_type(w[3]);
                if (!ct || !it || !is_integer_type(*ct))
                    header_error(origin, line_no, "malformed list property; expected 'property list COUNT_TYPE INDEX_TYPE NAME' with an integer count type");
                p.is_list = true, p.count_type = *ct, p.type = *it, p.name = std::string(w[4]);
            } else if (w.size() == 3) {
                const auto t = scalar_type(w[1]);
                if (!t) header_error(origin, line_no, "unknown property type '" + std::string(w[1].substr(0, 40)) + "'; expected char, uchar, short, ushort, int, uint, float or double");
                p.type = *t, p.name = std::string(w[2]);
            } else {
                header_error(origin, line_no, "malformed property line; expected 'property TYPE NAME' or 'property list COUNT_TYPE INDEX_TYPE NAME'");
            }
            for (const Property& other : elements.back().properties)
                if (other.name == p.name) header_error(origin, line_no, "property '" + p.name + "' declared twice; expected it once");
            elements.back().properties.push_back(std::move(p));
        } else if (w[0] == "end_header") {
            header_done = true;
        } else {
            header_error(origin, line_no, "unknown header keyword '" + std::string(w[0].substr(0, 40)) + "'; expected format, element, property, comment or end_header");
        }
    }
    if (!format_seen) header_error(origin, line_no, "no format line in the header; expected 'format ascii 1.0' or 'format binary_little_endian 1.0'");

    // Which element and properties hold the mesh.
    int vertex_element = -1, face_element = -1;
    int prop_xyz[3] = {-1, -1, -1}, prop_indices = -1;
    int prop_attr[5] = {-1, -1, -1, -1, -1};  ///< nx, ny, nz, u, v
    for (int e = 0; e < static_cast<int>(elements.size()); ++e) {
        const Element& el = elements[e];
        if (el.properties.empty() && el.count > 0)
            header_error(origin, el.line, "element '" + el.name + "' has no properties; expected at least one");
        if (el.name == "vertex") {
            vertex_element = e;
            for (int p = 0; p < static_cast<int>(el.properties.size()); ++p)
                for (int a = 0; a < 3; ++a)
                    if (el.properties[p].name == std::string(1, char('x' + a))) {
                        if (el.properties[p].is_list) header_error(origin, el.line, "vertex coordinate is a list; expected a scalar");
                        prop_xyz[a] = p;
                    }
            if (prop_xyz[0] < 0 || prop_xyz[1] < 0 || prop_xyz[2] < 0)
                header_error(origin, el.line, "vertex element without x, y and z properties; expected all three");
            // Optional per-vertex normals (nx ny nz) and surface coordinates (u v, or s t, or
            // texture_u texture_v), used only when complete.
            const char* const names[5][3] = {{"nx", "nx", "nx"}, {"ny", "ny", "ny"}, {"nz", "nz", "nz"},
                                             {"u", "s", "texture_u"}, {"v", "t", "texture_v"}};
            for (int p = 0; p < static_cast<int>(el.properties.size()); ++p)
                for (int a = 0; a < 5; ++a)
                    for (const char* name : names[a])
                        if (el.properties[p].name == name && !el.properties[p].is_list) prop_attr[a] = p;
            if (prop_attr[0] < 0 || prop_attr[1] < 0 || prop_attr[2] < 0)
                prop_attr[0] = prop_attr[1] = prop_attr[2] = -1;
            if (prop_attr[3] < 0 || prop_attr[4] < 0) prop_attr[3] = prop_attr[4] = -1;
        } else if (el.name == "face") {
            if (vertex_element < 0) header_error(origin, el.line, "face element before the vertex element; expected vertices first");
            face_element = e;
            for (int p = 0; p < static_cast<int>(el.properties.size()); ++p)
                if (el.properties[p].name == "vertex_indices" || el.properties[p].name == "vertex_index") {
                    if (!el.properties[p].is_list || !is_integer_type(el.properties[p].type))
                        header_error(origin, el.line, "vertex_indices is not a list of integers; expected 'property list uchar int vertex_indices'");
                    prop_indices = p;
                }
            if (prop_indices < 0) header_error(origin, el.line, "face element without vertex_indices; expected 'property list uchar int vertex_indices'");
        }
    }
    if (vertex_element < 0) header_error(origin, line_no, "no vertex element; expected 'element vertex N'");
    if (face_element < 0) header_error(origin, line_no, "no face element; expected 'element face N'");

    // Every element needs at least this many bytes per item, so counts that cannot fit in the
    // file are rejected before anything is allocated.
    const std::size_t body_bytes = bytes.size() - i;
    for (const Element& el : elements) {
        std::uint64_t min_bytes = 0;
        for (const Property& p : el.properties)
            min_bytes += binary ? type_size(p.is_list ? p.count_type : p.type) : 2;
        if (!binary) min_bytes -= 1;  // the last token needs no separator
        if (min_bytes > 0 && el.count > (body_bytes + 1) / min_bytes)
            header_error(origin, el.line, "element '" + el.name + "' declares " + std::to_string(el.count) +
                              " items but the file has only " + std::to_string(body_bytes) +
                              " bytes of data; expected a count that fits the file");
    }

    // ---------------------------- Body ----------------------------
    PlyMesh mesh;
    BodyReader body(bytes, i, binary, line_no + 1, origin);
    mesh.positions.reserve(elements[vertex_element].count);
    mesh.triangles.reserve(elements[face_element].count);
    const std::uint64_t vertex_count = elements[vertex_element].count;
    for (int e = 0; e < static_cast<int>(elements.size()); ++e) {
        const Element& el = elements[e];
        for (std::uint64_t item = 0; item < el.count; ++item) {
            double xyz[3] = {0, 0, 0};
            double attr[5] = {0, 0, 0, 0, 0};
            for (int p = 0; p < static_cast<int>(el.properties.size()); ++p) {
                const Property& prop = el.properties[p];
                if (!prop.is_list) {
                    const TextPos pos = body.next_pos();
                    const double v = body.read(prop.type, "a property value");
                    if (e == vertex_element)
                        for (int a = 0; a < 3; ++a)
                            if (p == prop_xyz[a]) {
                                if (!std::isfinite(v) || std::fabs(v) > 3.0e38)
                                    body.fail_at(pos, "vertex " + std::to_string(item) + " coordinate is not a finite float; expected a finite number");
                                xyz[a] = v;
                            }
                    if (e == vertex_element)
                        for (int a = 0; a < 5; ++a)
                            if (p == prop_attr[a]) {
                                if (!std::isfinite(v) || std::fabs(v) > 3.0e38)
                                    body.fail_at(pos, "vertex " + std::to_string(item) + " " + prop.name +
                                                          " is not a finite float; expected a finite number");
                                attr[a] = v;
                            }
                    continue;
                }
                const TextPos count_pos = body.next_pos();
                const double count = body.read(prop.count_type, "a list length");
                if (count < 0 || !body.can_hold(count, prop.type))
                    body.fail_at(count_pos, "list length " + std::to_string(static_cast<long long>(count)) +
                                                " is negative or needs more data than the rest of the file holds; expected a valid length");
                const bool is_face = e == face_element && p == prop_indices;
                if (is_face && count < 3)
                    body.fail_at(count_pos, "face " + std::to_string(item) + " has " + std::to_string(static_cast<int>(count)) + " vertices; expected at least 3");
                std::uint32_t first = 0, previous = 0;
                for (std::uint64_t k = 0; k < static_cast<std::uint64_t>(count); ++k) {
                    const TextPos pos = body.next_pos();
                    const double v = body.read(prop.type, "a list value");
                    if (!is_face) continue;
                    if (v < 0 || v >= double(vertex_count))
                        body.fail_at(pos, "face " + std::to_string(item) + " refers to vertex " + std::to_string(static_cast<long long>(v)) +
                                              "; expected an index from 0 to " + std::to_string(vertex_count) + " - 1");
                    const auto index = static_cast<std::uint32_t>(v);
                    // Fan triangulation: (v0, v(k-1), vk) for k ≥ 2.
                    if (k == 0) first = index;
                    else if (k >= 2) mesh.triangles.push_back({first, previous, index});
                    previous = index;
                }
            }
            if (e == vertex_element) {
                mesh.positions.push_back({static_cast<float>(xyz[0]), static_cast<float>(xyz[1]), static_cast<float>(xyz[2])});
                if (prop_attr[0] >= 0)
                    mesh.normals.push_back(
                        {static_cast<float>(attr[0]), static_cast<float>(attr[1]), static_cast<float>(attr[2])});
                if (prop_attr[3] >= 0) mesh.uvs.push_back({static_cast<float>(attr[3]), static_cast<float>(attr[4])});
            }
        }
    }
    body.expect_end();
    return mesh;
}

}  // namespace spt

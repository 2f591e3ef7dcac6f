#include "scene/pbrt_scene_reader.h"

#include <array>
#include <charconv>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "core/text.h"
#include "geometry/dvec3.h"
#include "io/image_writer.h"
#include "scene/pbrt_params.h"
#include "scene/pbrt_tokenizer.h"

namespace spt {

namespace {

// ------------------------------------------------------------------ transforms

/// A 4×4 matrix acting on column vectors (p' = M·p), pbrt-v4's convention inside the program.
using Matrix = std::array<std::array<double, 4>, 4>;

Matrix identity() {
    Matrix m{};
    for (int i = 0; i < 4; ++i) m[i][i] = 1;
    return m;
}

Matrix operator*(const Matrix& a, const Matrix& b) {
    Matrix c{};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            for (int k = 0; k < 4; ++k) c[i][j] += a[i][k] * b[k][j];
    return c;
}

Matrix transpose(const Matrix& m) {
    Matrix t{};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) t[i][j] = m[j][i];
    return t;
}

/// The inverse by Gauss–Jordan elimination with partial pivoting; nullopt when singular.
std::optional<Matrix> inverse(const Matrix& m) {
    Matrix a = m, inv = identity();
    double scale = 0;
    for (const auto& row : m)
        for (double x : row) scale = std::max(scale, std::fabs(x));
    for (int c = 0; c < 4; ++c) {
        int pivot = c;
        for (int r = c + 1; r < 4; ++r)
            if (std::fabs(a[r][c]) > std::fabs(a[pivot][c])) pivot = r;
        if (!(std::fabs(a[pivot][c]) > 1e-12 * scale)) return std::nullopt;
        std::swap(a[c], a[pivot]);
        std::swap(inv[c], inv[pivot]);
        const double d = 1 / a[c][c];
        for (int j = 0; j < 4; ++j) a[c][j] *= d, inv[c][j] *= d;
        for (int r = 0; r < 4; ++r) {
            if (r == c || a[r][c] == 0) continue;
            const double f = a[r][c];
            for (int j = 0; j < 4; ++j) a[r][j] -= f * a[c][j], inv[r][j] -= f * inv[c][j];
        }
    }
    return inv;
}

DVec3 apply_point(const Matrix& m, const DVec3& p) {
    return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3], m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
            m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
}

DVec3 apply_vector(const Matrix& m, const DVec3& v) {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
}

DVec3 column(const Matrix& m, int j) { return {m[0][j], m[1][j], m[2][j]}; }

double det3(const Matrix& m) { return dot(column(m, 0), cross(column(m, 1), column(m, 2))); }

/// The uniform scale of a rotation-and-scale matrix, or nullopt when its axes differ in length
/// or are not perpendicular (spheres, disks and cylinders take no other).
std::optional<double> uniform_scale(const Matrix& m) {
    const DVec3 c[3] = {column(m, 0), column(m, 1), column(m, 2)};
    const double l = length(c[0]);
    const double tol = 1e-5 * l;
    for (int i = 0; i < 3; ++i) {
        if (std::fabs(length(c[i]) - l) > tol) return std::nullopt;
        if (std::fabs(dot(c[i], c[(i + 1) % 3])) > tol * l) return std::nullopt;
    }
    return l > 0 ? std::optional<double>(l) : std::nullopt;
}

Matrix translate(const DVec3& t) {
    Matrix m = identity();
    m[0][3] = t.x, m[1][3] = t.y, m[2][3] = t.z;
    return m;
}

Matrix scale(const DVec3& s) {
    Matrix m = identity();
    m[0][0] = s.x, m[1][1] = s.y, m[2][2] = s.z;
    return m;
}

/// A right-handed rotation by `degrees` about `axis` (pbrt-v4's Rotate).
Matrix rotate(double degrees, DVec3 axis) {
    axis = normalize(axis);
    const double t = degrees * kPiDouble / 180, s = std::sin(t), c = std::cos(t);
    const double x = axis.x, y = axis.y, z = axis.z;
    Matrix m = identity();
    m[0][0] = x * x + (1 - x * x) * c, m[0][1] = x * y * (1 - c) - z * s, m[0][2] = x * z * (1 - c) + y * s;
    m[1][0] = x * y * (1 - c) + z * s, m[1][1] = y * y + (1 - y * y) * c, m[1][2] = y * z * (1 - c) - x * s;
    m[2][0] = x * z * (1 - c) - y * s, m[2][1] = y * z * (1 - c) + x * s, m[2][2] = z * z + (1 - z * z) * c;
    return m;
}

// ------------------------------------------------------------------ description values

ParamValue num(double x, SourcePos pos) { return ParamValue::number(x, pos); }
ParamValue str(std::string s, SourcePos pos) { return ParamValue::string(std::move(s), pos); }
ParamValue point(const DVec3& p, SourcePos pos) { return ParamValue::numbers({p.x, p.y, p.z}, pos); }

ParamValue list_of(const std::vector<double>& xs, SourcePos pos) {
    std::vector<ParamValue> items;
    items.reserve(xs.size());
    for (double x : xs) items.push_back(num(x, pos));
    return ParamValue::list(std::move(items), pos);
}

/// The description's {"matrix": [16 numbers, row-major]}.
ParamValue matrix_transform(const Matrix& m, SourcePos pos) {
    std::vector<double> xs;
    for (const auto& row : m)
        for (double x : row) xs.push_back(x);
    return ParamValue::dict({{"matrix", list_of(xs, pos)}}, pos);
}

/// A spectrum scaled so that its luminance is `luminance` (pbrt-v4's lights divide by the
/// spectrum's photometric integral).
ParamValue normalized(ParamValue spectrum, double luminance, SourcePos pos) {
    return ParamValue::dict({{"type", str("normalized", pos)}, {"spectrum", std::move(spectrum)}, {"luminance", num(luminance, pos)}},
                            pos);
}

ParamValue product(std::vector<ParamValue> factors, double scale, SourcePos pos) {
    return ParamValue::dict(
        {{"type", str("product", pos)}, {"factors", ParamValue::list(std::move(factors), pos)}, {"scale", num(scale, pos)}}, pos);
}

ParamValue d65(SourcePos pos) {
    return ParamValue::dict({{"type", str("illuminant", pos)}, {"name", str("D65", pos)}}, pos);
}

/// pbrt-v4's RGBUnboundedSpectrum: the fit of rgb / (2·max) times 2·max.
ParamValue unbounded_rgb(double r, double g, double b, SourcePos pos) {
    const double m = 2 * std::max({r, g, b});
    if (m == 0) return num(0, pos);
    return ParamValue::dict({{"type", str("rgb", pos)}, {"value", ParamValue::numbers({r / m, g / m, b / m}, pos)}, {"scale", num(m, pos)}},
                            pos);
}

/// How a spectrum parameter is used, which decides how pbrt-v4 turns RGB into a spectrum.
enum class Role { Albedo, Unbounded, Illuminant };

const char* const kDirectives[] = {
    "Accelerator", "AttributeBegin", "AttributeEnd", "Attribute", "ActiveTransform", "AreaLightSource", "Camera", "ColorSpace",
    "ConcatTransform", "CoordinateSystem", "CoordSysTransform", "Film", "Identity", "Import", "Include", "Integrator",
    "LightSource", "LookAt", "MakeNamedMaterial", "MakeNamedMedium", "Material", "MediumInterface", "NamedMaterial",
    "ObjectBegin", "ObjectEnd", "ObjectInstance", "Option", "PixelFilter", "ReverseOrientation", "Rotate", "Sampler",
    "Scale", "Shape", "Texture", "Transform", "TransformBegin", "TransformEnd", "TransformTimes", "Translate",
    "WorldBegin", "WorldEnd"};

struct AreaLight {
    ParamValue emission;
    bool two_sided = false;
    int id = 0;
};

struct GraphicsState {
    Matrix ctm[2] = {identity(), identity()};  ///< at the shutter's start and end
    bool active[2] = {true, true};             ///< which of them the transform directives change
    bool reverse_orientation = false;
    std::string material;  ///< a description material's name; empty: pbrt-v4's default diffuse
    std::optional<AreaLight> area_light;
};

/// A shape as its directive gave it, kept for an object definition or made at once.
struct ShapeRecord {
    std::string type;
    PbrtParams params;
    GraphicsState state;
    SourcePos pos;
    std::vector<Matrix> placements;  ///< where an object's instances put it
    bool warned = false;
};

struct TextureInfo {
    bool supported = false;
    std::optional<ParamValue> constant;  ///< a "constant" texture's value
};

bool is_mesh_type(const std::string& t) {
    return t == "trianglemesh" || t == "plymesh" || t == "bilinearmesh" || t == "loopsubdiv";
}

class PbrtReader {
public:
    PbrtReader(SceneDescription& d, const RelativeFileReader& read_relative) : m_d(d), m_read_relative(read_relative) {}

    void parse(std::string_view text, const std::string& origin, int depth) {
        PbrtTokenizer tokens(text, origin);
        const std::uint32_t file = m_d.add_file(origin);
        while (std::optional<PbrtToken> t = tokens.next()) directive(*t, tokens, file, depth);
    }

    void finish(SourcePos end) {
        if (m_object) fail(m_object_pos, "ObjectBegin \"" + *m_object + "\" without ObjectEnd; expected ObjectEnd before the end of the scene");
        if (!m_attributes.empty()) fail(m_attribute_pos.back(), "AttributeBegin without a matching AttributeEnd; expected one before the end of the scene");
        for (auto& [name, records] : m_objects)
            for (ShapeRecord& r : records)
                if (!r.placements.empty()) make_shape(r, r.placements);
        ParamValue& root = m_d.root;
        root = ParamValue::dict(end);
        root.set("camera", m_camera ? *m_camera : default_camera(end));
        ParamValue image = ParamValue::dict(end);
        image.set("width", num(m_width, end)).set("height", num(m_height, end)).set("spp", num(m_spp, end));
        if (m_output) image.set("file", *m_output);
        root.set("image", std::move(image));
        root.set("integrator", m_integrator ? *m_integrator
                                            : ParamValue::dict({{"type", str("path", end)}, {"max_depth", num(5, end)}}, end));
        if (m_background) root.set("background", *m_background);
        if (!m_textures.members().empty()) root.set("textures", m_textures);
        if (!m_materials.members().empty()) root.set("materials", m_materials);
        root.set("shapes", m_shapes);
        if (!m_lights.items().empty()) root.set("lights", m_lights);
    }

private:
    SceneDescription& m_d;
    const RelativeFileReader& m_read_relative;
    GraphicsState m_state;
    std::vector<GraphicsState> m_attributes;
    std::vector<SourcePos> m_attribute_pos;
    std::vector<std::array<Matrix, 2>> m_transform_stack;
    std::map<std::string, std::array<Matrix, 2>> m_coordinate_systems;
    std::set<std::string> m_including;
    bool m_in_world = false;

    std::optional<ParamValue> m_camera;
    int m_width = 1280, m_height = 720, m_spp = 16;
    std::optional<ParamValue> m_output;  ///< the Film's filename
    std::optional<ParamValue> m_integrator;
    std::optional<ParamValue> m_background;
    ParamValue m_textures = ParamValue::dict();
    ParamValue m_materials = ParamValue::dict();
    ParamValue m_shapes = ParamValue::list({});
    ParamValue m_lights = ParamValue::list({});
    std::map<std::string, TextureInfo> m_texture_info;
    std::set<std::string> m_interface_materials;  ///< names of "interface" materials: no surface
    std::map<std::pair<std::string, int>, std::string> m_emitting_materials;
    int m_anonymous = 0, m_area_lights = 0;

    std::optional<std::string> m_object;
    SourcePos m_object_pos;
    std::map<std::string, std::vector<ShapeRecord>> m_objects;

    [[noreturn]] void fail(SourcePos pos, const std::string& message) const {
        throw LocatedError(pos.file < m_d.files.size() ? m_d.files[pos.file] : "(unnamed file)", pos.text_pos(), message);
    }
    void warn(SourcePos pos, const std::string& message) {
        const std::string file = pos.file < m_d.files.size() ? m_d.files[pos.file] : "(unnamed file)";
        m_d.warnings.push_back(file + ":" + std::to_string(pos.line) + ":" + std::to_string(pos.column) + ": " + message);
    }
    void warn_unused(const PbrtParams& params, const std::string& what) {
        for (const PbrtParam* p : params.unused())
            warn(p->pos, "parameter \"" + p->type + " " + p->name + "\" of " + what + " is not supported; ignored");
    }

    // -------------------------------------------------------------- tokens

    static std::string expect_string(PbrtTokenizer& tokens, std::uint32_t file, const std::string& what,
                                     SourcePos* where = nullptr) {
        const std::optional<PbrtToken> t = tokens.next();
        if (!t || t->kind != PbrtToken::Kind::String)
            throw LocatedError(tokens.origin(), t ? t->pos : tokens.here(),
                               (t ? "'" + std::string(t->text) + "'" : std::string("end of file")) + "; expected " + what +
                                   " in double quotes");
        if (where) *where = SourcePos::in_file(t->pos, file);
        return pbrt_unescape(t->text);
    }

    /// `count` numbers, bare or in brackets.
    static std::vector<double> expect_numbers(PbrtTokenizer& tokens, std::size_t count, const std::string& directive) {
        const std::optional<PbrtToken> first = tokens.peek();
        const bool bracket = first && first->kind == PbrtToken::Kind::OpenBracket;
        if (bracket) tokens.next();
        std::vector<double> xs;
        while (xs.size() < count) {
            const std::optional<PbrtToken> t = tokens.next();
            double x = 0;
            bool ok = t && t->kind == PbrtToken::Kind::Word;
            if (ok) {
                const char* b = t->text.data();
                const char* e = b + t->text.size();
                if (b != e && *b == '+') ++b;
                const auto [p, ec] = std::from_chars(b, e, x);
                ok = ec == std::errc() && p == e && std::isfinite(x);
            }
            if (!ok)
                throw LocatedError(tokens.origin(), t ? t->pos : tokens.here(),
                                   directive + " takes " + std::to_string(count) + " numbers; got " +
                                       (t ? "'" + std::string(t->text) + "'" : std::string("the end of the file")) +
                                       " after " + std::to_string(xs.size()) + "; expected a finite number");
            xs.push_back(x);
        }
        if (bracket) {
            const std::optional<PbrtToken> t = tokens.next();
            if (!t || t->kind != PbrtToken::Kind::CloseBracket)
                throw LocatedError(tokens.origin(), t ? t->pos : tokens.here(),
                                   directive + " takes " + std::to_string(count) + " numbers; expected ']' after them");
        }
        return xs;
    }

    // -------------------------------------------------------------- directives

    void apply(const Matrix& m, bool replace = false) {
        for (int i = 0; i < 2; ++i)
            if (m_state.active[i]) m_state.ctm[i] = replace ? m : m_state.ctm[i] * m;
    }

    void directive(const PbrtToken& t, PbrtTokenizer& tokens, std::uint32_t file, int depth) {
        const SourcePos pos = SourcePos::in_file(t.pos, file);
        if (t.kind != PbrtToken::Kind::Word)
            fail(pos, "unexpected " + std::string(t.kind == PbrtToken::Kind::String ? "string" : "'" + std::string(t.text) + "'") +
                          "; expected a directive such as Shape or WorldBegin");
        const std::string name(t.text);
        const auto params = [&] { return PbrtParams::read(tokens, file); };
        const auto type = [&](const char* what) { return expect_string(tokens, file, what); };

        if (name == "Translate") {
            const auto v = expect_numbers(tokens, 3, name);
            apply(translate({v[0], v[1], v[2]}));
        } else if (name == "Scale") {
            const auto v = expect_numbers(tokens, 3, name);
            apply(scale({v[0], v[1], v[2]}));
        } else if (name == "Rotate") {
            const auto v = expect_numbers(tokens, 4, name);
            if (v[1] == 0 && v[2] == 0 && v[3] == 0) fail(pos, "Rotate about the axis (0, 0, 0); expected a non-zero axis");
            apply(rotate(v[0], {v[1], v[2], v[3]}));
        } else if (name == "LookAt") {
            const auto v = expect_numbers(tokens, 9, name);
            apply(look_at({v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}, pos));
        } else if (name == "Transform" || name == "ConcatTransform") {
            const auto v = expect_numbers(tokens, 16, name);
            Matrix m{};
            for (int i = 0; i < 16; ++i) m[i / 4][i % 4] = v[i];
            m = transpose(m);  // the file lists the matrix column by column
            if (m[3][0] != 0 || m[3][1] != 0 || m[3][2] != 0 || m[3][3] == 0)
                fail(pos, name + " is a projective matrix; expected an affine one (last column of the file's values 0 0 0 w)");
            if (m[3][3] != 1)
                for (auto& row : m)
                    for (double& x : row) x /= m[3][3];
            if (!inverse(m)) fail(pos, name + " is a singular matrix; expected an invertible transform");
            apply(m, name == "Transform");
        } else if (name == "Identity") {
            apply(identity(), true);
        } else if (name == "CoordinateSystem") {
            m_coordinate_systems[type("a name")] = {m_state.ctm[0], m_state.ctm[1]};
        } else if (name == "CoordSysTransform") {
            SourcePos at;
            const std::string n = expect_string(tokens, file, "a name", &at);
            const auto it = m_coordinate_systems.find(n);
            if (it == m_coordinate_systems.end()) fail(at, "unknown coordinate system \"" + n + "\"; expected one named by CoordinateSystem or \"camera\"");
            m_state.ctm[0] = it->second[0], m_state.ctm[1] = it->second[1];
        } else if (name == "ActiveTransform") {
            const std::optional<PbrtToken> w = tokens.next();
            const std::string which = w && w->kind == PbrtToken::Kind::Word ? std::string(w->text) : "";
            if (which == "All") m_state.active[0] = m_state.active[1] = true;
            else if (which == "StartTime") m_state.active[0] = true, m_state.active[1] = false;
            else if (which == "EndTime") m_state.active[0] = false, m_state.active[1] = true;
            else fail(pos, "ActiveTransform " + which + "; expected All, StartTime or EndTime");
        } else if (name == "TransformTimes") {
            const auto v = expect_numbers(tokens, 2, name);
            if (v[0] != 0 || v[1] != 1) warn(pos, "TransformTimes is not supported (motion is not read from pbrt files); ignored");
        } else if (name == "ReverseOrientation") {
            m_state.reverse_orientation = !m_state.reverse_orientation;
        } else if (name == "AttributeBegin") {
            m_attributes.push_back(m_state);
            m_attribute_pos.push_back(pos);
        } else if (name == "AttributeEnd") {
            if (m_attributes.empty()) fail(pos, "AttributeEnd without AttributeBegin; expected a matching AttributeBegin before it");
            m_state = m_attributes.back();
            m_attributes.pop_back();
            m_attribute_pos.pop_back();
        } else if (name == "TransformBegin") {
            m_transform_stack.push_back({m_state.ctm[0], m_state.ctm[1]});
        } else if (name == "TransformEnd") {
            if (m_transform_stack.empty()) fail(pos, "TransformEnd without TransformBegin; expected a matching TransformBegin before it");
            m_state.ctm[0] = m_transform_stack.back()[0], m_state.ctm[1] = m_transform_stack.back()[1];
            m_transform_stack.pop_back();
        } else if (name == "Attribute") {
            const std::string target = type("a target (\"shape\", \"light\", \"material\", \"medium\" or \"texture\")");
            params();
            warn(pos, "Attribute \"" + target + "\" (default parameters) is not supported; ignored");
        } else if (name == "Option") {
            const PbrtParams p = params();
            for (const PbrtParam& q : p.all()) warn(q.pos, "Option \"" + q.name + "\" is not supported; ignored");
        } else if (name == "ColorSpace") {
            SourcePos at;
            const std::string cs = expect_string(tokens, file, "a colour space name", &at);
            if (cs != "srgb") warn(at, "ColorSpace \"" + cs + "\" is not supported (RGB values are read as linear sRGB); ignored");
        } else if (name == "Camera") {
            const std::string kind = type("a camera type");
            camera(kind, params(), pos);
        } else if (name == "Film") {
            const std::string kind = type("a film type");
            film(kind, params(), pos);
        } else if (name == "Sampler") {
            const std::string kind = type("a sampler type");
            sampler(kind, params(), pos);
        } else if (name == "Integrator") {
            const std::string kind = type("an integrator type");
            integrator(kind, params(), pos);
        } else if (name == "Accelerator") {
            // How pbrt-v4 builds its BVH or k-d tree: the renderer builds its own; the image is the same.
            type("an accelerator type");
            params();
        } else if (name == "PixelFilter") {
            const std::string f = type("a filter type");
            const PbrtParams p = params();
            // A box of radius ½ is this renderer's film: each pixel the mean over its area.
            if (f != "box" || p.get_float("xradius", 0.5) != 0.5 || p.get_float("yradius", 0.5) != 0.5)
                warn(pos, "PixelFilter \"" + f + "\" is not supported (each pixel is the mean over its area); ignored");
        } else if (name == "WorldBegin") {
            if (m_in_world) fail(pos, "WorldBegin inside the world; expected it once");
            m_in_world = true;
            m_state.ctm[0] = m_state.ctm[1] = identity();
            m_coordinate_systems["world"] = {identity(), identity()};
        } else if (name == "WorldEnd") {
            // pbrt-v3's end of the world; pbrt-v4 ends it at the end of the file.
        } else if (name == "Include" || name == "Import") {
            SourcePos at;
            const std::string f = expect_string(tokens, file, "a file name", &at);
            include(f, at, depth);
        } else if (name == "MakeNamedMaterial") {
            SourcePos at;
            const std::string n = expect_string(tokens, file, "a material name", &at);
            PbrtParams p = params();
            const std::string kind = p.get_string("type", "");
            if (kind.empty()) fail(at, "MakeNamedMaterial \"" + n + "\" has no \"string type\"; expected the material's type");
            define_material(n, kind, p, at);
        } else if (name == "Material") {
            SourcePos at;
            const std::string kind = expect_string(tokens, file, "a material type", &at);
            const std::string n = "@" + std::to_string(++m_anonymous);
            define_material(n, kind, params(), at);
            m_state.material = n;
        } else if (name == "NamedMaterial") {
            SourcePos at;
            const std::string n = expect_string(tokens, file, "a material name", &at);
            if (!m_materials.peek(n) && !m_interface_materials.count(n))
                fail(at, "unknown material \"" + n + "\"; expected one defined by MakeNamedMaterial before it");
            m_state.material = n;
        } else if (name == "Texture") {
            SourcePos at;
            const std::string n = expect_string(tokens, file, "a texture name", &at);
            const std::string kind = type("\"spectrum\" or \"float\"");
            const std::string cls = type("a texture class");
            const PbrtParams p = params();
            texture(n, kind, cls, p, at);
        } else if (name == "LightSource") {
            const std::string kind = type("a light type");
            light(kind, params(), pos);
        } else if (name == "AreaLightSource") {
            const std::string kind = type("an area light type");
            area_light(kind, params(), pos);
        } else if (name == "Shape") {
            ShapeRecord r;
            r.type = type("a shape type");
            r.params = params();
            r.state = m_state;
            r.pos = pos;
            if (m_object) {
                m_objects[*m_object].push_back(std::move(r));
            } else {
                make_shape(r, {m_state.ctm[0]});
            }
        } else if (name == "ObjectBegin") {
            SourcePos at;
            const std::string n = expect_string(tokens, file, "an object name", &at);
            if (m_object) fail(at, "ObjectBegin inside the object \"" + *m_object + "\"; expected ObjectEnd first");
            if (m_objects.count(n)) fail(at, "object \"" + n + "\" defined twice; expected each name once");
            m_object = n;
            m_object_pos = at;
            m_objects[n];
            m_attributes.push_back(m_state);
            m_attribute_pos.push_back(pos);
        } else if (name == "ObjectEnd") {
            if (!m_object) fail(pos, "ObjectEnd without ObjectBegin; expected a matching ObjectBegin before it");
            m_object.reset();
            m_state = m_attributes.back();
            m_attributes.pop_back();
            m_attribute_pos.pop_back();
        } else if (name == "ObjectInstance") {
            SourcePos at;
            const std::string n = expect_string(tokens, file, "an object name", &at);
            if (m_object) fail(at, "ObjectInstance inside an object definition; expected it outside ObjectBegin/ObjectEnd");
            const auto it = m_objects.find(n);
            if (it == m_objects.end()) fail(at, "unknown object \"" + n + "\"; expected one defined by ObjectBegin before it");
            for (ShapeRecord& r : it->second) {
                const Matrix placed = m_state.ctm[0] * r.state.ctm[0];
                if (is_mesh_type(r.type) && !r.state.area_light) r.placements.push_back(placed);
                else make_shape(r, {placed});
            }
        } else if (name == "MakeNamedMedium") {
            const std::string n = type("a medium name");
            params();
            warn(pos, "MakeNamedMedium \"" + n + "\": media are not read from pbrt files yet; ignored");
        } else if (name == "MediumInterface") {
            type("a medium name");
            if (tokens.peek() && tokens.peek()->kind == PbrtToken::Kind::String) type("a medium name");
            warn(pos, "MediumInterface: media are not read from pbrt files yet; ignored");
        } else {
            std::string known;
            for (const char* d : kDirectives) known += (known.empty() ? "" : ", ") + std::string(d);
            fail(pos, "unknown directive '" + name + "'; expected one of " + known);
        }
    }

    /// pbrt-v4's LookAt: camera space with +z towards `look`, +y up and +x = up × forward.
    Matrix look_at(const DVec3& eye, const DVec3& look, const DVec3& up, SourcePos pos) const {
        const DVec3 dir = look - eye;
        if (length(dir) == 0) fail(pos, "LookAt with the eye at the point looked at; expected two different points");
        const DVec3 d = normalize(dir);
        if (length(up) == 0 || length(cross(normalize(up), d)) < 1e-9)
            fail(pos, "LookAt with the up vector along the view direction; expected an up vector across it");
        const DVec3 right = normalize(cross(normalize(up), d));
        const DVec3 new_up = cross(d, right);
        Matrix world_from_camera = identity();
        const DVec3 cols[4] = {right, new_up, d, eye};
        for (int j = 0; j < 4; ++j) world_from_camera[0][j] = cols[j].x, world_from_camera[1][j] = cols[j].y, world_from_camera[2][j] = cols[j].z;
        return *inverse(world_from_camera);
    }

    void include(const std::string& file_name, SourcePos at, int depth) {
        if (depth >= 32) fail(at, "Include nested more than 32 deep; expected a shallower chain of files");
        std::string contents, display, why;
        if (!m_read_relative(file_name, contents, display, why))
            fail(at, "cannot read \"" + file_name + "\": " + why + "; expected a readable file relative to the scene file");
        if (m_including.count(display)) fail(at, "\"" + file_name + "\" includes itself; expected no cycle of Include");
        m_including.insert(display);
        parse(contents, display, depth + 1);
        m_including.erase(display);
    }

    // -------------------------------------------------------------- camera, film, sampler, integrator

    ParamValue default_camera(SourcePos pos) const {
        return ParamValue::dict({{"position", point({0, 0, 0}, pos)}, {"look_at", point({0, 0, 1}, pos)},
                                 {"up", point({0, 1, 0}, pos)}, {"handedness", str("left", pos)},
                                 {"fov_degrees", num(90, pos)}, {"fov_axis", str("smaller", pos)}},
                                pos);
    }

    void camera(const std::string& type, const PbrtParams& p, SourcePos pos) {
        if (m_in_world) fail(pos, "Camera inside the world; expected it before WorldBegin");
        const std::optional<Matrix> world_from_camera = inverse(m_state.ctm[0]);
        if (!world_from_camera) fail(pos, "the camera's transform is singular; expected an invertible one");
        m_coordinate_systems["camera"] = {*world_from_camera, *world_from_camera};
        if (type != "perspective") warn(pos, "Camera \"" + type + "\" is not supported; rendered as a perspective camera");
        const Matrix& w = *world_from_camera;
        const DVec3 eye = apply_point(w, {0, 0, 0});
        const DVec3 forward = normalize(apply_vector(w, {0, 0, 1}));
        const DVec3 up = normalize(apply_vector(w, {0, 1, 0}));
        const DVec3 right = apply_vector(w, {1, 0, 0});
        if (!uniform_scale(w)) warn(pos, "the camera's transform scales its axes unequally or skews them; the camera is made from its view and up directions");
        ParamValue c = ParamValue::dict(pos);
        c.set("position", point(eye, pos)).set("look_at", point(eye + forward, pos)).set("up", point(up, pos));
        c.set("handedness", str(dot(cross(up, forward), right) > 0 ? "left" : "right", pos));
        c.set("fov_degrees", num(p.get_float("fov", 90), pos)).set("fov_axis", str("smaller", pos));
        const double lens = p.get_float("lensradius", 0);
        if (lens > 0) {
            c.set("aperture_radius", num(lens, pos));
            c.set("focus_distance", num(p.get_float("focaldistance", 1e6), pos));
        }
        const double open = p.get_float("shutteropen", 0), close = p.get_float("shutterclose", 1);
        if (open != 0 || close != 1) c.set("shutter", ParamValue::numbers({open, close}, pos));
        warn_unused(p, "Camera \"" + type + "\"");
        m_camera = std::move(c);
    }

    void film(const std::string& type, const PbrtParams& p, SourcePos pos) {
        if (type != "rgb") warn(pos, "Film \"" + type + "\" is written as an RGB image");
        p.find("diagonal");  // the sensor's size, which only pbrt-v4's realistic camera reads
        if (const PbrtParam* f = p.find("filename")) {
            const std::string name = p.get_string("filename", "");
            if (image_format_from_path(name)) m_output = ParamValue::string(name, f->pos);
            else warn(f->pos, "Film filename \"" + name + "\" is not an image format this renderer writes (.png, .exr, .pfm, .ppm); the default output is used");
        }
        m_width = p.get_int("xresolution", 1280);
        m_height = p.get_int("yresolution", 720);
        // The sensor's defaults are the plain CIE observer at unit exposure, which is what this
        // renderer's film is; anything else is reported as unsupported.
        if (p.get_string("sensor", "cie1931") != "cie1931") p.find("sensor")->used = false;
        if (p.get_float("iso", 100) != 100) p.find("iso")->used = false;
        if (p.get_float("exposuretime", 1) != 1) p.find("exposuretime")->used = false;
        if (p.get_float("whitebalance", 0) != 0) p.find("whitebalance")->used = false;
        warn_unused(p, "Film \"" + type + "\"");
    }

    void sampler(const std::string& type, const PbrtParams& p, SourcePos pos) {
        static const std::set<std::string> known = {"zsobol", "halton", "sobol", "paddedsobol", "pmj02bn", "independent", "stratified"};
        if (!known.count(type)) warn(pos, "Sampler \"" + type + "\" is unknown; the renderer's own sampler is used");
        if (type == "stratified") m_spp = p.get_int("xsamples", 4) * p.get_int("ysamples", 4);
        else m_spp = p.get_int("pixelsamples", 16);
        // How pbrt-v4's samplers decorrelate their points: ours decorrelates its own.
        p.find("randomization");
        p.find("jitter");
        warn_unused(p, "Sampler \"" + type + "\"");
    }

    void integrator(const std::string& type, const PbrtParams& p, SourcePos pos) {
        std::string ours = "path";
        if (type == "bdpt") ours = "bdpt";
        else if (type == "sppm") ours = "vcm";
        else if (type == "mlt") ours = "bdpt";
        if (type != "path" && type != "volpath" && type != "bdpt")
            warn(pos, "Integrator \"" + type + "\" is not supported; rendered with \"" + ours + "\"");
        const int depth = p.get_int("maxdepth", 5);
        if (depth < 0) fail(p.find("maxdepth")->pos, "maxdepth " + std::to_string(depth) + "; expected at least 0");
        m_integrator = ParamValue::dict({{"type", str(ours, pos)}, {"max_depth", num(depth, pos)}}, pos);
        p.find("lightsampler");  // which light to sample is the renderer's choice; the expected image is the same
        warn_unused(p, "Integrator \"" + type + "\"");
    }

    // -------------------------------------------------------------- spectra and textures

    ParamValue named_spectrum(const std::string& name, SourcePos pos) const {
        static const std::map<std::string, std::pair<std::string, std::string>> names = {
            {"stdillum-D65", {"illuminant", "D65"}}, {"stdillum-A", {"illuminant", "A"}},
            {"stdillum-F2", {"illuminant", "F2"}},   {"stdillum-F7", {"illuminant", "F7"}},
            {"stdillum-F11", {"illuminant", "F11"}},
            {"glass-BK7", {"glass", "N-BK7"}},       {"glass-BAF10", {"glass", "N-BAF10"}},
            {"glass-FK51A", {"glass", "N-FK51A"}},   {"glass-LASF9", {"glass", "N-LASF9"}},
            {"glass-F10", {"glass", "SF10"}},        {"glass-F11", {"glass", "SF11"}}};
        const auto it = names.find(name);
        if (it == names.end()) {
            std::string known;
            for (const auto& [n, v] : names) known += (known.empty() ? "" : ", ") + n;
            fail(pos, "named spectrum \"" + name + "\" is not available here; expected one of " + known +
                          (name.starts_with("metal-") ? " (metals: use a conductor's eta and k)" : ""));
        }
        return ParamValue::dict({{"type", str(it->second.first, pos)}, {"name", str(it->second.second, pos)}}, pos);
    }

    /// A spectrum-valued parameter as the description's spectrum form.
    ParamValue spectrum(const PbrtParam& p, Role role) const {
        const SourcePos pos = p.pos;
        ParamValue s;
        if (p.type == "rgb") {
            if (p.numbers.size() != 3) fail(pos, "rgb \"" + p.name + "\" has " + std::to_string(p.size()) + " values; expected 3");
            const double r = p.numbers[0], g = p.numbers[1], b = p.numbers[2];
            if (r < 0 || g < 0 || b < 0) fail(pos, "rgb \"" + p.name + "\" has a negative component; expected values >= 0");
            if (role == Role::Albedo) {
                if (std::max({r, g, b}) > 1)
                    fail(pos, "rgb \"" + p.name + "\" has a component above 1; expected a reflectance in [0, 1]");
                return ParamValue::numbers({r, g, b}, pos);
            }
            s = unbounded_rgb(r, g, b, pos);
            return role == Role::Illuminant ? product({std::move(s), normalized(d65(pos), 1, pos)}, 1, pos) : s;
        }
        if (p.type == "blackbody") {
            if (p.numbers.size() != 1) fail(pos, "blackbody \"" + p.name + "\" has " + std::to_string(p.size()) + " values; expected a temperature");
            const double t = p.numbers[0];
            if (!(t > 0)) fail(pos, "blackbody temperature " + std::to_string(t) + "; expected a positive temperature in K");
            s = ParamValue::dict({{"type", str("blackbody", pos)}, {"temperature_k", num(t, pos)},
                                  {"normalize_nm", num(2.8977721e6 / t, pos)}},
                                 pos);  // pbrt-v4 normalises a blackbody to 1 at its peak (Wien's law)
        } else if (p.type == "spectrum") {
            if (!p.strings.empty()) {
                if (p.strings.size() != 1) fail(pos, "spectrum \"" + p.name + "\" has several names; expected one");
                s = p.strings[0].find('.') != std::string::npos ? spectrum_file(p.strings[0], pos) : named_spectrum(p.strings[0], pos);
            } else {
                if (p.numbers.size() < 4 || p.numbers.size() % 2)
                    fail(pos, "spectrum \"" + p.name + "\" has " + std::to_string(p.numbers.size()) +
                                  " values; expected pairs of wavelength (nm) and value, at least two");
                s = table(p.numbers, pos);
            }
        } else if (p.type == "float") {
            if (p.numbers.size() != 1) fail(pos, "float \"" + p.name + "\" has " + std::to_string(p.size()) + " values; expected 1");
            s = num(p.numbers[0], pos);
        } else {
            fail(pos, "parameter \"" + p.name + "\" is declared " + p.type + "; expected rgb, spectrum or blackbody");
        }
        return role == Role::Illuminant ? normalized(std::move(s), 1, pos) : s;
    }

    ParamValue table(const std::vector<double>& xs, SourcePos pos) const {
        ParamValue points = ParamValue::list({}, pos);
        for (std::size_t i = 0; i + 1 < xs.size(); i += 2) points.push(ParamValue::numbers({xs[i], xs[i + 1]}, pos));
        return ParamValue::dict({{"type", str("table", pos)}, {"points", std::move(points)}}, pos);
    }

    /// A spectrum file: pairs of wavelength (nm) and value, `#` comments.
    ParamValue spectrum_file(const std::string& name, SourcePos pos) const {
        std::string contents, display, why;
        if (!m_read_relative(name, contents, display, why))
            fail(pos, "cannot read the spectrum file \"" + name + "\": " + why + "; expected a readable file");
        std::vector<double> xs;
        std::istringstream in(contents);
        for (std::string line; std::getline(in, line);) {
            std::istringstream words(line.substr(0, line.find('#')));
            for (double x; words >> x;) xs.push_back(x);
            if (!words.eof()) fail(pos, "spectrum file \"" + display + "\" has something other than numbers; expected wavelength and value pairs");
        }
        if (xs.size() < 4 || xs.size() % 2) fail(pos, "spectrum file \"" + display + "\" holds " + std::to_string(xs.size()) + " numbers; expected pairs, at least two");
        return table(xs, pos);
    }

    /// A material parameter that may be a texture: the texture reference when the texture can
    /// be read, else its constant value, else the spectrum or number as written. nullopt when
    /// absent (or an unsupported texture, reported).
    std::optional<ParamValue> textured(const PbrtParams& params, const std::string& name, Role role) {
        const PbrtParam* p = params.find(name);
        if (!p) return std::nullopt;
        if (p->type == "texture") {
            const std::string& t = p->strings.at(0);
            const auto it = m_texture_info.find(t);
            if (it == m_texture_info.end()) fail(p->pos, "unknown texture \"" + t + "\"; expected one defined by Texture before it");
            if (it->second.constant) return it->second.constant;
            if (!it->second.supported) {
                warn(p->pos, "\"" + name + "\" uses the texture \"" + t + "\", which is not supported; the parameter's default is used");
                return std::nullopt;
            }
            return ParamValue::dict({{"texture", str(t, p->pos)}}, p->pos);
        }
        return spectrum(*p, role);
    }

    void texture(const std::string& name, const std::string& kind, const std::string& cls, const PbrtParams& p, SourcePos pos) {
        if (kind != "spectrum" && kind != "float")
            fail(pos, "texture \"" + name + "\" of kind \"" + kind + "\"; expected \"spectrum\" or \"float\"");
        TextureInfo info;
        const Role role = kind == "float" ? Role::Unbounded : Role::Albedo;
        if (cls == "constant") {
            const PbrtParam* v = p.find("value");
            info.constant = v ? spectrum(*v, role) : num(1, pos);
        } else if (cls == "imagemap") {
            ParamValue t = ParamValue::dict({{"type", str("image", pos)}}, pos);
            const PbrtParam* f = p.find("filename");
            if (!f || f->type != "string") fail(pos, "imagemap texture \"" + name + "\" has no \"string filename\"; expected the image's file");
            const std::string& file_name = f->strings[0];
            const std::string ext = lowercase(file_name.substr(std::min(file_name.size(), file_name.rfind('.'))));
            if (ext != ".png" && ext != ".pfm" && ext != ".exr" && ext != ".ppm" && ext != ".hdr" && ext != ".pic") {
                warn(f->pos, "image \"" + file_name + "\": this format is not read (PNG, PFM, EXR, PPM and Radiance HDR are); materials that use \"" +
                                 name + "\" take their default");
                for (const PbrtParam& q : p.all()) q.used = true;
                m_texture_info[name] = info;
                return;
            }
            t.set("file", str(f->strings[0], f->pos));
            const std::string wrap = p.get_string("wrap", "repeat");
            if (wrap == "repeat" || wrap == "clamp") t.set("wrap", str(wrap, pos));
            else warn(p.find("wrap")->pos, "wrap \"" + wrap + "\" is not supported; \"repeat\" is used");
            const std::string filter = p.get_string("filter", "bilinear");
            t.set("filter", str(filter == "point" ? "nearest" : "bilinear", pos));
            if (filter != "bilinear" && filter != "point")
                warn(p.find("filter")->pos, "filter \"" + filter + "\" is not supported; bilinear filtering is used");
            const std::string encoding = p.get_string("encoding", "");
            if (encoding == "linear") t.set("encoding", str("linear", pos));
            else if (encoding == "sRGB") t.set("encoding", str("srgb", pos));
            else if (!encoding.empty()) warn(p.find("encoding")->pos, "encoding \"" + encoding + "\" is not supported; the file's own is used");
            uv_mapping(t, p);
            info.supported = true;
            m_textures.set(name, std::move(t), pos);
        } else if (cls == "bilerp") {
            // pbrt-v4's bilinear blend of four values at the corners of the (u, v) square: a
            // gradient when it varies along one axis only.
            const auto value = [&](const char* key, double fallback) -> ParamValue {
                const PbrtParam* v = p.find(key);
                if (!v) return num(fallback, pos);
                if (v->type == "texture") fail(v->pos, "bilerp \"" + std::string(key) + "\" names a texture; expected a value");
                return spectrum(*v, role);
            };
            const ParamValue v00 = value("v00", 0), v01 = value("v01", 1), v10 = value("v10", 0), v11 = value("v11", 1);
            const auto same = [](const ParamValue& a, const ParamValue& b) { return a.is_number() && b.is_number() ? a.as_number() == b.as_number() : false; };
            const auto same_list = [&](const ParamValue& a, const ParamValue& b) {
                if (same(a, b)) return true;
                if (!a.is_array() || !b.is_array() || a.items().size() != b.items().size()) return false;
                for (std::size_t i = 0; i < a.items().size(); ++i)
                    if (!same(a.items()[i], b.items()[i])) return false;
                return true;
            };
            ParamValue t = ParamValue::dict({{"type", str("gradient", pos)}}, pos);
            if (same_list(v00, v01) && same_list(v10, v11)) t.set("start", v00).set("end", v10).set("axis", str("u", pos));
            else if (same_list(v00, v10) && same_list(v01, v11)) t.set("start", v00).set("end", v01).set("axis", str("v", pos));
            else {
                warn(pos, "Texture \"bilerp\" varying along both u and v is not supported; materials that use \"" + name + "\" take their default");
                m_texture_info[name] = info;
                return;
            }
            uv_mapping(t, p);
            info.supported = true;
            m_textures.set(name, std::move(t), pos);
        } else if (cls == "checkerboard") {
            ParamValue t = ParamValue::dict({{"type", str("checkerboard", pos)}}, pos);
            const auto value = [&](const char* key, double fallback) {
                const PbrtParam* v = p.find(key);
                if (!v) return num(fallback, pos);
                if (v->type == "texture") fail(v->pos, "checkerboard \"" + std::string(key) + "\" names a texture; expected a value (textures of textures are not supported)");
                return spectrum(*v, role);
            };
            t.set("even", value("tex1", 1)).set("odd", value("tex2", 0));
            if (p.get_int("dimension", 2) != 2) fail(p.find("dimension")->pos, "checkerboard dimension 3 is not supported; expected 2");
            uv_mapping(t, p);
            info.supported = true;
            m_textures.set(name, std::move(t), pos);
        } else {
            warn(pos, "Texture class \"" + cls + "\" is not supported; materials that use \"" + name + "\" take their default");
            m_texture_info[name] = info;
            return;
        }
        warn_unused(p, "Texture \"" + name + "\"");
        m_texture_info[name] = std::move(info);
    }

    void uv_mapping(ParamValue& t, const PbrtParams& p) const {
        const std::string mapping = p.get_string("mapping", "uv");
        if (mapping != "uv") p.find("mapping")->used = false;
        const double su = p.get_float("uscale", 1), sv = p.get_float("vscale", 1);
        const double du = p.get_float("udelta", 0), dv = p.get_float("vdelta", 0);
        const SourcePos pos = t.pos();
        if (su != 1 || sv != 1) t.set("uv_scale", ParamValue::numbers({su, sv}, pos));
        if (du != 0 || dv != 0) t.set("uv_offset", ParamValue::numbers({du, dv}, pos));
    }

    // -------------------------------------------------------------- materials

    /// α of pbrt-v4's Trowbridge–Reitz distribution: √roughness when remapped.
    std::optional<ParamValue> roughness(const PbrtParams& p, const std::string& name, bool remap) {
        const PbrtParam* q = p.find(name);
        if (!q) return std::nullopt;
        if (q->type == "texture") {
            if (remap) {
                warn(q->pos, "a textured \"" + name + "\" with remaproughness is not supported; the texture is read as the microfacet alpha");
            }
            q->used = false;
            return textured(p, name, Role::Unbounded);
        }
        const double r = p.get_float(name, 0);
        if (r < 0) fail(q->pos, name + " " + std::to_string(r) + "; expected a roughness >= 0");
        return num(std::min(1.0, remap ? std::sqrt(r) : r), q->pos);
    }

    void set_roughness(ParamValue& m, const PbrtParams& p, bool anisotropic_allowed, const std::string& what, SourcePos pos,
                       const std::string& prefix = "") {
        const bool remap = p.get_bool("remaproughness", true);
        std::optional<ParamValue> u = roughness(p, prefix + "uroughness", remap), v = roughness(p, prefix + "vroughness", remap);
        const std::optional<ParamValue> r = roughness(p, prefix + "roughness", remap);
        if (!u) u = r;
        if (!v) v = r;
        if (!u && !v) return;
        const ParamValue zero = num(0, pos);
        const ParamValue& a = u ? *u : zero;
        const ParamValue& b = v ? *v : zero;
        if (a.is_number() && b.is_number() && a.as_number() != b.as_number()) {
            if (anisotropic_allowed && a.as_number() > 0 && b.as_number() > 0) {
                m.set("roughness_u", num(std::max(0.001, a.as_number()), a.pos()));
                m.set("roughness_v", num(std::max(0.001, b.as_number()), b.pos()));
                return;
            }
            warn(pos, what + ": unequal u and v roughness is not supported here; their geometric mean is used");
            m.set("roughness", num(std::sqrt(a.as_number() * b.as_number()), a.pos()));
            return;
        }
        m.set("roughness", a);
    }

    /// The conductor's η and k: a metal this renderer measures, or the spectra as written.
    void conductor_index(ParamValue& m, const PbrtParams& p, SourcePos pos, const std::string& prefix) {
        const PbrtParam* eta = p.find(prefix + "eta");
        const PbrtParam* k = p.find(prefix + "k");
        if (p.has(prefix + "reflectance")) {
            p.find(prefix + "reflectance")->used = false;
            warn(pos, "a conductor given by \"" + prefix + "reflectance\" is not supported; its eta and k are used");
        }
        const auto metal_of = [](const PbrtParam* q, const char* suffix) -> std::string {
            if (!q || q->type != "spectrum" || q->strings.size() != 1) return "";
            const std::string& s = q->strings[0];
            if (!s.starts_with("metal-") || !s.ends_with(suffix)) return "";
            return s.substr(6, s.size() - 6 - std::string(suffix).size());
        };
        const std::string a = eta ? metal_of(eta, "-eta") : "Cu", b = k ? metal_of(k, "-k") : "Cu";
        static const std::set<std::string> measured = {"Au", "Ag", "Cu", "Al"};
        if (!a.empty() && a == b) {
            if (!measured.count(a))
                fail(eta ? eta->pos : pos, "the metal \"" + a + "\" is not available here; expected Au, Ag, Cu or Al");
            m.set("metal", str(a, eta ? eta->pos : pos));
            return;
        }
        if (!eta || !k) fail(pos, "a conductor with only one of eta and k given; expected both, or neither (copper)");
        m.set("eta", spectrum(*eta, Role::Unbounded)).set("k", spectrum(*k, Role::Unbounded));
    }

    /// The description of a pbrt-v4 material, or nullopt for "interface" (no surface).
    std::optional<ParamValue> material(const std::string& type, const PbrtParams& p, SourcePos pos) {
        const std::string what = "material \"" + type + "\"";
        ParamValue m = ParamValue::dict(pos);
        const auto approximated = [&](const std::string& by) { warn(pos, "Material \"" + type + "\" is approximated by " + by); };
        if (type == "interface") {
            warn_unused(p, "Material \"interface\"");
            return std::nullopt;
        }
        if (type == "diffuse" || type == "diffusetransmission") {
            if (type == "diffusetransmission") approximated("a diffuse reflector of its reflectance (no transmission)");
            m.set("type", str("diffuse", pos));
            m.set("kd", textured(p, "reflectance", Role::Albedo).value_or(num(type == "diffuse" ? 0.5 : 0.25, pos)));
        } else if (type == "conductor" || type == "coatedconductor") {
            const std::string prefix = type == "coatedconductor" ? "conductor." : "";
            if (type == "coatedconductor") approximated("its conductor without the dielectric coat");
            m.set("type", str("conductor", pos));
            conductor_index(m, p, pos, prefix);
            set_roughness(m, p, true, what, pos, prefix);
        } else if (type == "dielectric" || type == "thindielectric") {
            if (type == "thindielectric") approximated("a dielectric interface (a thin slab is two)");
            m.set("type", str("dielectric", pos));
            const PbrtParam* eta = p.find("eta");
            m.set("ior", eta ? spectrum(*eta, Role::Unbounded) : num(1.5, pos));
            set_roughness(m, p, false, what, pos);
        } else if (type == "coateddiffuse") {
            approximated("plastic (a Lambertian base under a dielectric coat, without the layer's thickness and albedo)");
            m.set("type", str("plastic", pos));
            m.set("kd", textured(p, "reflectance", Role::Albedo).value_or(num(0.5, pos)));
            const PbrtParam* eta = p.find("eta");
            if (eta) m.set("ior", spectrum(*eta, Role::Unbounded));
            set_roughness(m, p, false, what, pos);
        } else if (type == "mix") {
            const PbrtParam* names = p.find("materials");
            if (!names || names->type != "string" || names->strings.size() != 2)
                fail(pos, "mix material without two \"string materials\"; expected the names of the two materials it mixes");
            const double amount = p.get_float("amount", 0.5);
            const std::string& chosen = names->strings[amount >= 0.5 ? 1 : 0];
            if (!m_materials.peek(chosen)) fail(names->pos, "unknown material \"" + chosen + "\"; expected one defined before the mix");
            approximated("\"" + chosen + "\", the one it chooses more often");
            warn_unused(p, what);
            return *m_materials.peek(chosen);
        } else {
            approximated("a diffuse reflector of reflectance 0.5 (the type is not supported)");
            for (const PbrtParam& q : p.all()) q.used = true;
            m.set("type", str("diffuse", pos)).set("kd", num(0.5, pos));
        }
        warn_unused(p, what);
        return m;
    }

    void define_material(const std::string& name, const std::string& type, const PbrtParams& p, SourcePos pos) {
        std::optional<ParamValue> m = material(type, p, pos);
        if (!m) {
            m_interface_materials.insert(name);
            return;
        }
        m_interface_materials.erase(name);
        m_materials.set(name, std::move(*m), pos);
    }

    // -------------------------------------------------------------- lights

    /// A light's spectrum at luminance `scale`: pbrt-v4 divides `scale` by the spectrum's
    /// photometric integral (of the illuminant alone for an RGB value).
    ParamValue light_spectrum(const PbrtParams& p, const char* name, double scale, SourcePos pos) const {
        const PbrtParam* q = p.find(name);
        ParamValue s = q ? spectrum(*q, Role::Illuminant) : normalized(d65(pos), 1, pos);
        return product({std::move(s)}, scale, pos);
    }

    void light(const std::string& type, const PbrtParams& p, SourcePos pos) {
        const Matrix& m = m_state.ctm[0];
        double sc = p.get_float("scale", 1);
        if (type == "point" || type == "spot") {
            const DVec3 from = apply_point(m, p.get_point3("from").value_or(DVec3{0, 0, 0}));
            ParamValue l = ParamValue::dict({{"type", str(type, pos)}, {"position", point(from, pos)}}, pos);
            double cone = 0, delta = 0;
            if (type == "spot") {
                const DVec3 to = apply_point(m, p.get_point3("to").value_or(DVec3{0, 0, 1}));
                if (length(to - from) == 0) fail(pos, "spot light with \"from\" equal to \"to\"; expected a direction");
                cone = p.get_float("coneangle", 30), delta = p.get_float("conedeltaangle", 5);
                if (!(cone > 0 && cone <= 180)) fail(p.find("coneangle")->pos, "coneangle " + std::to_string(cone) + "; expected (0, 180]");
                l.set("direction", point(normalize(to - from), pos)).set("cone_degrees", num(cone, pos));
                l.set("falloff_degrees", num(std::clamp(cone - delta, 0.0, cone), pos));
            }
            const double power = p.get_float("power", -1);
            if (power > 0) {
                // pbrt-v4: the intensity that emits `power` (in the unit of luminance × 4π).
                const double ce = std::cos(cone * kPiDouble / 180), cf = std::cos(std::clamp(cone - delta, 0.0, cone) * kPiDouble / 180);
                sc *= power / (type == "point" ? 4 * kPiDouble : 2 * kPiDouble * (1 - 0.5 * (cf + ce)));
            }
            l.set("intensity", light_spectrum(p, "I", sc, pos));
            if (m_state.ctm[0] != m_state.ctm[1]) warn(pos, "a moving light is not supported; the light stays where the shutter opens");
            warn_unused(p, "LightSource \"" + type + "\"");
            m_lights.push(std::move(l));
        } else if (type == "infinite") {
            if (const PbrtParam* f = p.find("filename")) {
                image_infinite_light(*f, p, m, sc, pos);
                return;
            }
            if (m_background) warn(pos, "a second infinite light; only the first is kept");
            else m_background = light_spectrum(p, "L", sc, pos);
            warn_unused(p, "LightSource \"infinite\"");
        } else {
            for (const PbrtParam& q : p.all()) q.used = true;
            warn(pos, "LightSource \"" + type + "\" is not supported; the light is skipped");
        }
    }

    /// An image infinite light: pbrt-v4's equal-area octahedral map in light space, turned by
    /// the CTM (pbrt-v4 looks Le up at the light-space direction), times "scale"; or scaled
    /// to an "illuminance" of its upper (+z) hemisphere. Texels are RGB illuminants as the
    /// builder reads every environment map (pbrt-v4's RGBIlluminantSpectrum, whose
    /// photometric normalisation leaves a white texel at luminance 1 × scale).
    void image_infinite_light(const PbrtParam& f, const PbrtParams& p, const Matrix& m, double scale, SourcePos pos) {
        if (f.type != "string") fail(f.pos, "\"filename\" of an infinite light is a " + f.type + "; expected \"string filename\"");
        if (p.has("L")) fail(p.find("L")->pos, "an infinite light with both \"L\" and \"filename\"; expected one of them");
        // pbrt-v4's portal: four corners in world space, p0 p1 p2 p3 around the rectangle, its
        // frame x = p3 − p0, y = p1 − p0, the map seen on the side of x × y.
        std::optional<ParamValue> portal;
        if (const PbrtParam* q = p.find("portal")) {
            const std::vector<double> c = p.get_numbers("portal", {"point3"}, 3);
            if (c.size() != 12) fail(q->pos, "\"portal\" has " + std::to_string(c.size() / 3) + " points; expected 4 (the corners of a rectangle)");
            const DVec3 p0{c[0], c[1], c[2]}, p1{c[3], c[4], c[5]}, p3{c[9], c[10], c[11]};
            portal = ParamValue::dict({{"origin", point(p0, q->pos)}, {"edge1", point(p3 - p0, q->pos)}, {"edge2", point(p1 - p0, q->pos)}}, q->pos);
        }
        if (m_background) {
            warn(pos, "a second infinite light; only the first is kept");
            for (const PbrtParam& q : p.all()) q.used = true;
            return;
        }
        ParamValue bg = ParamValue::dict(pos);
        bg.set("type", str("image", pos)).set("file", str(p.get_string("filename", ""), f.pos));
        bg.set("mapping", str("equal_area", pos)).set("transform", matrix_transform(m, pos));
        const double e_v = p.get_float("illuminance", -1);
        // pbrt-v4 weighs each upper-hemisphere texel by 2π/N where it covers 4π/N steradians, so
        // the map it renders has twice the illuminance asked for: kept, so that a file renders
        // here as it does there.
        if (e_v > 0) bg.set("illuminance", num(2 * e_v * scale, p.find("illuminance")->pos));
        else bg.set("scale", num(scale, pos));
        if (portal) bg.set("portal", std::move(*portal));
        if (m_state.ctm[0] != m_state.ctm[1]) warn(pos, "a moving light is not supported; the light stays where the shutter opens");
        warn_unused(p, "LightSource \"infinite\"");
        m_background = std::move(bg);
    }

    void area_light(const std::string& type, const PbrtParams& p, SourcePos pos) {
        if (type != "diffuse") fail(pos, "AreaLightSource \"" + type + "\"; expected \"diffuse\"");
        AreaLight a;
        if (const PbrtParam* f = p.find("filename")) {
            // An image of radiance: texels are RGB illuminants (the fit times D65 of luminance
            // 1), which is how this renderer reads an emission texture.
            if (p.has("L")) fail(f->pos, "an area light with both \"L\" and \"filename\"; expected one of them");
            const std::string name = "@area-light-image-" + std::to_string(m_area_lights + 1);
            m_textures.set(name, ParamValue::dict({{"type", str("image", f->pos)}, {"file", str(p.get_string("filename", ""), f->pos)}}, f->pos));
            m_texture_info[name].supported = true;
            a.emission = ParamValue::dict({{"texture", str(name, f->pos)}, {"scale", num(p.get_float("scale", 1), pos)}}, pos);
        } else {
            a.emission = light_spectrum(p, "L", p.get_float("scale", 1), pos);
        }
        a.two_sided = p.get_bool("twosided", false);
        a.id = ++m_area_lights;
        warn_unused(p, "AreaLightSource \"diffuse\"");
        m_state.area_light = std::move(a);
    }

    // -------------------------------------------------------------- shapes

    /// The material a shape names: its own, with the area light's emission added when it emits.
    std::optional<std::string> surface(const GraphicsState& s, SourcePos pos) {
        std::string base = s.material;
        if (base.empty()) {
            base = "@default";
            if (!m_materials.peek(base))
                m_materials.set(base, ParamValue::dict({{"type", str("diffuse", pos)}, {"kd", num(0.5, pos)}}, pos), pos);
        }
        if (m_interface_materials.count(base)) return std::nullopt;
        if (!s.area_light) return base;
        const auto key = std::make_pair(base, s.area_light->id);
        auto it = m_emitting_materials.find(key);
        if (it == m_emitting_materials.end()) {
            ParamValue m = *m_materials.peek(base);
            m.set("emission", s.area_light->emission);
            const std::string name = base + "+light" + std::to_string(s.area_light->id);
            m_materials.set(name, std::move(m), pos);
            it = m_emitting_materials.emplace(key, name).first;
        }
        return it->second;
    }

    void make_shape(ShapeRecord& r, const std::vector<Matrix>& placements) {
        const std::string what = "Shape \"" + r.type + "\"";
        const SourcePos pos = r.pos;
        const PbrtParams& p = r.params;
        const GraphicsState& s = r.state;
        const bool warn_now = !r.warned;
        r.warned = true;
        const auto finish = [&](ParamValue shape) {
            const std::optional<std::string> mat = surface(s, pos);
            if (mat) shape.set("material", str(*mat, pos));
            else if (s.area_light) shape.set("emission", s.area_light->emission);
            else {
                if (warn_now) warn(pos, what + " with the \"interface\" material bounds a medium, and media are not read from pbrt files yet; skipped");
                return;
            }
            if (s.area_light && s.area_light->two_sided == false && r.type != "sphere") shape.set("two_sided", ParamValue::boolean(false, pos));
            m_shapes.push(std::move(shape));
        };
        if (s.ctm[0] != s.ctm[1] && warn_now) warn(pos, "a moving shape is not supported; the shape stays where the shutter opens");
        if (is_mesh_type(r.type)) {
            std::optional<ParamValue> mesh = mesh_shape(r, det3(placements.front()) < 0, warn_now);
            if (!mesh) return;
            if (placements.size() == 1) {
                mesh->set("transform", matrix_transform(placements.front(), pos));
            } else {
                ParamValue list = ParamValue::list({}, pos);
                for (const Matrix& m : placements) list.push(matrix_transform(m, pos));
                mesh->set("instances", std::move(list));
            }
            if (warn_now) warn_unused(p, what);
            finish(std::move(*mesh));
            return;
        }
        for (const Matrix& m : placements) {
            const std::optional<double> k = uniform_scale(m);
            if (!k && (r.type == "sphere" || r.type == "disk" || r.type == "cylinder"))
                fail(pos, what + " under a transform that scales its axes unequally or skews them; expected rotations, translations and uniform scales (an ellipsoid is not a shape here)");
            ParamValue shape = ParamValue::dict({{"type", str(r.type, pos)}}, pos);
            if (r.type == "sphere") {
                const double radius = p.get_float("radius", 1);
                if (!(radius > 0)) fail(p.find("radius")->pos, "sphere radius " + std::to_string(radius) + "; expected > 0");
                partial(p, "zmin", -radius, warn_now), partial(p, "zmax", radius, warn_now), partial(p, "phimax", 360, warn_now);
                shape.set("center", point(apply_point(m, {0, 0, 0}), pos)).set("radius", num(radius * *k, pos));
                if (s.reverse_orientation && warn_now) warn(pos, "ReverseOrientation on a sphere is not supported; its normals point out");
            } else if (r.type == "disk") {
                const double radius = p.get_float("radius", 1), h = p.get_float("height", 0);
                partial(p, "innerradius", 0, warn_now), partial(p, "phimax", 360, warn_now);
                if (!(radius > 0)) fail(p.find("radius")->pos, "disk radius " + std::to_string(radius) + "; expected > 0");
                DVec3 n = normalize(cross(apply_vector(m, {1, 0, 0}), apply_vector(m, {0, 1, 0})));
                if (det3(m) < 0) n = -n;  // a normal follows the inverse transpose, not the mirrored axes
                if (s.reverse_orientation) n = -n;
                shape.set("center", point(apply_point(m, {0, 0, h}), pos)).set("normal", point(n, pos));
                shape.set("radius", num(radius * *k, pos));
            } else if (r.type == "cylinder") {
                const double radius = p.get_float("radius", 1), z0 = p.get_float("zmin", -1), z1 = p.get_float("zmax", 1);
                partial(p, "phimax", 360, warn_now);
                if (!(radius > 0) || !(z1 != z0)) fail(pos, "cylinder with radius " + std::to_string(radius) + " and zmin = zmax; expected a radius > 0 and zmin != zmax");
                const double lo = std::min(z0, z1), hi = std::max(z0, z1);
                shape.set("base", point(apply_point(m, {0, 0, lo}), pos));
                shape.set("axis", point(normalize(apply_vector(m, {0, 0, 1})), pos));
                shape.set("radius", num(radius * *k, pos)).set("height", num((hi - lo) * *k, pos));
                if (s.reverse_orientation && warn_now) warn(pos, "ReverseOrientation on a cylinder is not supported; its normals point out");
            } else {
                if (warn_now) warn(pos, what + " is not supported; skipped");
                for (const PbrtParam& q : p.all()) q.used = true;
                return;
            }
            if (warn_now) warn_unused(p, what);
            finish(std::move(shape));
        }
    }

    /// A parameter that cuts a quadric (zmin, phimax...): only its full value is supported.
    void partial(const PbrtParams& p, const char* name, double full, bool warn_now) {
        const PbrtParam* q = p.find(name);
        if (q && p.get_float(name, full) != full && warn_now)
            warn(q->pos, std::string("\"") + name + "\" (a partial shape) is not supported; the whole shape is rendered");
    }

    /// A mesh shape's description without its transform; `mirrored`: the placement turns
    /// handedness (pbrt-v4 keeps the faces' orientation through a mirror).
    std::optional<ParamValue> mesh_shape(const ShapeRecord& r, bool mirrored, bool warn_now) {
        const PbrtParams& p = r.params;
        const SourcePos pos = r.pos;
        const bool flip = mirrored != r.state.reverse_orientation;
        if (r.type == "plymesh") {
            const PbrtParam* f = p.find("filename");
            if (!f || f->type != "string") fail(pos, "plymesh without \"string filename\"; expected the PLY file");
            if (flip && warn_now) warn(pos, "ReverseOrientation or a mirroring transform on a plymesh is not supported; its faces keep the file's orientation");
            if (p.has("displacement") && warn_now) warn(p.find("displacement")->pos, "displacement is not supported; the mesh is rendered undisplaced");
            p.find("edgelength");
            return ParamValue::dict({{"type", str("mesh", pos)}, {"file", str(f->strings[0], f->pos)}}, pos);
        }
        const std::vector<double> P = p.get_numbers("P", {"point3"}, 3);
        if (P.empty()) fail(pos, r.type + " without \"point3 P\"; expected its vertex positions");
        const std::size_t n = P.size() / 3;
        std::vector<double> indices = p.get_numbers("indices", {"integer"}, r.type == "bilinearmesh" ? 4 : 3);
        if (indices.empty()) {
            if (n == 3 && r.type != "bilinearmesh") indices = {0, 1, 2};
            else if (n == 4 && r.type == "bilinearmesh") indices = {0, 1, 2, 3};
            else fail(pos, r.type + " without \"integer indices\"; expected them (only a single triangle or patch may omit them)");
        }
        for (double i : indices)
            if (i < 0 || i >= static_cast<double>(n))
                fail(p.find("indices")->pos, r.type + " index " + std::to_string(static_cast<long long>(i)) + " is outside the " +
                                                 std::to_string(n) + " vertices; expected 0 to " + std::to_string(n - 1));
        if (r.type == "bilinearmesh") {
            // Each patch (p00, p10, p01, p11) as two triangles: exact for planar patches.
            std::vector<double> tris;
            for (std::size_t i = 0; i + 3 < indices.size(); i += 4) {
                const double a = indices[i], b = indices[i + 1], c = indices[i + 2], d = indices[i + 3];
                tris.insert(tris.end(), {a, b, d, a, d, c});
            }
            indices = std::move(tris);
            if (warn_now) warn(pos, "bilinearmesh patches are rendered as two triangles each (exact only for flat patches)");
        }
        if (r.type == "loopsubdiv") {
            p.find("levels");
            if (warn_now) warn(pos, "loopsubdiv is not subdivided here; its control mesh is rendered");
        }
        const std::vector<double> N = p.get_numbers("N", {"normal3"}, 3);
        const std::vector<double> uv = p.get_numbers("uv", {"point2"}, 2);
        if (!N.empty() && N.size() != P.size()) fail(p.find("N")->pos, "N has " + std::to_string(N.size() / 3) + " normals for " + std::to_string(n) + " vertices; expected one per vertex");
        if (!uv.empty() && uv.size() / 2 != n) fail(p.find("uv")->pos, "uv has " + std::to_string(uv.size() / 2) + " pairs for " + std::to_string(n) + " vertices; expected one per vertex");
        // pbrt-v4 faces a triangle towards its shading normals when it has them, else keeps
        // its winding unless the orientation is reversed (a mirror is reversed back).
        for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
            bool swap = flip;
            if (!N.empty()) {
                const auto v = [&](std::size_t k) { const std::size_t i = static_cast<std::size_t>(indices[t + k]); return DVec3{P[3 * i], P[3 * i + 1], P[3 * i + 2]}; };
                const auto nn = [&](std::size_t k) { const std::size_t i = static_cast<std::size_t>(indices[t + k]); return DVec3{N[3 * i], N[3 * i + 1], N[3 * i + 2]}; };
                const double side = dot(cross(v(1) - v(0), v(2) - v(0)), nn(0) + nn(1) + nn(2));
                swap = (side < 0) != mirrored;  // a mirror turns the winding, not the normals
            }
            if (swap) std::swap(indices[t + 1], indices[t + 2]);
        }
        ParamValue mesh = ParamValue::dict({{"type", str("mesh", pos)}, {"positions", list_of(P, pos)}, {"indices", list_of(indices, pos)}}, pos);
        if (!N.empty()) mesh.set("normals", list_of(N, pos));
        if (!uv.empty()) mesh.set("uv", list_of(uv, pos));
        p.find("faceIndices");  // per-face data for ptex textures, which are not read
        return mesh;
    }
};

}  // namespace

SceneDescription read_pbrt_scene(std::string_view text, const std::string& origin, const std::string& name,
                                 const RelativeFileReader& read_relative) {
    SceneDescription d;
    d.name = name;
    PbrtReader reader(d, read_relative);
    reader.parse(text, origin, 0);
    reader.finish(SourcePos{1, 1, 0});
    return d;
}

}  // namespace spt

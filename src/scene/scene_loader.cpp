// JSON scene files → Scene. Each value is checked where it is read, so messages point at the
// offending value: unknown keys (with a suggestion), wrong types, out-of-range numbers,
// unknown names, unreadable meshes, and materials that reflect more than they receive.
#include "scene/scene_loader.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <map>
#include <sstream>
#include <stdexcept>

#include "io/embedded_files.h"
#include "io/ply_reader.h"
#include "spectral/glass_catalog.h"
#include "spectral/rgb_to_spectrum.h"
#include "spectral/spectral_table.h"

namespace spt {

namespace {

/// Largest coordinate or length accepted in a scene: far beyond any sensible scene, small
/// enough that products of coordinates stay finite in float.
constexpr double kMaxCoordinate = 1e15;

std::size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t above = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diagonal = above;
        }
    }
    return row[b.size()];
}

/// " Did you mean "x"?" when a candidate is close to `word`, else "".
std::string suggestion(std::string_view word, const std::vector<std::string>& candidates) {
    std::string best;
    std::size_t best_distance = std::max<std::size_t>(2, word.size() / 2) + 1;
    for (const std::string& c : candidates) {
        const std::size_t d = edit_distance(word.substr(0, 200), c);
        if (d < best_distance) best_distance = d, best = c;
    }
    return best.empty() ? "" : " Did you mean \"" + best + "\"?";
}

std::string join(const std::vector<std::string>& words) {
    std::string out;
    for (const std::string& w : words) out += (out.empty() ? "" : ", ") + w;
    return out;
}

/// Quoted, shortened text of a user string for messages.
std::string quote_text(std::string_view s) {
    std::string out = "\"";
    for (char c : s.substr(0, 60)) out += (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) ? '?' : c;
    return out + (s.size() > 60 ? "...\"" : "\"");
}

std::string number_text(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

enum class SpectrumUse { Reflectance, Emission, Index };

class Loader {
public:
    Loader(const std::string& origin, SpectralResolution resolution, const RelativeFileReader& read_relative)
        : m_origin(origin), m_resolution(resolution), m_read_relative(read_relative) {}

    Scene load(const JsonValue& root, const std::string& name) {
        m_scene.name = name;
        const JsonValue& top = object(root, "the scene");
        check_keys(top, "the scene", {"description", "camera", "image", "background", "materials", "shapes", "lights"});
        if (const JsonValue* d = top.find("description")) string(*d, "description");
        camera(required(top, "camera", "the scene"));
        if (const JsonValue* image = top.find("image")) image_settings(*image);
        if (const JsonValue* bg = top.find("background"))
            m_scene.background = spectrum(*bg, "background", SpectrumUse::Emission);
        if (const JsonValue* mats = top.find("materials")) materials(*mats);
        const JsonValue& shape_list = required(top, "shapes", "the scene");
        if (!shape_list.is_array()) wrong_type(shape_list, "shapes", "an array of shapes");
        for (const JsonValue& s : shape_list.items()) shape(s);
        if (const JsonValue* lights = top.find("lights")) {
            if (!lights->is_array()) wrong_type(*lights, "lights", "an array of lights");
            for (const JsonValue& l : lights->items()) light(l);
        }
        try {
            m_scene.finalize();
        } catch (const SceneError& e) {  // every check above should have come first
            fail(root.pos(), e.what());
        }
        return std::move(m_scene);
    }

private:
    const std::string& m_origin;
    SpectralResolution m_resolution;
    const RelativeFileReader& m_read_relative;
    Scene m_scene;
    std::map<std::string, int> m_material_index;

    // ---------------------------- Generic checks ----------------------------

    [[noreturn]] void fail(TextPos pos, const std::string& message) const {
        throw LocatedError(m_origin, pos, message);
    }
    [[noreturn]] void wrong_type(const JsonValue& v, const std::string& what, const std::string& expected) const {
        fail(v.pos(), what + " is " + JsonValue::type_name(v.type()) + "; expected " + expected);
    }

    const JsonValue& object(const JsonValue& v, const std::string& what) const {
        if (!v.is_object()) wrong_type(v, what, "an object");
        return v;
    }

    void check_keys(const JsonValue& obj, const std::string& what, std::initializer_list<const char*> allowed) const {
        std::vector<std::string> names(allowed.begin(), allowed.end());
        for (std::size_t i = 0; i < obj.members().size(); ++i) {
            const std::string& key = obj.members()[i].first;
            if (std::find(names.begin(), names.end(), key) != names.end()) continue;
            fail(obj.key_pos(i), "unknown key " + quote_text(key) + " in " + what + "." + suggestion(key, names) +
                                  " Expected one of: " + join(names));
        }
    }

    const JsonValue& required(const JsonValue& obj, const char* key, const std::string& what) const {
        const JsonValue* v = obj.find(key);
        if (!v) fail(obj.pos(), what + " has no \"" + key + "\"; expected one");
        return *v;
    }

    double number(const JsonValue& v, const std::string& what) const {
        if (!v.is_number()) wrong_type(v, what, "a number");
        return v.as_number();
    }
    double number_in(const JsonValue& v, const std::string& what, double lo, double hi, bool lo_open = false) const {
        const double x = number(v, what);
        if (x < lo || x > hi || (lo_open && x == lo))
            fail(v.pos(), what + " is " + number_text(x) + "; expected a number in " + (lo_open ? "(" : "[") +
                              number_text(lo) + ", " + number_text(hi) + "]");
        return x;
    }
    int integer_in(const JsonValue& v, const std::string& what, int lo, int hi) const {
        const double x = number(v, what);
        if (x != std::floor(x) || x < lo || x > hi)
            fail(v.pos(), what + " is " + number_text(x) + "; expected an integer from " + std::to_string(lo) +
                              " to " + std::to_string(hi));
        return static_cast<int>(x);
    }
    const std::string& string(const JsonValue& v, const std::string& what) const {
        if (!v.is_string()) wrong_type(v, what, "a string");
        return v.as_string();
    }
    double optional_number(const JsonValue& obj, const char* key, double fallback, const std::string& what) const {
        const JsonValue* v = obj.find(key);
        return v ? number(*v, what + " " + key) : fallback;
    }

    /// Array of exactly n numbers.
    std::vector<double> numbers(const JsonValue& v, const std::string& what, std::size_t n) const {
        if (!v.is_array() || v.items().size() != n)
            fail(v.pos(), what + " is " + (v.is_array() ? "an array of " + std::to_string(v.items().size()) + " values" : JsonValue::type_name(v.type())) +
                              "; expected an array of " + std::to_string(n) + " numbers");
        std::vector<double> out;
        for (const JsonValue& x : v.items()) out.push_back(number(x, "an element of " + what));
        return out;
    }

    Vec3 point(const JsonValue& v, const std::string& what) const {
        const std::vector<double> c = numbers(v, what, 3);
        for (double x : c)
            if (std::fabs(x) > kMaxCoordinate)
                fail(v.pos(), what + " has a coordinate of " + number_text(x) + "; expected magnitudes up to 1e15");
        return {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2])};
    }
    Vec3 direction(const JsonValue& v, const std::string& what) const {
        const Vec3 d = point(v, what);
        const double len = std::sqrt(double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z);
        if (!(len > 1e-30)) fail(v.pos(), what + " is the zero vector; expected a non-zero direction");
        return d;
    }

    // ---------------------------- Camera and image ----------------------------

    void camera(const JsonValue& v) {
        object(v, "camera");
        check_keys(v, "camera", {"position", "look_at", "up", "vfov_degrees"});
        CameraSpec& c = m_scene.camera;
        c.position = point(required(v, "position", "camera"), "camera position");
        c.look_at = point(required(v, "look_at", "camera"), "camera look_at");
        if (const JsonValue* up = v.find("up")) c.up = direction(*up, "camera up");
        if (const JsonValue* fov = v.find("vfov_degrees"))
            c.vfov_degrees = static_cast<float>(number_in(*fov, "camera vfov_degrees", 0, 179.9, true));
        const Vec3 forward = c.look_at - c.position;
        if (!(length(forward) > 0.f)) fail(v.pos(), "camera look_at equals its position; expected a point to look at");
        if (!(length(cross(normalize(forward), normalize(c.up))) > 1e-6f))
            fail(v.pos(), "camera up is parallel to the viewing direction; expected a different up vector");
    }

    void image_settings(const JsonValue& v) {
        object(v, "image");
        check_keys(v, "image", {"width", "height", "spp"});
        if (const JsonValue* w = v.find("width")) m_scene.width = integer_in(*w, "image width", 1, 65536);
        if (const JsonValue* h = v.find("height")) m_scene.height = integer_in(*h, "image height", 1, 65536);
        if (const JsonValue* s = v.find("spp")) m_scene.spp = integer_in(*s, "image spp", 1, 1000000);
        if (double(m_scene.width) * m_scene.height > double(1 << 28))
            fail(v.pos(), "image of " + std::to_string(m_scene.width) + "x" + std::to_string(m_scene.height) +
                              " pixels is too large; expected at most 268435456 pixels");
    }

    // ---------------------------- Spectra ----------------------------

    Spectrum spectrum(const JsonValue& v, const std::string& what, SpectrumUse use) const {
        const SpectrumSource source = spectrum_source(v, what, use);
        // Scan the exact source over the whole sampled range.
        double lo = 0, hi = 1e30;
        const char* expected = "a finite value >= 0";
        if (use == SpectrumUse::Reflectance) hi = 1, expected = "a reflectance in [0, 1]";
        if (use == SpectrumUse::Index) lo = 1, hi = 100, expected = "an index of refraction in [1, 100]";
        for (double l = kLambdaMin; l <= kLambdaMax; l += 1.0) {
            const double x = source.eval(l);
            if (std::isfinite(x) && x >= lo && x <= hi) continue;
            fail(v.pos(), what + " is " + number_text(x) + " at " + number_text(l) + " nm; expected " + expected +
                              " at every wavelength from 360 to 830 nm");
        }
        return Spectrum(source, m_resolution);
    }

    SpectrumSource spectrum_source(const JsonValue& v, const std::string& what, SpectrumUse use) const {
        if (v.is_number()) return SpectrumSource::constant(v.as_number());
        if (v.is_array()) return rgb(v, what, 1.0);
        if (!v.is_object())
            wrong_type(v, what, "a spectrum: a number, an [r, g, b] array or an object with a \"type\"");
        const std::string& type = string(required(v, "type", what), what + " type");
        const std::string w = what + " (" + type + ")";
        auto need = [&](const char* key) -> double { return number(required(v, key, w), w + " " + key); };
        auto opt = [&](const char* key, double fallback) { return optional_number(v, key, fallback, w); };
        auto width = [&](const char* key) {
            return number_in(required(v, key, w), w + " " + key, 0, 1e6, true);
        };
        if (type == "constant") {
            check_keys(v, w, {"type", "value"});
            return SpectrumSource::constant(need("value"));
        }
        if (type == "gaussian" || type == "sigmoid") {
            check_keys(v, w, {"type", "center_nm", "width_nm", "scale", "offset"});
            const double center = need("center_nm"), wd = width("width_nm");
            return type == "gaussian" ? SpectrumSource::gaussian(center, wd, opt("scale", 1), opt("offset", 0))
                                      : SpectrumSource::sigmoid(center, wd, opt("scale", 1), opt("offset", 0));
        }
        if (type == "blackbody") {
            check_keys(v, w, {"type", "temperature_k", "scale", "normalize_nm"});
            const double t = number_in(required(v, "temperature_k", w), w + " temperature_k", 100, 1e6);
            const double at = v.find("normalize_nm")
                                  ? number_in(*v.find("normalize_nm"), w + " normalize_nm", 100, 10000)
                                  : 560.0;
            return SpectrumSource::blackbody(t, opt("scale", 1), at);
        }
        if (type == "table") {
            check_keys(v, w, {"type", "points", "scale"});
            const JsonValue& pts = required(v, "points", w);
            if (!pts.is_array() || pts.items().empty())
                fail(pts.pos(), w + " points is not a non-empty array; expected [[lambda_nm, value], ...]");
            std::vector<std::pair<double, double>> table;
            const double scale = opt("scale", 1);
            for (const JsonValue& p : pts.items()) {
                const std::vector<double> lv = numbers(p, w + " point", 2);
                if (!table.empty() && !(lv[0] > table.back().first))
                    fail(p.pos(), w + " wavelengths do not increase; expected strictly increasing wavelengths");
                table.emplace_back(lv[0], lv[1] * scale);
            }
            return SpectrumSource::piecewise_linear(std::move(table));
        }
        if (type == "cauchy") {
            check_keys(v, w, {"type", "a", "b_um2", "c_um4"});
            return SpectrumSource::cauchy(need("a"), opt("b_um2", 0), opt("c_um4", 0));
        }
        if (type == "sellmeier") {
            check_keys(v, w, {"type", "b", "c_um2"});
            const auto b = numbers(required(v, "b", w), w + " b", 3);
            const auto c = numbers(required(v, "c_um2", w), w + " c_um2", 3);
            return SpectrumSource::sellmeier(b[0], b[1], b[2], c[0], c[1], c[2]);
        }
        if (type == "glass") {
            check_keys(v, w, {"type", "name"});
            const JsonValue& n = required(v, "name", w);
            const std::string& name = string(n, w + " name");
            const std::optional<GlassInfo> glass = find_glass(name);
            if (!glass)
                fail(n.pos(), "unknown glass " + quote_text(name) + "." + suggestion(name, glass_names()) +
                                  " Expected one of: " + join(glass_names()));
            return glass->ior;
        }
        if (type == "rgb") {
            check_keys(v, w, {"type", "value", "scale"});
            return rgb(required(v, "value", w), w, opt("scale", 1));
        }
        if (type == "illuminant") {
            check_keys(v, w, {"type", "name", "scale"});
            const JsonValue& n = required(v, "name", w);
            const std::string& name = string(n, w + " name");
            const char* file = name == "D65" ? "cie_d65.csv" : name == "A" ? "cie_a.csv" : nullptr;
            if (!file)
                fail(n.pos(), "unknown illuminant " + quote_text(name) + "." + suggestion(name, {"D65", "A"}) +
                                  " Expected D65 or A");
            // Tables are normalised to 100 at 560 nm; here to 1.
            return table_column(embedded_spectral_table(file), "value", opt("scale", 1) / 100.0);
        }
        if (type == "colorchecker") {
            check_keys(v, w, {"type", "patch", "scale"});
            const JsonValue& n = required(v, "patch", w);
            const std::string& patch = string(n, w + " patch");
            const SpectralTable& t = embedded_spectral_table("colorchecker.csv");
            const std::vector<std::string> patches(t.column_names.begin() + 1, t.column_names.end());
            if (std::find(patches.begin(), patches.end(), patch) == patches.end())
                fail(n.pos(), "unknown ColorChecker patch " + quote_text(patch) + "." + suggestion(patch, patches) +
                                  " Expected one of: " + join(patches));
            return table_column(t, patch, opt("scale", 1));
        }
        const JsonValue& t = *v.find("type");
        const std::vector<std::string> types = {"constant", "gaussian", "sigmoid", "blackbody", "table", "cauchy",
                                                "sellmeier", "glass", "rgb", "illuminant", "colorchecker"};
        (void)use;
        fail(t.pos(), "unknown spectrum type " + quote_text(type) + "." + suggestion(type, types) +
                          " Expected one of: " + join(types));
    }

    SpectrumSource rgb(const JsonValue& v, const std::string& what, double scale) const {
        const std::vector<double> c = numbers(v, what + " rgb", 3);
        for (double x : c)
            if (x < 0 || x > 1)
                fail(v.pos(), what + " rgb component " + number_text(x) +
                                  " is out of range; expected linear sRGB components in [0, 1] (use \"scale\" for brighter emission)");
        SpectrumSource s;
        try {
            s = rgb_to_spectrum({c[0], c[1], c[2]});
        } catch (const std::exception& e) {
            fail(v.pos(), what + ": " + e.what() + "; expected an RGB reflectance that can be fitted");
        }
        if (s.kind == SpectrumSource::Kind::Constant) return SpectrumSource::constant(s.p[0] * scale);
        s.p[3] = scale;
        return s;
    }

    static SpectrumSource table_column(const SpectralTable& t, const std::string& column, double scale) {
        const std::vector<double>& values = t.column(column);
        std::vector<std::pair<double, double>> points;
        for (std::size_t i = 0; i < values.size(); ++i) points.emplace_back(t.wavelengths_nm[i], values[i] * scale);
        return SpectrumSource::piecewise_linear(std::move(points));
    }

    // ---------------------------- Materials ----------------------------

    void materials(const JsonValue& v) {
        object(v, "materials");
        for (const auto& [name, def] : v.members()) {
            const std::string what = "material " + quote_text(name);
            object(def, what);
            check_keys(def, what, {"kd", "ks", "kt", "ior", "emission"});
            Material m;
            m.name = name;
            if (const JsonValue* x = def.find("kd")) m.kd = spectrum(*x, what + " kd", SpectrumUse::Reflectance);
            if (const JsonValue* x = def.find("ks")) m.ks = spectrum(*x, what + " ks", SpectrumUse::Reflectance);
            if (const JsonValue* x = def.find("kt")) m.kt = spectrum(*x, what + " kt", SpectrumUse::Reflectance);
            if (const JsonValue* x = def.find("ior")) m.eta = spectrum(*x, what + " ior", SpectrumUse::Index);
            if (const JsonValue* x = def.find("emission"))
                m.emission = spectrum(*x, what + " emission", SpectrumUse::Emission);
            if (m.has_transmission() && !def.find("ior"))
                fail(def.pos(), what + " has kt but no \"ior\"; expected an index of refraction");
            add_material(std::move(m), def.pos());
            m_material_index[name] = static_cast<int>(m_scene.materials.size()) - 1;
        }
    }

    int add_material(Material m, TextPos pos) {
        try {
            validate_material(m);
        } catch (const SceneError& e) {
            fail(pos, e.what());
        }
        return m_scene.add_material(std::move(m));
    }

    /// The material of a shape: "material": NAME, or "emission": SPECTRUM (a black emitter).
    int shape_material(const JsonValue& v, const std::string& what) {
        const JsonValue* name = v.find("material");
        const JsonValue* emission = v.find("emission");
        if (name && emission) fail(v.pos(), what + " has both \"material\" and \"emission\"; expected one of them");
        if (emission) {
            Material m;
            m.name = what + " emission";
            m.emission = spectrum(*emission, what + " emission", SpectrumUse::Emission);
            return add_material(std::move(m), emission->pos());
        }
        if (!name) fail(v.pos(), what + " has neither \"material\" nor \"emission\"; expected one of them");
        const std::string& n = string(*name, what + " material");
        if (auto it = m_material_index.find(n); it != m_material_index.end()) return it->second;
        std::vector<std::string> known;
        for (const auto& [k, i] : m_material_index) known.push_back(k);
        fail(name->pos(), "unknown material " + quote_text(n) + "." + suggestion(n, known) +
                              (known.empty() ? " Expected a material defined in \"materials\" (there are none)"
                                             : " Expected one of: " + join(known)));
    }

    // ---------------------------- Shapes ----------------------------

    /// Affine map: scale, then rotate about an axis through the origin, then translate.
    struct Transform {
        double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        double t[3] = {0, 0, 0};
        Vec3 apply(const Vec3& p) const {
            double out[3];
            for (int i = 0; i < 3; ++i) out[i] = m[i][0] * p.x + m[i][1] * p.y + m[i][2] * p.z + t[i];
            return {static_cast<float>(out[0]), static_cast<float>(out[1]), static_cast<float>(out[2])};
        }
    };

    Transform transform(const JsonValue* v) const {
        Transform tr;
        if (!v) return tr;
        object(*v, "transform");
        check_keys(*v, "transform", {"scale", "rotate", "translate"});
        double s[3] = {1, 1, 1};
        if (const JsonValue* sv = v->find("scale")) {
            if (sv->is_number()) {
                s[0] = s[1] = s[2] = sv->as_number();
            } else {
                const auto c = numbers(*sv, "transform scale", 3);
                std::copy(c.begin(), c.end(), s);
            }
            for (double x : s)
                if (x == 0 || std::fabs(x) > 1e6 || std::fabs(x) < 1e-6)
                    fail(sv->pos(), "transform scale " + number_text(x) + " is out of range; expected a magnitude in [1e-6, 1e6]");
        }
        double r[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        if (const JsonValue* rv = v->find("rotate")) {
            object(*rv, "transform rotate");
            check_keys(*rv, "transform rotate", {"axis", "degrees"});
            const Vec3 a = direction(required(*rv, "axis", "transform rotate"), "transform rotate axis");
            const double deg = number_in(required(*rv, "degrees", "transform rotate"), "transform rotate degrees", -36000, 36000);
            const double len = std::sqrt(double(a.x) * a.x + double(a.y) * a.y + double(a.z) * a.z);
            const double x = a.x / len, y = a.y / len, z = a.z / len;
            const double th = deg * 3.14159265358979323846 / 180.0, c = std::cos(th), sn = std::sin(th), k = 1 - c;
            const double rot[3][3] = {{c + x * x * k, x * y * k - z * sn, x * z * k + y * sn},
                                      {y * x * k + z * sn, c + y * y * k, y * z * k - x * sn},
                                      {z * x * k - y * sn, z * y * k + x * sn, c + z * z * k}};
            std::copy(&rot[0][0], &rot[0][0] + 9, &r[0][0]);
        }
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) tr.m[i][j] = r[i][j] * s[j];
        if (const JsonValue* tv = v->find("translate")) {
            const Vec3 t = point(*tv, "transform translate");
            tr.t[0] = t.x, tr.t[1] = t.y, tr.t[2] = t.z;
        }
        return tr;
    }

    void add_triangle(const Vec3& a, const Vec3& b, const Vec3& c, int material, TextPos pos, const std::string& what) {
        const Triangle t{a, b, c, material};
        if (!is_finite(a) || !is_finite(b) || !is_finite(c))
            fail(pos, what + " has a vertex that is not finite after its transform; expected finite coordinates");
        if (t.is_degenerate()) fail(pos, what + " has zero area; expected three vertices that are not collinear");
        m_scene.triangles.push_back(t);
    }

    void shape(const JsonValue& v) {
        const std::string index = std::to_string(m_shape_count++);
        object(v, "shape " + index);
        const std::string& type = string(required(v, "type", "shape " + index), "shape " + index + " type");
        const std::string what = type + " (shape " + index + ")";
        if (type == "sphere") {
            check_keys(v, what, {"type", "center", "radius", "material", "emission"});
            Sphere s;
            s.center = point(required(v, "center", what), what + " center");
            s.radius = static_cast<float>(number_in(required(v, "radius", what), what + " radius", 0, kMaxCoordinate, true));
            if (!(s.radius > 0.f)) fail(v.find("radius")->pos(), what + " radius rounds to 0 in single precision; expected a larger radius");
            s.material = shape_material(v, what);
            m_scene.spheres.push_back(s);
        } else if (type == "plane") {
            check_keys(v, what, {"type", "normal", "point", "material", "emission"});
            const JsonValue& nv = required(v, "normal", what);
            const Vec3 n = normalize(direction(nv, what + " normal"));
            const Vec3 p = point(required(v, "point", what), what + " point");
            if (!is_finite(n)) fail(nv.pos(), what + " normal cannot be normalised; expected a normal of moderate length");
            Plane plane;
            plane.normal = n;
            plane.offset = static_cast<float>(double(n.x) * p.x + double(n.y) * p.y + double(n.z) * p.z);
            plane.material = shape_material(v, what);
            m_scene.planes.push_back(plane);
        } else if (type == "quad") {
            check_keys(v, what, {"type", "origin", "edge1", "edge2", "transform", "material", "emission"});
            const Vec3 o = point(required(v, "origin", what), what + " origin");
            const Vec3 e1 = direction(required(v, "edge1", what), what + " edge1");
            const Vec3 e2 = direction(required(v, "edge2", what), what + " edge2");
            const Transform tr = transform(v.find("transform"));
            const int m = shape_material(v, what);
            const Vec3 a = tr.apply(o), b = tr.apply(o + e1), c = tr.apply(o + e1 + e2), d = tr.apply(o + e2);
            add_triangle(a, b, c, m, v.pos(), what);
            add_triangle(a, c, d, m, v.pos(), what);
        } else if (type == "triangle") {
            check_keys(v, what, {"type", "vertices", "material", "emission"});
            const JsonValue& vs = required(v, "vertices", what);
            if (!vs.is_array() || vs.items().size() != 3)
                fail(vs.pos(), what + " vertices is not an array of 3 points; expected [[x, y, z], [x, y, z], [x, y, z]]");
            const Vec3 a = point(vs.items()[0], what + " vertex"), b = point(vs.items()[1], what + " vertex"),
                       c = point(vs.items()[2], what + " vertex");
            add_triangle(a, b, c, shape_material(v, what), v.pos(), what);
        } else if (type == "mesh") {
            check_keys(v, what, {"type", "file", "transform", "material", "emission"});
            const JsonValue& fv = required(v, "file", what);
            const std::string& file = string(fv, what + " file");
            const Transform tr = transform(v.find("transform"));
            const int m = shape_material(v, what);
            std::string contents, display, error;
            if (file.empty() || !m_read_relative(file, contents, display, error))
                fail(fv.pos(), "cannot read mesh " + quote_text(file) + (error.empty() ? "" : ": " + error) +
                                   "; expected a PLY file path relative to the scene file");
            const PlyMesh mesh = parse_ply(contents, display);
            std::vector<Vec3> p;
            p.reserve(mesh.positions.size());
            for (const Vec3& x : mesh.positions) {
                if (std::fabs(x.x) > kMaxCoordinate || std::fabs(x.y) > kMaxCoordinate || std::fabs(x.z) > kMaxCoordinate)
                    fail(fv.pos(), what + ": a vertex of " + quote_text(display) + " has a coordinate beyond 1e15; expected smaller coordinates");
                p.push_back(tr.apply(x));
            }
            std::size_t added = 0;
            for (const auto& t : mesh.triangles) {
                const Triangle tri{p[t[0]], p[t[1]], p[t[2]], m};
                if (tri.is_degenerate()) continue;  // zero-area faces are common in scanned meshes: never hit
                if (!is_finite(tri.p0) || !is_finite(tri.p1) || !is_finite(tri.p2))
                    fail(fv.pos(), what + " has a vertex that is not finite after its transform; expected finite coordinates");
                m_scene.triangles.push_back(tri);
                ++added;
            }
            if (added == 0) fail(fv.pos(), what + ": " + quote_text(display) + " has no triangle of non-zero area; expected at least one");
        } else {
            const std::vector<std::string> types = {"sphere", "plane", "quad", "triangle", "mesh"};
            fail(v.find("type")->pos(), "unknown shape type " + quote_text(type) + "." + suggestion(type, types) +
                                            " Expected one of: " + join(types));
        }
    }
    int m_shape_count = 0;

    void light(const JsonValue& v) {
        object(v, "light");
        const std::string& type = string(required(v, "type", "light"), "light type");
        if (type != "point")
            fail(v.find("type")->pos(), "unknown light type " + quote_text(type) + "." + suggestion(type, {"point"}) +
                                            " Expected \"point\" (area lights are shapes with \"emission\")");
        check_keys(v, "point light", {"type", "position", "intensity"});
        PointLight l;
        l.position = point(required(v, "position", "point light"), "point light position");
        l.intensity = spectrum(required(v, "intensity", "point light"), "point light intensity", SpectrumUse::Emission);
        m_scene.point_lights.push_back(std::move(l));
    }
};

std::string read_whole_file(const std::filesystem::path& path, std::string& error) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
        error = "no such file";
        return {};
    }
    if (std::filesystem::is_directory(path, ec)) {
        error = "it is a directory";
        return {};
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        error = "cannot open it";
        return {};
    }
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) error = "read error";
    return text;
}

}  // namespace

Scene load_scene_text(std::string_view text, const std::string& origin, const std::string& scene_name,
                      SpectralResolution resolution, const RelativeFileReader& read_relative) {
    const JsonValue root = parse_json(text, origin);
    return Loader(origin, resolution, read_relative).load(root, scene_name);
}

Scene load_scene_file(const std::string& path, SpectralResolution resolution) {
    std::string error;
    const std::string text = read_whole_file(path, error);
    if (!error.empty()) throw LocatedError(path, {1, 1}, "cannot read the scene file: " + error + "; expected a readable JSON file");
    const std::filesystem::path base = std::filesystem::path(path).parent_path();
    const RelativeFileReader reader = [&](const std::string& rel, std::string& contents, std::string& display,
                                          std::string& why) {
        const std::filesystem::path full = base / rel;
        display = full.string();
        contents = read_whole_file(full, why);
        return why.empty();
    };
    return load_scene_text(text, path, std::filesystem::path(path).stem().string(), resolution, reader);
}

std::vector<std::string> builtin_scene_names() {
    std::vector<std::string> names;
    for (std::size_t i = 0; i < kEmbeddedScenes_count; ++i) {
        const std::string_view file = kEmbeddedScenes[i].name ? kEmbeddedScenes[i].name : "";
        if (file.starts_with("scenes/") && file.ends_with(".json"))
            names.emplace_back(file.substr(7, file.size() - 12));
    }
    std::sort(names.begin(), names.end(), [](const std::string& a, const std::string& b) {
        if ((a == "cornell") != (b == "cornell")) return a == "cornell";
        return a < b;
    });
    return names;
}

std::optional<Scene> load_builtin_scene(const std::string& name, SpectralResolution resolution) {
    if (name.find('/') != std::string::npos) return std::nullopt;
    const std::string file = "scenes/" + name + ".json";
    const EmbeddedFile* embedded = find_embedded(file);
    if (!embedded) return std::nullopt;
    const RelativeFileReader reader = [](const std::string& rel, std::string& contents, std::string& display,
                                         std::string& why) {
        display = (std::filesystem::path("scenes") / rel).lexically_normal().generic_string();
        const EmbeddedFile* f = find_embedded(display);
        if (!f) {
            why = "no such built-in file";
            return false;
        }
        contents = f->text;
        return true;
    };
    return load_scene_text(embedded->text, file, name, resolution, reader);
}

}  // namespace spt

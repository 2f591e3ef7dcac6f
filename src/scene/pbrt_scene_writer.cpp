// The pbrt-v4 writer: one pass over the description's sections, in pbrt-v4's order (options,
// camera, WorldBegin, lights, textures, materials, shapes).
#include "scene/pbrt_scene_writer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "scene/spectrum_parser.h"
#include "spectral/cie.h"
#include "spectral/metal_catalog.h"

namespace spt {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegrees = kPi / 180.0;

using V3 = std::array<double, 3>;

V3 operator+(const V3& a, const V3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
V3 operator-(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V3 operator*(double s, const V3& a) { return {s * a[0], s * a[1], s * a[2]}; }
double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V3 normalized(const V3& a) { return (1.0 / std::sqrt(dot(a, a))) * a; }

/// A 4x4 matrix, row-major (a point is a column vector: p' = M p).
using M4 = std::array<std::array<double, 4>, 4>;
M4 identity() { return {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}}; }

/// The unit tangents of a plane's (u, v) for normal n (scenes/README.md, "Plane coordinates":
/// Duff et al. 2017), t_u × t_v = n.
std::pair<V3, V3> plane_tangents(const V3& n) {
    const double s = n[2] >= 0 ? 1.0 : -1.0;
    const double a = -1.0 / (s + n[2]), b = n[0] * n[1] * a;
    return {{1 + s * n[0] * n[0] * a, s * b, -s * n[0]}, {b, s + n[1] * n[1] * a, -n[1]}};
}

/// A right-handed frame (t, b, n) about a unit n: maps +z to n without a mirror.
M4 frame_to(const V3& n, const V3& origin) {
    const auto [t, b] = plane_tangents(n);
    M4 m = identity();
    for (int i = 0; i < 3; ++i) m[i][0] = t[i], m[i][1] = b[i], m[i][2] = n[i], m[i][3] = origin[i];
    return m;
}

std::string num(double x) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.9g", x);
    return buf;
}

/// A pbrt-v4 string: in double quotes, with \\ and \" escaped.
std::string pstr(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out + "\"";
}

/// A comment line's text: one line, whatever the message holds.
std::string comment_text(std::string s) {
    std::replace(s.begin(), s.end(), '\n', ' ');
    return s;
}

class PbrtWriter : public ParamChecker {
public:
    PbrtWriter(const SceneDescription& d, const PbrtExportSettings& settings)
        : ParamChecker(d.files), m_d(d), m_settings(settings), m_spectra(d.files, SpectralResolution{}) {}

    PbrtExport run() {
        const ParamValue& top = m_d.root;
        line("# pbrt-v4 scene written by pathtracer --export-pbrt from " + comment_text(m_d.name) + ".");
        line("# Spectra are tabulated every 5 nm over 360-830 nm from the exact sources; a light's \"scale\" is");
        line("# its spectrum's luminance (pbrt-v4 normalises light spectra to luminance 1).");
        header(top);
        camera(top.peek("camera"));
        line("");
        line("WorldBegin");
        line("");
        if (top.peek("medium") || top.peek("media"))
            line("# participating media (\"media\", \"medium\") are not exported: pbrt-v4's media differ; the scene "
                 "renders here without them");
        if (const ParamValue* bg = top.peek("background")) background(*bg);
        if (const ParamValue* lights = top.peek("lights"))
            for (std::size_t i = 0; i < lights->items().size(); ++i) light(lights->items()[i], i);
        if (const ParamValue* textures = top.peek("textures")) this->textures(*textures);
        if (const ParamValue* materials = top.peek("materials")) this->materials(*materials);
        if (const ParamValue* shapes = top.peek("shapes"))
            for (std::size_t i = 0; i < shapes->items().size(); ++i) shape(shapes->items()[i], i);
        return {m_out.str(), std::move(m_files)};
    }

private:
    const SceneDescription& m_d;
    const PbrtExportSettings& m_settings;
    SpectrumParser m_spectra;
    std::ostringstream m_out;
    std::vector<std::pair<std::string, std::string>> m_files;
    std::map<std::string, std::string> m_file_names;  ///< relative name in the scene → name in the output
    std::set<std::string> m_float_textures;           ///< textures some number parameter reads
    int m_width = 512, m_height = 512;

    void line(const std::string& s) { m_out << s << '\n'; }
    void comment(const std::string& s) { line("# " + comment_text(s)); }

    static double number_or(const ParamValue* v, double fallback) {
        return v && v->is_number() ? v->as_number() : fallback;
    }
    static V3 vec(const ParamValue* v, const V3& fallback) {
        if (!v || !v->is_array() || v->items().size() != 3) return fallback;
        return {v->items()[0].as_number(), v->items()[1].as_number(), v->items()[2].as_number()};
    }
    static std::string point_text(const V3& p) { return num(p[0]) + " " + num(p[1]) + " " + num(p[2]); }
    static const ParamValue* texture_ref(const ParamValue* v) {
        if (v && v->is_object())
            if (const ParamValue* t = v->peek("texture"); t && t->is_string()) return t;
        return nullptr;
    }

    // ------------------------------------------------------------------ spectra

    SpectrumSource source(const ParamValue& v, const std::string& what) const { return m_spectra.spectrum_source(v, what); }

    /// "spectrum NAME" [λ v ...] of a source, every 5 nm over 360–830 nm (a constant: its two ends).
    static std::string table(const std::string& name, const SpectrumSource& s, double factor = 1.0) {
        std::string out = "\"spectrum " + name + "\" [";
        if (s.is_constant()) return out + " 360 " + num(s.eval(560) * factor) + " 830 " + num(s.eval(560) * factor) + " ]";
        for (int l = 360; l <= 830; l += 5) out += " " + std::to_string(l) + " " + num(s.eval(l) * factor);
        return out + " ]";
    }

    /// A spectrum parameter: a texture reference or the tabulated spectrum.
    std::string spectrum_param(const std::string& name, const ParamValue& v, const std::string& what, double factor = 1.0) {
        if (const ParamValue* t = texture_ref(&v)) {
            if (factor != 1.0) comment(what + ": a texture scaled by " + num(factor) + " is written unscaled");
            return "\"texture " + name + "\" " + pstr(t->as_string());
        }
        return table(name, source(v, what), factor);
    }

    /// An index of refraction: "float" when constant, else tabulated.
    std::string eta_param(const std::string& name, const ParamValue& v, const std::string& what) {
        const SpectrumSource s = source(v, what);
        if (s.is_constant()) return "\"float " + name + "\" " + num(s.eval(560));
        return table(name, s);
    }

    /// A number parameter: a number or a float texture.
    std::string float_param(const std::string& name, const ParamValue& v) {
        if (const ParamValue* t = texture_ref(&v)) return "\"texture " + name + "\" " + pstr(t->as_string() + ".float");
        return "\"float " + name + "\" " + num(v.is_number() ? v.as_number() : 0.0);
    }

    /// "spectrum NAME" [...] "float scale" Y for an emitted spectrum; empty when it is black.
    std::string light_spectrum(const std::string& name, const ParamValue& v, const std::string& what) {
        const SpectrumSource s = source(v, what);
        const double y = cie_luminance(s);
        if (!(y > 0)) return {};
        return table(name, s) + " \"float scale\" " + num(y);
    }

    // ------------------------------------------------------------------ options and camera

    void header(const ParamValue& top) {
        const ParamValue* image = top.peek("image");
        int spp = 128;
        if (image) {
            m_width = static_cast<int>(number_or(image->peek("width"), 512));
            m_height = static_cast<int>(number_or(image->peek("height"), 512));
            spp = static_cast<int>(number_or(image->peek("spp"), 128));
        }
        std::string output = std::filesystem::path(m_settings.output_path).stem().string() + ".exr";
        line("Film \"rgb\" \"integer xresolution\" " + std::to_string(m_width) + " \"integer yresolution\" " +
             std::to_string(m_height) + " \"string filename\" " + pstr(output));
        line("# our film adds each path to its pixel alone: a box filter of radius 0.5");
        line("PixelFilter \"box\" \"float xradius\" 0.5 \"float yradius\" 0.5");
        line("Sampler \"zsobol\" \"integer pixelsamples\" " + std::to_string(spp));
        std::string type = "path";
        const ParamValue* integrator = top.peek("integrator");
        const ParamValue* depth = nullptr;
        if (integrator && integrator->is_string()) type = integrator->as_string();
        if (integrator && integrator->is_object()) {
            if (const ParamValue* t = integrator->peek("type"); t && t->is_string()) type = t->as_string();
            depth = integrator->peek("max_depth");
            if (integrator->peek("light_sampling"))
                comment("the scene's light_sampling has no pbrt-v4 equivalent (pbrt-v4's path integrator always uses MIS)");
            if (integrator->peek("merge_radius")) comment("the scene's vcm merge_radius is not exported");
        }
        std::transform(type.begin(), type.end(), type.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        if (type == "vcm") {
            comment("the scene chooses vcm, which pbrt-v4 does not have: bdpt (the same image, more noise on caustics)");
            type = "bdpt";
        }
        if (type != "bdpt") type = "path";
        std::string max_depth = "100";
        if (depth && depth->is_number()) max_depth = std::to_string(static_cast<long long>(depth->as_number()));
        else comment("the scene's path length is unbounded; pbrt-v4 needs a bound: 100 scattering events");
        line("Integrator " + pstr(type) + " \"integer maxdepth\" " + max_depth);
    }

    void camera(const ParamValue* c) {
        if (!c) return;
        const V3 position = vec(c->peek("position"), {0, 0, 0});
        const V3 look_at = vec(c->peek("look_at"), {0, 0, -1});
        const V3 up = vec(c->peek("up"), {0, 1, 0});
        const double aspect = double(m_width) / double(m_height);
        double vfov = number_or(c->peek("vfov_degrees"), 40);
        double fov = pbrt_fov_degrees(vfov, m_width, m_height);
        if (const ParamValue* f = c->peek("fov_degrees"); f && f->is_number()) {
            std::string axis = "smaller";
            if (const ParamValue* a = c->peek("fov_axis"); a && a->is_string()) axis = a->as_string();
            const double t = std::tan(f->as_number() * kDegrees / 2);
            const bool horizontal = axis == "horizontal" || axis == "x" || (axis == "smaller" && aspect < 1) ||
                                    (axis == "larger" && aspect >= 1);
            vfov = 2 * std::atan(horizontal ? t / aspect : t) / kDegrees;
            fov = pbrt_fov_degrees(vfov, m_width, m_height);
        }
        const ParamValue* handedness = c->peek("handedness");
        const bool left = handedness && handedness->is_string() && handedness->as_string() == "left";
        line("");
        if (!left) {
            line("# our camera is right-handed (the image's right is forward x up); pbrt-v4's camera space is");
            line("# left-handed, so the camera transform mirrors x (this mirrors the camera only, not the world)");
            line("Scale -1 1 1");
        }
        line("LookAt " + point_text(position) + "  " + point_text(look_at) + "  " + point_text(up));
        std::string params = "\"float fov\" " + num(fov);
        double aperture = number_or(c->peek("aperture_radius"), 0);
        if (c->peek("f_number") && c->peek("focal_length"))
            aperture = number_or(c->peek("focal_length"), 0) / (2 * number_or(c->peek("f_number"), 1));
        if (aperture > 0) {
            const V3 forward = normalized(look_at - position);
            double focus = std::sqrt(dot(look_at - position, look_at - position));
            if (const ParamValue* d = c->peek("focus_distance"); d && d->is_number()) focus = d->as_number();
            if (const ParamValue* p = c->peek("focus_point")) focus = dot(vec(p, look_at) - position, forward);
            params += " \"float lensradius\" " + num(aperture) + " \"float focaldistance\" " + num(focus);
            if (c->peek("blades"))
                comment("the aperture's polygon (blades, rotation_degrees) is not exported: pbrt-v4's thin lens is a disc");
        }
        if (const ParamValue* s = c->peek("shutter"); s && s->is_array() && s->items().size() == 2)
            params += " \"float shutteropen\" " + num(s->items()[0].as_number()) + " \"float shutterclose\" " +
                      num(s->items()[1].as_number());
        line("Camera \"perspective\" " + params);
    }

    // ------------------------------------------------------------------ lights

    void background(const ParamValue& bg) {
        const ParamValue* type = bg.is_object() ? bg.peek("type") : nullptr;
        if (type && type->is_string() && type->as_string() == "image") return environment_map(bg);
        if (type && type->is_string() && type->as_string() == "sky") {
            comment("the background's Hosek-Wilkie sky and sun are not exported: pbrt-v4 has no sky model (an "
                    "equal-area map of the sky, named as an \"image\" background, can stand in for it)");
            return;
        }
        const std::string l = light_spectrum("L", bg, "background");
        if (l.empty()) return;
        line("# the constant background: an infinite light");
        line("LightSource \"infinite\" " + l);
    }

    /// An equal-area map is pbrt-v4's image infinite light under the map's transform; a
    /// lat-long one has no pbrt-v4 form (pbrt-v4 reads only its octahedral square).
    void environment_map(const ParamValue& bg) {
        const ParamValue* file = bg.peek("file");
        const std::string name = file && file->is_string() ? file->as_string() : "";
        const ParamValue* mapping = bg.peek("mapping");
        if (!(mapping && mapping->is_string() && mapping->as_string() == "equal_area")) {
            comment("the background's lat-long environment map " + quote_text(name) +
                    " is not exported: pbrt-v4 reads only equal-area octahedral maps (convert it with pbrt-v4's "
                    "\"imgtool makeequiarea\", then name the result with \"mapping\": \"equal_area\", +y up "
                    "turned to +z by its transform)");
            return;
        }
        std::string params = "\"string filename\" " + pstr(file_ref(name));
        // pbrt-v4's illuminance renders twice what it asks for (docs/PBRT.md): half of ours.
        if (const ParamValue* e = bg.peek("illuminance"); e && e->is_number())
            params += " \"float illuminance\" " + num(e->as_number() / 2);
        else params += " \"float scale\" " + num(number_or(bg.peek("scale"), 1));
        if (const ParamValue* portal = bg.peek("portal"); portal && portal->is_object()) {
            // pbrt-v4's corners p0 p1 p2 p3, its frame x = p3 − p0, y = p1 − p0 (world space).
            const V3 o = vec(portal->peek("origin"), {0, 0, 0}), e1 = vec(portal->peek("edge1"), {1, 0, 0}),
                     e2 = vec(portal->peek("edge2"), {0, 1, 0});
            params += " \"point3 portal\" [";
            for (const V3& c : {o, o + e2, o + e1 + e2, o + e1}) params += " " + point_text(c);
            params += " ]";
        }
        if (bg.peek("sampling") || bg.peek("mis_compensation"))
            comment("the background's \"sampling\" and \"mis_compensation\" are not exported: pbrt-v4 samples its maps its own way");
        line("# the background: an equal-area environment map");
        line("AttributeBegin");
        concat(transform(bg.peek("transform")));
        line("  LightSource \"infinite\" " + params);
        line("AttributeEnd");
    }

    void light(const ParamValue& v, std::size_t index) {
        const std::string what = "light " + std::to_string(index);
        const ParamValue* type = v.peek("type");
        const std::string t = type && type->is_string() ? type->as_string() : "";
        if (v.peek("motion")) comment(what + ": its motion is not exported; the light stands where it is at rest");
        const ParamValue* intensity = v.peek("intensity");
        const std::string i = intensity ? light_spectrum("I", *intensity, what + " intensity") : "";
        if (i.empty()) {
            comment(what + ": black, not exported");
            return;
        }
        const V3 position = vec(v.peek("position"), {0, 0, 0});
        if (t == "point") {
            line("LightSource \"point\" \"point3 from\" [ " + point_text(position) + " ] " + i);
        } else if (t == "spot") {
            const V3 to = position + normalized(vec(v.peek("direction"), {0, 0, -1}));
            const double cone = number_or(v.peek("cone_degrees"), 30);
            const double falloff = number_or(v.peek("falloff_degrees"), cone);
            line("LightSource \"spot\" \"point3 from\" [ " + point_text(position) + " ] \"point3 to\" [ " + point_text(to) +
                 " ] \"float coneangle\" " + num(cone) + " \"float conedeltaangle\" " + num(cone - falloff) + " " + i);
        } else {
            comment(what + ": light type " + pstr(t) + " is not exported");
        }
    }

    // ------------------------------------------------------------------ files

    /// The name by which the output refers to the scene's file `rel`.
    std::string file_ref(const std::string& rel) {
        if (auto it = m_file_names.find(rel); it != m_file_names.end()) return it->second;
        namespace fs = std::filesystem;
        const fs::path out_dir = fs::absolute(fs::path(m_settings.output_path)).parent_path();
        std::string name;
        std::error_code ec;
        if (!m_settings.scene_folder.empty() && fs::is_regular_file(fs::path(m_settings.scene_folder) / rel, ec)) {
            const fs::path full = fs::absolute(fs::path(m_settings.scene_folder) / rel).lexically_normal();
            const fs::path r = full.lexically_relative(out_dir);
            name = r.empty() ? full.generic_string() : r.generic_string();
        } else {
            std::string contents, display, why;
            if (!m_settings.read_relative || !m_settings.read_relative(rel, contents, display, why))
                throw std::runtime_error("cannot read " + quote_text(rel) + " for the pbrt-v4 file: " + why);
            std::string base = fs::path(rel).filename().string();
            // Two files of one name from different folders get different names beside the output.
            for (int k = 2; std::any_of(m_files.begin(), m_files.end(),
                                        [&](const auto& f) { return fs::path(f.first).filename() == base; });
                 ++k)
                base = fs::path(rel).stem().string() + "-" + std::to_string(k) + fs::path(rel).extension().string();
            m_files.emplace_back((out_dir / base).string(), std::move(contents));
            name = base;
        }
        m_file_names[rel] = name;
        return name;
    }

    // ------------------------------------------------------------------ textures

    void note_float_texture(const ParamValue* v) {
        if (const ParamValue* t = texture_ref(v)) m_float_textures.insert(t->as_string());
    }

    std::string uv_params(const ParamValue& v) {
        std::string p;
        if (const ParamValue* s = v.peek("uv_scale"); s && s->is_array() && s->items().size() == 2)
            p += " \"float uscale\" " + num(s->items()[0].as_number()) + " \"float vscale\" " + num(s->items()[1].as_number());
        if (const ParamValue* o = v.peek("uv_offset"); o && o->is_array() && o->items().size() == 2)
            p += " \"float udelta\" " + num(o->items()[0].as_number()) + " \"float vdelta\" " + num(o->items()[1].as_number());
        return p;
    }

    void textures(const ParamValue& defs) {
        // Which textures a number parameter reads (pbrt-v4 textures are of one kind each).
        if (const ParamValue* mats = m_d.root.peek("materials"))
            for (const auto& [name, m] : mats->members()) {
                note_float_texture(m.peek("roughness"));
                note_float_texture(m.peek("thickness_nm"));
                if (const ParamValue* f = m.peek("film")) note_float_texture(f->peek("thickness_nm"));
            }
        line("");
        for (const auto& [name, v] : defs.members()) {
            texture(name, v, false);
            if (m_float_textures.count(name)) texture(name, v, true);
        }
    }

    void texture(const std::string& name, const ParamValue& v, bool as_float) {
        const std::string what = "texture " + pstr(name);
        const std::string out_name = as_float ? name + ".float" : name;
        const std::string kind = as_float ? "float" : "spectrum";
        const ParamValue* type = v.peek("type");
        const std::string t = type && type->is_string() ? type->as_string() : "";
        const auto value = [&](const std::string& param, const ParamValue* x) -> std::string {
            if (!x) return "";
            if (as_float) return " \"float " + param + "\" " + num(x->is_number() ? x->as_number() : 0.0);
            return " " + table(param, source(*x, what + " " + param));
        };
        if (t == "checkerboard") {
            line("Texture " + pstr(out_name) + " " + pstr(kind) + " \"checkerboard\"" + value("tex1", v.peek("even")) +
                 value("tex2", v.peek("odd")) + uv_params(v));
        } else if (t == "gradient") {
            const ParamValue* axis = v.peek("axis");
            const bool along_v = axis && axis->is_string() && axis->as_string() == "v";
            comment(what + ": a gradient is pbrt-v4's bilerp, which extrapolates beyond [0, 1] where ours holds its ends");
            const ParamValue* s = v.peek("start");
            const ParamValue* e = v.peek("end");
            line("Texture " + pstr(out_name) + " " + pstr(kind) + " \"bilerp\"" + value("v00", s) +
                 value("v10", along_v ? s : e) + value("v01", along_v ? e : s) + value("v11", e) + uv_params(v));
        } else if (t == "image") {
            const ParamValue* file = v.peek("file");
            std::string p = " \"string filename\" " + pstr(file_ref(file && file->is_string() ? file->as_string() : ""));
            if (const ParamValue* enc = v.peek("encoding"); enc && enc->is_string())
                p += std::string(" \"string encoding\" ") + (enc->as_string() == "linear" ? "\"linear\"" : "\"sRGB\"");
            if (const ParamValue* w = v.peek("wrap"); w && w->is_string()) {
                if (w->as_string() == "mirror") comment(what + ": pbrt-v4 has no mirrored wrap; repeat");
                else p += " \"string wrap\" " + pstr(w->as_string());
            }
            if (const ParamValue* f = v.peek("filter"); f && f->is_string())
                p += std::string(" \"string filter\" ") + (f->as_string() == "nearest" ? "\"point\"" : "\"bilinear\"");
            line("Texture " + pstr(out_name) + " " + pstr(kind) + " \"imagemap\"" + p + uv_params(v));
        } else {
            comment(what + ": texture type " + pstr(t) + " is not exported");
        }
    }

    // ------------------------------------------------------------------ materials

    /// The emission of a material, or nullptr.
    const ParamValue* material_emission(const std::string& name) const {
        const ParamValue* mats = m_d.root.peek("materials");
        const ParamValue* m = mats ? mats->peek(name) : nullptr;
        return m ? m->peek("emission") : nullptr;
    }

    std::string roughness_params(const ParamValue& m) {
        std::string p;
        if (const ParamValue* r = m.peek("roughness")) p += " " + float_param("roughness", *r);
        if (const ParamValue* u = m.peek("roughness_u")) p += " " + float_param("uroughness", *u);
        if (const ParamValue* v = m.peek("roughness_v")) p += " " + float_param("vroughness", *v);
        if (!p.empty()) p += " \"bool remaproughness\" false";
        return p;
    }

    void make_material(const std::string& name, const std::string& type, const std::string& params) {
        line("MakeNamedMaterial " + pstr(name) + " \"string type\" " + pstr(type) + params);
    }

    void materials(const ParamValue& defs) {
        line("");
        for (const auto& [name, m] : defs.members()) material(name, m);
    }

    void material(const std::string& name, const ParamValue& m) {
        const std::string what = "material " + pstr(name);
        const ParamValue* type = m.peek("type");
        const std::string t = type && type->is_string() ? type->as_string() : "lobes";
        if (const ParamValue* f = m.peek("film"))
            comment(what + ": its thin film (thickness " + (f->peek("thickness_nm") && f->peek("thickness_nm")->is_number()
                                                                 ? num(f->peek("thickness_nm")->as_number()) + " nm"
                                                                 : std::string("textured")) +
                    ") is not exported: pbrt-v4 has no thin-film interference");
        if (t == "diffuse") {
            const ParamValue* kd = m.peek("kd");
            make_material(name, "diffuse", kd ? " " + spectrum_param("reflectance", *kd, what + " kd") : " \"spectrum reflectance\" [ 360 0 830 0 ]");
        } else if (t == "conductor") {
            std::string p;
            if (const ParamValue* metal = m.peek("metal"); metal && metal->is_string()) {
                const std::optional<MetalInfo> info = find_metal(metal->as_string());
                if (!info) fail(metal->pos(), what + ": unknown metal " + quote_text(metal->as_string()) + "; expected Au, Ag, Cu or Al");
                p = " " + table("eta", info->eta) + " " + table("k", info->k);
            } else {
                if (const ParamValue* e = m.peek("eta")) p += " " + spectrum_param("eta", *e, what + " eta");
                if (const ParamValue* k = m.peek("k")) p += " " + spectrum_param("k", *k, what + " k");
            }
            make_material(name, "conductor", p + roughness_params(m));
        } else if (t == "dielectric") {
            const ParamValue* ior = m.peek("ior");
            make_material(name, "dielectric", (ior ? " " + eta_param("eta", *ior, what + " ior") : "") + roughness_params(m));
        } else if (t == "plastic") {
            comment(what + ": our plastic (a Lambertian base under a single-scattering GGX coat, Kelemen-style energy "
                           "compensation) is pbrt-v4's coateddiffuse, whose layered random-walk model differs");
            const ParamValue* ior = m.peek("ior");
            const ParamValue* kd = m.peek("kd");
            std::string p = kd ? " " + spectrum_param("reflectance", *kd, what + " kd") : "";
            p += ior ? " " + eta_param("eta", *ior, what + " ior") : " \"float eta\" 1.5";
            const ParamValue* r = m.peek("roughness");
            p += r ? " " + float_param("roughness", *r) : " \"float roughness\" 0";
            make_material(name, "coateddiffuse", p + " \"bool remaproughness\" false \"float thickness\" 0.0001");
        } else if (t == "thin_sheet") {
            comment(what + ": a thin sheet's Airy (interference) reflectance has no pbrt-v4 form: thindielectric, "
                           "which reflects by Fresnel without interference");
            const ParamValue* ior = m.peek("ior");
            make_material(name, "thindielectric", ior ? " " + eta_param("eta", *ior, what + " ior") : "");
        } else if (t == "lobes") {
            lobes(name, m, what);
        } else if (t == "fluorescent") {
            comment(what + ": its fluorescent dye layer (absorption and re-emission) is not exported: pbrt-v4 has no "
                           "fluorescence; the surface under the layer is written");
            if (const ParamValue* surface = m.peek("surface"); surface && surface->is_object())
                material(name, *surface);
            else if (const ParamValue* base = m.peek("base"))
                make_material(name, "diffuse", " " + spectrum_param("reflectance", *base, what + " base"));
            else
                make_material(name, "diffuse", " \"spectrum reflectance\" [ 360 0.9 830 0.9 ]");
        } else {
            comment(what + ": material type " + pstr(t) + " is not exported; black diffuse");
            make_material(name, "diffuse", " \"spectrum reflectance\" [ 360 0 830 0 ]");
        }
    }

    /// The weight of a lobe for pbrt-v4's mix (a number): the spectrum's value when constant,
    /// else its mean over 380–780 nm with a comment.
    double lobe_weight(const ParamValue& v, const std::string& what) {
        if (texture_ref(&v)) {
            comment(what + ": a textured lobe weight cannot be a pbrt-v4 mix amount; its weight is taken as 1");
            return 1;
        }
        const SpectrumSource s = source(v, what);
        if (s.is_constant()) return s.eval(560);
        double sum = 0;
        for (int l = 380; l <= 780; ++l) sum += s.eval(l);
        comment(what + ": a mirror or glass lobe that varies with wavelength is a pbrt-v4 mix of its mean weight");
        return sum / 401;
    }

    /// kd·Lambert + ks·mirror + kt·glass as pbrt-v4 mixes of a diffuse, a mirror and a dielectric,
    /// each chosen with the probability of its weight.
    void lobes(const std::string& name, const ParamValue& m, const std::string& what) {
        struct Part {
            std::string name;
            double weight;
        };
        std::vector<Part> parts;
        const ParamValue* kd = m.peek("kd");
        const ParamValue* ks = m.peek("ks");
        const ParamValue* kt = m.peek("kt");
        const double ws = ks ? lobe_weight(*ks, what + " ks") : 0.0;
        const double wt = kt ? lobe_weight(*kt, what + " kt") : 0.0;
        const double wd = std::max(0.0, 1.0 - ws - wt);
        const bool has_d = kd && wd > 0;
        const int count = int(has_d) + int(ws > 0) + int(wt > 0);
        // One lobe of full weight is that material under the material's own name.
        const bool single = count == 1 && (has_d || ws >= 1 || wt >= 1);
        const auto part_name = [&](const char* suffix) { return single ? name : name + suffix; };
        if (has_d) {
            const std::string n = part_name(".diffuse");
            make_material(n, "diffuse", " " + spectrum_param("reflectance", *kd, what + " kd", 1.0 / wd));
            parts.push_back({n, wd});
        }
        if (ws > 0) {
            const std::string n = part_name(".mirror");
            make_material(n, "conductor", " \"spectrum reflectance\" [ 360 1 830 1 ]");
            parts.push_back({n, ws});
        }
        if (wt > 0) {
            const ParamValue* ior = m.peek("ior");
            const std::string n = part_name(".glass");
            make_material(n, "dielectric", ior ? " " + eta_param("eta", *ior, what + " ior") : "");
            parts.push_back({n, wt});
        }
        if (count == 0) {
            make_material(name, "diffuse", " \"spectrum reflectance\" [ 360 0 830 0 ]");
            return;
        }
        if (single) return;
        comment(what + ": a sum of lobes, written as pbrt-v4 mixes that choose each lobe with the probability of its weight");
        // Absorbed energy (weights summing below 1 without a diffuse part) is a black diffuse part.
        double total = 0;
        for (const Part& part : parts) total += part.weight;
        if (total < 1) {
            make_material(name + ".black", "diffuse", " \"spectrum reflectance\" [ 360 0 830 0 ]");
            parts.insert(parts.begin(), {name + ".black", 1 - total});
        }
        Part cur = parts[0];
        for (std::size_t i = 1; i < parts.size(); ++i) {
            const double w = cur.weight + parts[i].weight;
            const std::string n = i + 1 == parts.size() ? name : name + ".mix" + std::to_string(i);
            make_material(n, "mix", " \"string materials\" [ " + pstr(cur.name) + " " + pstr(parts[i].name) +
                                        " ] \"float amount\" " + num(parts[i].weight / w));
            cur = {n, w};
        }
    }

    // ------------------------------------------------------------------ shapes

    /// A shape's transform ({"scale", "rotate", "translate"} or {"matrix"}) as a 4x4 matrix.
    M4 transform(const ParamValue* v) {
        M4 m = identity();
        if (!v || !v->is_object()) return m;
        if (const ParamValue* mx = v->peek("matrix"); mx && mx->is_array() && mx->items().size() == 16) {
            for (int i = 0; i < 16; ++i) m[i / 4][i % 4] = mx->items()[i].as_number();
            return m;
        }
        V3 s = {1, 1, 1};
        if (const ParamValue* sv = v->peek("scale")) s = sv->is_number() ? V3{sv->as_number(), sv->as_number(), sv->as_number()} : vec(sv, s);
        double r[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        if (const ParamValue* rv = v->peek("rotate"); rv && rv->is_object()) {
            const V3 a = normalized(vec(rv->peek("axis"), {0, 1, 0}));
            const double th = number_or(rv->peek("degrees"), 0) * kDegrees, c = std::cos(th), sn = std::sin(th), k = 1 - c;
            const double x = a[0], y = a[1], z = a[2];
            const double rot[3][3] = {{c + x * x * k, x * y * k - z * sn, x * z * k + y * sn},
                                      {y * x * k + z * sn, c + y * y * k, y * z * k - x * sn},
                                      {z * x * k - y * sn, z * y * k + x * sn, c + z * z * k}};
            std::copy(&rot[0][0], &rot[0][0] + 9, &r[0][0]);
        }
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) m[i][j] = r[i][j] * s[j];
        const V3 t = vec(v->peek("translate"), {0, 0, 0});
        for (int i = 0; i < 3; ++i) m[i][3] = t[i];
        return m;
    }

    /// ConcatTransform of a matrix: pbrt-v4 lists the 16 values column by column.
    void concat(const M4& m) {
        if (m == identity()) return;
        std::string s = "ConcatTransform [";
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) s += " " + num(m[r][c]);
        line("  " + s + " ]");
    }

    static V3 apply(const M4& m, const V3& p) {
        return {m[0][0] * p[0] + m[0][1] * p[1] + m[0][2] * p[2] + m[0][3],
                m[1][0] * p[0] + m[1][1] * p[1] + m[1][2] * p[2] + m[1][3],
                m[2][0] * p[0] + m[2][1] * p[1] + m[2][2] * p[2] + m[2][3]};
    }

    std::string trianglemesh(const std::vector<V3>& p, const std::vector<int>& indices, const std::vector<double>& uv) {
        std::string s = "Shape \"trianglemesh\" \"integer indices\" [";
        for (int i : indices) s += " " + std::to_string(i);
        s += " ] \"point3 P\" [";
        for (const V3& x : p) s += " " + point_text(x);
        s += " ]";
        if (!uv.empty()) {
            s += " \"point2 uv\" [";
            for (double x : uv) s += " " + num(x);
            s += " ]";
        }
        return s;
    }

    /// The surface lines of a shape: its material and its area light.
    void surface(const ParamValue& v, const std::string& what) {
        const ParamValue* material = v.peek("material");
        const ParamValue* emission = v.peek("emission");
        if (material && material->is_string()) {
            line("  NamedMaterial " + pstr(material->as_string()));
            if (!emission) emission = material_emission(material->as_string());
        } else if (emission) {
            line("  Material \"diffuse\" \"spectrum reflectance\" [ 360 0 830 0 ]");
        } else {
            line("  # no surface: it bounds media only (not exported), so it lets light through");
            line("  Material \"interface\"");
        }
        if (v.peek("interior") || v.peek("exterior")) line("  # its media (interior, exterior) are not exported");
        if (!emission) return;
        const ParamValue* two = v.peek("two_sided");
        const bool two_sided = !(two && two->is_bool() && !two->as_bool());
        const std::string sides = std::string(" \"bool twosided\" ") + (two_sided ? "true" : "false");
        if (const ParamValue* t = texture_ref(emission)) {
            const ParamValue* defs = m_d.root.peek("textures");
            const ParamValue* tex = defs ? defs->peek(t->as_string()) : nullptr;
            const ParamValue* type = tex ? tex->peek("type") : nullptr;
            const ParamValue* file = tex ? tex->peek("file") : nullptr;
            if (type && type->is_string() && type->as_string() == "image" && file && file->is_string()) {
                const double scale = number_or(emission->peek("scale"), 1);
                line("  # an emitting image: pbrt-v4's area light reads the image itself (its RGB times the colour "
                     "space's illuminant, as our emission texels)");
                line("  AreaLightSource \"diffuse\" \"string filename\" " + pstr(file_ref(file->as_string())) +
                     " \"float scale\" " + num(scale) + sides);
            } else {
                line("  # " + comment_text(what) + ": an emission texture other than an image is not exported");
            }
            return;
        }
        const std::string l = light_spectrum("L", *emission, what + " emission");
        if (!l.empty()) line("  AreaLightSource \"diffuse\" " + l + sides);
    }

    void shape(const ParamValue& v, std::size_t index) {
        const ParamValue* type = v.peek("type");
        const std::string t = type && type->is_string() ? type->as_string() : "";
        const std::string what = t + " (shape " + std::to_string(index) + ")";
        line("");
        if (v.peek("motion")) comment(what + ": its motion is not exported; the shape stands where it is at rest");
        const ParamValue* instances = v.peek("instances");
        if (instances && instances->is_array()) {
            const std::string object = "shape" + std::to_string(index);
            line("ObjectBegin " + pstr(object));
            surface(v, what);
            mesh(v, what);
            line("ObjectEnd");
            for (const ParamValue& inst : instances->items()) {
                line("AttributeBegin");
                concat(transform(&inst));
                line("  ObjectInstance " + pstr(object));
                line("AttributeEnd");
            }
            return;
        }
        line("AttributeBegin");
        surface(v, what);
        if (t == "sphere") {
            line("  Translate " + point_text(vec(v.peek("center"), {0, 0, 0})));
            // pbrt-v4's sphere has its poles on z; turned so they are on y with φ running from +x
            // towards +z, its (u, v) and its tangent (growing u) are ours.
            line("  Rotate 90 1 0 0");
            line("  Shape \"sphere\" \"float radius\" " + num(number_or(v.peek("radius"), 1)));
        } else if (t == "plane") {
            const V3 n = normalized(vec(v.peek("normal"), {0, 1, 0}));
            const V3 p = vec(v.peek("point"), {0, 0, 0});
            const auto [tu, tv] = plane_tangents(n);
            // Centred where the camera stands over it, so the square reaches equally far every way it looks.
            const V3 eye = m_d.root.peek("camera") ? vec(m_d.root.peek("camera")->peek("position"), p) : p;
            const V3 center = eye - dot(eye - p, n) * n;
            const double size = plane_size();
            comment(what + ": pbrt-v4 has no infinite plane: a square of side " + num(2 * size) + " centred on its point");
            std::vector<V3> corners;
            std::vector<double> uv;
            for (const auto& [a, b] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
                const V3 c = center + (a * size) * tu + (b * size) * tv;
                corners.push_back(c);
                uv.push_back(dot(c, tu)), uv.push_back(dot(c, tv));
            }
            line("  " + trianglemesh(corners, {0, 1, 2, 0, 2, 3}, uv));
        } else if (t == "quad") {
            const M4 m = transform(v.peek("transform"));
            concat(m);
            const V3 o = vec(v.peek("origin"), {0, 0, 0});
            const V3 e1 = vec(v.peek("edge1"), {1, 0, 0});
            const V3 e2 = vec(v.peek("edge2"), {0, 1, 0});
            line("  " + trianglemesh({o, o + e1, o + e1 + e2, o + e2}, {0, 1, 2, 0, 2, 3}, {0, 0, 1, 0, 1, 1, 0, 1}));
        } else if (t == "triangle") {
            std::vector<V3> p;
            if (const ParamValue* vs = v.peek("vertices"); vs && vs->is_array())
                for (const ParamValue& x : vs->items()) p.push_back(vec(&x, {0, 0, 0}));
            line("  " + trianglemesh(p, {0, 1, 2}, {0, 0, 1, 0, 0, 1}));
        } else if (t == "mesh") {
            mesh(v, what);
        } else if (t == "disk") {
            concat(frame_to(normalized(vec(v.peek("normal"), {0, 1, 0})), vec(v.peek("center"), {0, 0, 0})));
            line("  Shape \"disk\" \"float radius\" " + num(number_or(v.peek("radius"), 1)));
        } else if (t == "cylinder") {
            concat(frame_to(normalized(vec(v.peek("axis"), {0, 1, 0})), vec(v.peek("base"), {0, 0, 0})));
            line("  Shape \"cylinder\" \"float radius\" " + num(number_or(v.peek("radius"), 1)) +
                 " \"float zmin\" 0 \"float zmax\" " + num(number_or(v.peek("height"), 1)));
        } else if (t == "cone") {
            comment(what + ": pbrt-v4 has no cone: a mesh of 128 triangles (the apex shared)");
            concat(frame_to(normalized(vec(v.peek("axis"), {0, 1, 0})), vec(v.peek("base"), {0, 0, 0})));
            const double r = number_or(v.peek("radius"), 1), h = number_or(v.peek("height"), 1);
            constexpr int kSegments = 128;
            std::vector<V3> p;
            std::vector<int> idx;
            std::vector<double> uv;
            for (int i = 0; i <= kSegments; ++i) {
                const double phi = 2 * kPi * i / kSegments;
                p.push_back({r * std::cos(phi), r * std::sin(phi), 0});
                p.push_back({0, 0, h});
                uv.insert(uv.end(), {double(i) / kSegments, 0, double(i) / kSegments, 1});
            }
            for (int i = 0; i < kSegments; ++i) idx.insert(idx.end(), {2 * i, 2 * i + 2, 2 * i + 1});
            line("  " + trianglemesh(p, idx, uv));
        } else {
            comment(what + ": shape type " + pstr(t) + " is not exported");
        }
        line("AttributeEnd");
    }

    /// A mesh's geometry: a PLY file or inline positions, under its transform.
    void mesh(const ParamValue& v, const std::string& what) {
        concat(transform(v.peek("transform")));
        if (const ParamValue* file = v.peek("file"); file && file->is_string()) {
            line("  Shape \"plymesh\" \"string filename\" " + pstr(file_ref(file->as_string())));
            return;
        }
        const ParamValue* positions = v.peek("positions");
        const ParamValue* indices = v.peek("indices");
        if (!positions || !indices) {
            comment(what + ": a mesh without a file or positions is not exported");
            return;
        }
        const auto list = [&](const ParamValue* x) {
            std::string s;
            for (const ParamValue& n : x->items()) s += " " + num(n.as_number());
            return s;
        };
        std::string s = "  Shape \"trianglemesh\" \"integer indices\" [" + list(indices) + " ] \"point3 P\" [" + list(positions) + " ]";
        if (const ParamValue* n = v.peek("normals")) s += " \"normal N\" [" + list(n) + " ]";
        if (const ParamValue* uv = v.peek("uv")) s += " \"point2 uv\" [" + list(uv) + " ]";
        line(s);
    }

    /// Half the side of the square that stands for an infinite plane: a thousand times the
    /// scene's scale (the camera's distance from the origin and from its target, at least 1),
    /// where the rest of an infinite plane adds a part in a million to what it lights.
    double plane_size() const {
        const ParamValue* c = m_d.root.peek("camera");
        double extent = 1;
        if (c) {
            const V3 p = vec(c->peek("position"), {0, 0, 0});
            extent = std::max({extent, std::sqrt(dot(p, p)), std::sqrt(dot(vec(c->peek("look_at"), {0, 0, 0}) - p,
                                                                            vec(c->peek("look_at"), {0, 0, 0}) - p))});
        }
        return 1000 * extent;
    }
};

}  // namespace

double pbrt_fov_degrees(double vfov_degrees, int width, int height) {
    if (width >= height) return vfov_degrees;
    const double t = std::tan(vfov_degrees * kDegrees / 2) * double(width) / double(height);
    return 2 * std::atan(t) / kDegrees;
}

PbrtExport export_pbrt(const SceneDescription& description, const PbrtExportSettings& settings) {
    return PbrtWriter(description, settings).run();
}

}  // namespace spt

// SceneDescription → Scene, whatever file format the description came from. Each value is
// checked where it is read, so messages point at the offending value: unknown keys (with a
// suggestion), wrong types, out-of-range numbers, unknown names, unreadable meshes, and
// materials that reflect more than they receive.
#include "scene/scene_builder.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <map>
#include <sstream>
#include <stdexcept>
#include <cstring>

#include "geometry/mesh_closure.h"
#include "io/image_decoders.h"
#include "io/image_writer.h"
#include "io/ply_reader.h"
#include "scene/param_checker.h"
#include "scene/material_types.h"
#include "scene/medium_parser.h"
#include "scene/spectrum_parser.h"
#include "scene/texture_parser.h"
#include "spectral/line_spectra.h"

namespace spt {

namespace {

/// Reads the scene's sections in a fixed order (camera, image, background, materials,
/// shapes, lights), so materials may be referred to before they appear in the file.
class Builder : public ParamChecker {
public:
    Builder(const SourceFiles& files, SpectralResolution resolution, const RelativeFileReader& read_relative)
        : ParamChecker(files), m_spectra(files, resolution), m_read_relative(read_relative),
          m_textures(files, resolution, m_spectra, read_relative, m_scene) {}

    Scene load(const ParamValue& root, const std::string& name) {
        m_scene.name = name;
        const ParamValue& top = object(root, "the scene");
        if (const ParamValue* d = top.find("description")) m_scene.summary = first_sentence(string(*d, "description"));
        if (const ParamValue* s = top.find("summary")) m_scene.summary = one_line(*s, "summary");
        camera(required(top, "camera", "the scene"));
        if (const ParamValue* image = top.find("image")) image_settings(*image);
        if (const ParamValue* integrator = top.find("integrator")) integrator_preset(*integrator);
        if (const ParamValue* bg = top.find("background")) background(*bg);
        if (const ParamValue* tex = top.find("textures")) m_textures.definitions(*tex);
        if (const ParamValue* mats = top.find("materials")) materials(*mats);
        if (const ParamValue* media = top.find("media")) media_section(*media);
        if (const ParamValue* m = top.find("medium")) m_scene.camera_medium = medium_ref(*m, "medium");
        const ParamValue& shape_list = required(top, "shapes", "the scene");
        if (!shape_list.is_array()) wrong_type(shape_list, "shapes", "an array of shapes");
        for (const ParamValue& s : shape_list.items()) shape(s);
        if (const ParamValue* lights = top.find("lights")) {
            if (!lights->is_array()) wrong_type(*lights, "lights", "an array of lights");
            for (const ParamValue& l : lights->items()) light(l);
        }
        all_read(top, "the scene");
        try {
            m_scene.finalize();
        } catch (const SceneError& e) {  // every check above should have come first
            fail(root.pos(), e.what());
        }
        return std::move(m_scene);
    }

private:
    SpectrumParser m_spectra;
    const RelativeFileReader& m_read_relative;
    Scene m_scene;
    TextureParser m_textures;
    std::map<std::string, int> m_material_index;
    /// Emission of each material (zero if none), attached to every shape that uses it.
    std::vector<Spectrum> m_material_emission;
    /// The texture of each material's emission, or −1.
    std::vector<int> m_material_emission_texture;

    Spectrum spectrum(const ParamValue& v, const std::string& what, SpectrumUse use) const {
        return m_spectra.spectrum(v, what, use);
    }

    // ---------------------------- Background ----------------------------

    /// A spectrum (the constant environment), an environment map, {"type": "image", ...},
    /// or the Hosek–Wilkie sky and sun, {"type": "sky", ...}.
    void background(const ParamValue& v) {
        const ParamValue* type = v.is_object() ? v.peek("type") : nullptr;
        if (type && type->is_string() && type->as_string() == "sky") {
            sky(v);
            return;
        }
        if (!type || !type->is_string() || type->as_string() != "image") {
            m_scene.set_background(spectrum(v, "background", SpectrumUse::Emission));
            return;
        }
        const std::string what = "background image";
        v.find("type");
        const ParamValue& fv = required(v, "file", what);
        const std::string& file = string(fv, what + " file");
        EnvironmentMapping mapping = EnvironmentMapping::equirect;
        if (const ParamValue* m = v.find("mapping"))
            mapping = choice(*m, what + " mapping", {"equirect", "equal_area"}) == 1 ? EnvironmentMapping::equal_area
                                                                                    : EnvironmentMapping::equirect;
        EnvironmentMapLight light;
        const ParamValue* scale = v.find("scale");
        const ParamValue* illuminance = v.find("illuminance");
        if (scale && illuminance)
            fail(illuminance->pos(), what + " has both \"scale\" and \"illuminance\"; expected one of them");
        if (scale) light.scale = static_cast<float>(number_in(*scale, what + " scale", 0, 1e30, true));
        if (const ParamValue* s = v.find("sampling"))
            light.sampling = choice(*s, what + " sampling", {"importance", "uniform"}) == 1 ? EnvironmentSampling::uniform
                                                                                           : EnvironmentSampling::importance;
        if (const ParamValue* c = v.find("mis_compensation")) {
            if (!c->is_bool()) wrong_type(*c, what + " mis_compensation", "true or false");
            light.mis_compensation = c->as_bool();
        }
        if (const ParamValue* t = v.find("transform")) rotation_of(transform(t), *t, what, light);
        const ParamValue* portal = v.find("portal");
        Vec3 portal_origin, portal_edge1, portal_edge2;
        if (portal) {
            object(*portal, what + " portal");
            portal_origin = point(required(*portal, "origin", what + " portal"), what + " portal origin");
            portal_edge1 = direction(required(*portal, "edge1", what + " portal"), what + " portal edge1");
            portal_edge2 = direction(required(*portal, "edge2", what + " portal"), what + " portal edge2");
            all_read(*portal, what + " portal");
            // A portal is a way of sampling the map: it replaces the other two.
            if (light.sampling != EnvironmentSampling::importance || light.mis_compensation)
                fail(portal->pos(), what + " has a \"portal\" and " +
                                        (light.mis_compensation ? "\"mis_compensation\"" : "\"sampling\": \"uniform\"") +
                                        "; expected the portal alone (it decides how the map is sampled)");
        }
        all_read(v, what);
        std::string contents, display, error;
        if (file.empty() || !m_read_relative(file, contents, display, error))
            fail(fv.pos(), "cannot read environment map " + quote_text(file) + (error.empty() ? "" : ": " + error) +
                               "; expected a PFM or EXR file path relative to the scene file");
        try {
            DecodedImage img = decode_image(contents);
            std::string().swap(contents);  // the file's bytes: not needed beside the map's tables
            if (img.integer_codes)
                throw std::invalid_argument("holds integer codes (an 8- or 16-bit image); expected linear radiance (PFM or EXR)");
            light.map = make_environment_map(img.width, img.height, img.channels, std::move(img.values), mapping,
                                             light.mis_compensation);
        } catch (const std::exception& e) {
            fail(fv.pos(), "environment map " + quote_text(display) + ": " + e.what());
        }
        if (illuminance) {
            const double e = number_in(*illuminance, what + " illuminance", 0, 1e30, true);
            if (!(light.map->up_illuminance > 0))
                fail(illuminance->pos(), what + " illuminance: " + quote_text(display) +
                                             " sends no light from above its horizon; expected a map lit from above, or \"scale\"");
            light.scale = static_cast<float>(e / light.map->up_illuminance);
        }
        if (portal) {
            try {
                m_scene.set_background(make_portal_light(light, portal_origin, portal_edge1, portal_edge2));
            } catch (const std::invalid_argument& e) {
                fail(portal->pos(), what + " portal: " + e.what());
            }
            return;
        }
        m_scene.set_background(std::move(light));
    }

    /// {"type": "sky", "sun_elevation_degrees": η, "sun_azimuth_degrees": φ, "turbidity": T,
    ///  "ground_albedo": a, "sun": true|false, "scale": s}: the sky light and the sun's disc.
    void sky(const ParamValue& v) {
        const std::string what = "background sky";
        v.find("type");
        const double deg = 3.14159265358979323846 / 180.0;
        const double elevation =
            number_in(required(v, "sun_elevation_degrees", what), what + " sun_elevation_degrees", 0, 90) * deg;
        double azimuth = 0, turbidity = 3, albedo = 0.1, scale = 1;
        bool with_sun = true;
        if (const ParamValue* a = v.find("sun_azimuth_degrees"))
            azimuth = number_in(*a, what + " sun_azimuth_degrees", -360, 360) * deg;
        if (const ParamValue* t = v.find("turbidity")) turbidity = number_in(*t, what + " turbidity", 1, 10);
        if (const ParamValue* a = v.find("ground_albedo")) albedo = number_in(*a, what + " ground_albedo", 0, 1);
        if (const ParamValue* s = v.find("scale")) scale = number_in(*s, what + " scale", 0, 1e30, true);
        if (const ParamValue* s = v.find("sun")) {
            if (!s->is_bool()) wrong_type(*s, what + " sun", "true or false");
            with_sun = s->as_bool();
        }
        all_read(v, what);
        SkyLight sky_light;
        sky_light.model = make_sky_model(elevation, azimuth, turbidity, albedo);
        sky_light.scale = static_cast<float>(scale);
        std::optional<SunLight> sun;
        if (with_sun) {
            sun.emplace();
            sun->model = make_sun_model(elevation, azimuth, turbidity);
            sun->scale = static_cast<float>(scale);
        }
        m_scene.set_background(std::move(sky_light), std::move(sun));
    }

    /// The rotation of an environment map: the linear part of `tr`, which must turn
    /// directions without distorting them (a rotation, possibly mirrored, times a uniform
    /// scale, which leaves directions as they are).
    void rotation_of(const AffineMap& tr, const ParamValue& at, const std::string& what, EnvironmentMapLight& light) const {
        const double det = tr.determinant();
        const double s = std::cbrt(std::fabs(det));
        double r[3][3];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) r[i][j] = tr.a[i][j] / s;
        // RᵀR = I within rounding.
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                const double d = r[0][i] * r[0][j] + r[1][i] * r[1][j] + r[2][i] * r[2][j];
                if (!(std::fabs(d - (i == j ? 1.0 : 0.0)) < 1e-4))
                    fail(at.pos(), what + " transform shears or stretches directions; expected a rotation (a mirror "
                                          "and a uniform scale are allowed)");
            }
        for (int i = 0; i < 3; ++i)
            light.world_from_map[i] = Vec3(static_cast<float>(r[i][0]), static_cast<float>(r[i][1]), static_cast<float>(r[i][2]));
    }

    // ---------------------------- Camera and image ----------------------------

    void camera(const ParamValue& v) {
        object(v, "camera");
        CameraSpec& c = m_scene.camera;
        c.position = point(required(v, "position", "camera"), "camera position");
        c.look_at = point(required(v, "look_at", "camera"), "camera look_at");
        if (const ParamValue* up = v.find("up")) c.up = direction(*up, "camera up");
        field_of_view(v);
        if (const ParamValue* h = v.find("handedness"))
            c.left_handed = choice(*h, "camera handedness", {"right", "left"}) == 1;
        const Vec3 forward = c.look_at - c.position;
        if (!(length(forward) > 0.f)) fail(v.pos(), "camera look_at equals its position; expected a point to look at");
        if (!(length(cross(normalize(forward), normalize(c.up))) > 1e-6f))
            fail(v.pos(), "camera up is parallel to the viewing direction; expected a different up vector");
        thin_lens(v);
        if (const ParamValue* shutter = v.find("shutter")) {
            const std::vector<double> t = numbers(*shutter, "camera shutter", 2);
            for (double x : t)
                if (!(std::fabs(x) <= 1e9)) fail(shutter->pos(), "camera shutter time " + number_text(x) + " is out of range; expected times within ±1e9");
            if (t[0] > t[1]) fail(shutter->pos(), "camera shutter closes before it opens; expected [open, close] with open <= close");
            c.shutter_open = static_cast<float>(t[0]);
            c.shutter_close = static_cast<float>(t[1]);
        }
        all_read(v, "camera");
    }

    /// "vfov_degrees": F, or "fov_degrees": F with "fov_axis" (default vertical): the image
    /// axis is resolved where the camera meets the rendered size (Camera), as width and height
    /// may still change.
    void field_of_view(const ParamValue& v) {
        CameraSpec& c = m_scene.camera;
        const ParamValue* vfov = v.find("vfov_degrees");
        const ParamValue* fov = v.find("fov_degrees");
        const ParamValue* axis = v.find("fov_axis");
        if (vfov && fov) fail(fov->pos(), "camera has both vfov_degrees and fov_degrees; expected one of them");
        if (axis && !fov) fail(axis->pos(), "camera fov_axis goes with fov_degrees; expected \"fov_degrees\" too");
        if (vfov || fov)
            c.fov_degrees = static_cast<float>(number_in(vfov ? *vfov : *fov, vfov ? "camera vfov_degrees" : "camera fov_degrees",
                                                         0, 179.9, true));
        if (axis)
            c.fov_axis = static_cast<FovAxis>(choice(*axis, "camera fov_axis", {"vertical", "horizontal", "smaller", "larger"}));
    }

    /// The index of the string `v` among `names`; an error listing them otherwise.
    int choice(const ParamValue& v, const std::string& what, const std::vector<std::string>& names) const {
        const std::string& name = string(v, what);
        for (std::size_t i = 0; i < names.size(); ++i)
            if (names[i] == name) return static_cast<int>(i);
        fail(v.pos(), "unknown " + what + " " + quote_text(name) + "." + suggestion(name, names) +
                          " Expected " + quoted_alternatives(names));
    }

    /// "motion": {"keyframes": [{"time": t, "translate": [x, y, z], "rotate": {"axis":
    /// [x, y, z], "degrees": d}}, ...], "pivot": [x, y, z]}: at least two keyframes in
    /// increasing time; translate and rotate default to none; the pivot (the centre of the
    /// rotations) defaults to `default_pivot`.
    RigidMotion motion(const ParamValue& v, const std::string& what, const Vec3& default_pivot) const {
        const std::string who = what + " motion";
        object(v, who);
        RigidMotion m;
        m.pivot = v.find("pivot") ? point(*v.find("pivot"), who + " pivot") : default_pivot;
        const ParamValue& keys = required(v, "keyframes", who);
        if (!keys.is_array() || keys.items().size() < 2)
            fail(keys.pos(), who + " keyframes is not an array of at least 2 keyframes; expected [{\"time\": 0, ...}, {\"time\": 1, ...}]");
        for (const ParamValue& k : keys.items()) {
            const std::string key_what = who + " keyframe";
            object(k, key_what);
            Keyframe key;
            key.time = static_cast<float>(number_in(required(k, "time", key_what), key_what + " time", -1e9, 1e9));
            if (!m.keys.empty() && !(key.time > m.keys.back().time))
                fail(k.find("time")->pos(), key_what + " time " + number_text(key.time) + " does not follow " +
                                                number_text(m.keys.back().time) + "; expected increasing times");
            if (const ParamValue* t = k.find("translate")) key.translation = point(*t, key_what + " translate");
            if (const ParamValue* r = k.find("rotate")) {
                const std::string rot = key_what + " rotate";
                object(*r, rot);
                const Vec3 axis = normalize(direction(required(*r, "axis", rot), rot + " axis"));
                const double degrees = number_in(required(*r, "degrees", rot), rot + " degrees", -1e6, 1e6);
                key.rotation = Quaternion::axis_angle(axis, static_cast<float>(degrees * kPiDouble / 180.0));
                all_read(*r, rot);
            }
            // A half turn between keyframes (quaternions orthogonal, within about 0.01°) has two
            // shorter arcs, either way round: the motion would be a guess.
            if (!m.keys.empty() && std::fabs(dot(m.keys.back().rotation, key.rotation)) < 1e-4f)
                fail(k.find("rotate") ? k.find("rotate")->pos() : k.pos(),
                     key_what + " rotate turns 180 degrees from the keyframe before, which is ambiguous (either "
                                "way round is as short); expected a keyframe in between");
            m.keys.push_back(key);
            all_read(k, key_what);
        }
        all_read(v, who);
        return m;
    }

    /// The camera's aperture and focus (depth of field); none of the keys: the pinhole.
    void thin_lens(const ParamValue& v) {
        CameraSpec& c = m_scene.camera;
        const ParamValue* radius = v.find("aperture_radius");
        const ParamValue* f_number = v.find("f_number");
        const ParamValue* focal_length = v.find("focal_length");
        if (radius && f_number) fail(f_number->pos(), "camera has both aperture_radius and f_number; expected one of them");
        if (f_number && !focal_length)
            fail(f_number->pos(), "camera f_number needs \"focal_length\" (scene units); expected both");
        if (focal_length && !f_number)
            fail(focal_length->pos(), "camera focal_length only goes with f_number; expected \"f_number\" too");
        if (radius) c.aperture.radius = static_cast<float>(number_in(*radius, "camera aperture_radius", 0, 1e6));
        if (f_number) {
            const double n = number_in(*f_number, "camera f_number", 0, 1e6, true);
            const double f = number_in(*focal_length, "camera focal_length", 0, 1e6, true);
            c.aperture.radius = static_cast<float>(f / (2 * n));  // N = focal length / diameter
        }
        const ParamValue* distance = v.find("focus_distance");
        const ParamValue* point_key = v.find("focus_point");
        const ParamValue* blades = v.find("blades");
        const ParamValue* rotation = v.find("rotation_degrees");
        if (!radius && !f_number) {
            for (const ParamValue* key : {distance, point_key, blades, rotation})
                if (key) fail(key->pos(), "camera focus and blades need an aperture; expected \"aperture_radius\" or \"f_number\"");
            return;
        }
        if (distance && point_key) fail(point_key->pos(), "camera has both focus_distance and focus_point; expected one of them");
        const Vec3 forward = normalize(c.look_at - c.position);
        c.focus_distance = length(c.look_at - c.position);  // default: focused on look_at
        if (distance) c.focus_distance = static_cast<float>(number_in(*distance, "camera focus_distance", 0, 1e9, true));
        if (point_key) {
            c.focus_distance = dot(point(*point_key, "camera focus_point") - c.position, forward);
            if (!(c.focus_distance > 0.f))
                fail(point_key->pos(), "camera focus_point is not in front of the camera; expected a point ahead of it");
        }
        if (rotation && !blades) fail(rotation->pos(), "camera rotation_degrees turns the blades; expected \"blades\" too");
        if (blades) c.aperture.blades = integer_in(*blades, "camera blades", 3, 64);
        if (rotation) c.aperture.rotation_degrees = static_cast<float>(number_in(*rotation, "camera rotation_degrees", -360, 360));
    }

    void image_settings(const ParamValue& v) {
        object(v, "image");
        if (const ParamValue* w = v.find("width")) m_scene.width = integer_in(*w, "image width", 1, 65536);
        if (const ParamValue* h = v.find("height")) m_scene.height = integer_in(*h, "image height", 1, 65536);
        if (const ParamValue* s = v.find("spp")) m_scene.spp = integer_in(*s, "image spp", 1, 1000000);
        if (const ParamValue* f = v.find("file")) {
            m_scene.output = string(*f, "image file");
            if (!image_format_from_path(m_scene.output))
                fail(f->pos(), "image file " + quote_text(m_scene.output) +
                                   " has no image format's ending; expected a name ending in .png, .exr, .pfm or .ppm");
        }
        if (double(m_scene.width) * m_scene.height > double(1 << 28))
            fail(v.pos(), "image of " + std::to_string(m_scene.width) + "x" + std::to_string(m_scene.height) +
                              " pixels is too large; expected at most 268435456 pixels");
        all_read(v, "image");
    }

    /// The text up to the first ". " (or all of it).
    static std::string first_sentence(const std::string& text) {
        const std::size_t end = text.find(". ");
        return end == std::string::npos ? text : text.substr(0, end + 1);
    }

    std::string one_line(const ParamValue& v, const std::string& what) const {
        const std::string& text = string(v, what);
        if (text.find_first_of("\n\r") != std::string::npos)
            fail(v.pos(), what + " has a line break; expected one line");
        return text;
    }

    /// "integrator": "vcm", or {"type": "vcm", "max_depth": D, "merge_radius": R} (and
    /// "light_sampling" for path): the settings a scene renders best with.
    void integrator_preset(const ParamValue& v) {
        IntegratorPreset& p = m_scene.integrator;
        const ParamValue* type = &v;
        if (!v.is_object() && !v.is_string())
            wrong_type(v, "integrator", "a name (path, bdpt or vcm) or an object with \"type\"");
        if (v.is_object()) type = &required(v, "type", "integrator");
        const std::string& name = string(*type, "integrator type");
        const std::vector<std::string> names = integrator_names();
        p.kind = integrator_from_name(name);
        if (!p.kind)
            fail(type->pos(), "unknown integrator " + quote_text(name) + "." + suggestion(name, names) +
                                  " Expected one of: " + join(names));
        if (!v.is_object()) return;
        if (const ParamValue* d = v.find("max_depth")) p.max_depth = integer_in(*d, "integrator max_depth", 0, 100000);
        if (const ParamValue* ls = v.find("light_sampling")) {
            if (*p.kind != IntegratorKind::path)
                fail(ls->pos(), "integrator light_sampling applies to the path integrator only; expected no "
                                "light_sampling with " + name);
            const std::string& mode = string(*ls, "integrator light_sampling");
            p.light_sampling = light_sampling_from_name(mode);
            if (!p.light_sampling)
                fail(ls->pos(), "unknown light_sampling " + quote_text(mode) + "." +
                                    suggestion(mode, light_sampling_names()) + " Expected one of: " + join(light_sampling_names()));
        }
        if (const ParamValue* r = v.find("merge_radius")) {
            if (*p.kind != IntegratorKind::vcm)
                fail(r->pos(), "integrator merge_radius applies to vcm only; expected no merge_radius with " + name);
            p.merge_radius = number_in(*r, "integrator merge_radius", 1e-12, 1e12, true);
        }
        all_read(v, "integrator");
    }

    /// A refracting mesh must bound a volume with its faces pointing out, or rays inside and
    /// outside swap their indices: warn (the image is still what the file describes).
    void check_refracting_mesh(const std::vector<Vec3>& p, const PlyMesh& mesh, int material,
                               const std::string& what, const std::string& display) {
        const MeshClosure c = mesh_closure(p, mesh.triangles);
        const std::string head = what + " (" + display + ", material " +
                                 quote_text(m_scene.materials[material].name) + ") refracts but ";
        if (!c.closed)
            m_scene.warnings.push_back(head + "is not closed (an edge without exactly one opposite neighbour): "
                                              "rays can enter without leaving, so inside and outside are undefined");
        else if (c.signed_volume < 0)
            m_scene.warnings.push_back(head + "has its faces pointing inward (negative signed volume): "
                                              "rays entering it are treated as leaving glass; reverse the vertex order of its faces");
    }

    // ---------------------------- Materials ----------------------------

    void materials(const ParamValue& v) {
        object(v, "materials");
        for (const auto& [name, def] : v.members()) {
            const std::string what = "material " + quote_text(name);
            object(def, what);
            Material m;
            m.name = name;
            // Parameters given as {"texture": NAME}: the parameter's key and the texture.
            std::vector<std::pair<std::string, int>> bound;
            auto reflectance = [&](const ParamValue& x, const char* key) {
                if (!TextureParser::is_binding(x)) return spectrum(x, what + " " + key, SpectrumUse::Reflectance);
                const int t = m_textures.bind(x, what + " " + key, TextureUse::reflectance);
                bound.emplace_back(key, t);
                return m_textures.envelope(t);
            };
            std::string type = "lobes";
            if (const ParamValue* t = def.find("type")) type = string(*t, what + " type");
            const MaterialType* material_type = find_material_type(type);
            if (!material_type) {
                std::vector<std::string> types;
                for (const MaterialType& t : material_types()) types.emplace_back(t.name);
                fail(def.find("type")->pos(), "unknown material type " + quote_text(type) + "." +
                                                  suggestion(type, types) + " Expected one of: " + join(types));
            }
            const FloatParameter number = float_parameter(bound);
            const ReflectanceParameter reflectance_parameter = reflectance;
            m.bsdf = material_type->create({m_spectra, def, what, number, reflectance_parameter, &m.fluorescence});
            for (const auto& [key, texture] : bound) {
                const TexturableParameter* p = find_texturable(m.bsdf.index(), key);
                if (!p) {
                    const ParamValue* x = def.find(key);
                    fail(x ? x->pos() : def.pos(), what + " " + key + " cannot be bound to a texture; expected a spectrum");
                }
                m.textures.push_back({p, texture});
            }
            Spectrum emission;
            int emission_texture = -1;
            if (const ParamValue* x = def.find("emission")) emission = emission_value(*x, what, emission_texture);
            all_read(def, def.peek("type") ? what + " of type " + quote_text(type) : what);
            add_material(std::move(m), def.pos());
            m_material_emission.push_back(std::move(emission));
            m_material_emission_texture.push_back(emission_texture);
            m_material_index[name] = static_cast<int>(m_scene.materials.size()) - 1;
        }
    }

    /// Float parameters of the microfacet types: a number, or {"texture": NAME} of a number
    /// texture whose every value lies in the range (recorded in `bound`, its largest value
    /// returned: the envelope).
    FloatParameter float_parameter(std::vector<std::pair<std::string, int>>& bound) {
        return [this, &bound](const ParamValue& v, const std::string& key, const std::string& what, double lo,
                              double hi, bool lo_open) -> float {
            if (!TextureParser::is_binding(v)) return static_cast<float>(number_in(v, what, lo, hi, lo_open));
            const int t = m_textures.bind(v, what, TextureUse::number);
            for (const float x : m_scene.textures[static_cast<std::size_t>(t)].values)
                if (!((lo_open ? x > lo : x >= lo) && x <= hi)) {
                    std::ostringstream msg;
                    msg << what << " texture has the value " << x << "; expected every value in " << (lo_open ? "(" : "[")
                        << lo << ", " << hi << "]";
                    fail(v.pos(), msg.str());
                }
            bound.emplace_back(key, t);
            return m_textures.max_number(t);
        };
    }

    /// An emission spectrum, or {"texture": NAME, "scale": S}: then `texture` is set and the
    /// result is the texture's mean over its (u, v) square (the light's power for light
    /// selection: Scene::light_textures).
    Spectrum emission_value(const ParamValue& x, const std::string& what, int& texture) {
        if (!TextureParser::is_binding(x)) return spectrum(x, what + " emission", SpectrumUse::Emission);
        texture = m_textures.bind(x, what + " emission", TextureUse::emission);
        return m_textures.mean(texture);
    }

    /// Makes the emitter of a shape; a textured one records its texture, read at the surface
    /// coordinates of the light's points.
    template <typename MakeEmitter>
    int emitter(const MakeEmitter& make_emitter, const Spectrum& le, int texture) {
        const int light = make_emitter(le);
        if (texture < 0) return light;
        m_scene.light_textures.resize(m_scene.lights.size(), -1);
        m_scene.light_textures[static_cast<std::size_t>(light)] = texture;
        return light;
    }

    int add_material(Material m, SourcePos pos) {
        try {
            validate_material(m);
        } catch (const SceneError& e) {
            fail(pos, e.what());
        }
        return m_scene.add_material(std::move(m));
    }

    /// What a shape is made of: its material index, and the index of the emitter attached
    /// to it (−1 if it does not emit).
    struct Surface {
        int material = -1;
        int light = -1;
    };

    /// The surface of a shape of the given kind: "material": NAME (emitting if the material
    /// has "emission"), or "emission": SPECTRUM (a black emitter).
    Surface shape_surface(const ParamValue& v, const std::string& what, ShapeKind kind) {
        return shape_surface(v, what, [&](const Spectrum& le) { return m_scene.add_emitter(kind, le); });
    }

    /// shape_surface with the shape's own way of making its emitter (a quad's light knows
    /// its corners), and the emitter's sides ("two_sided", default true: both emit).
    template <typename MakeEmitter>
    Surface shape_surface(const ParamValue& v, const std::string& what, const MakeEmitter& make_emitter) {
        const Surface surface = surface_of(v, what, make_emitter);
        const ParamValue* two_sided = v.find("two_sided");
        if (!two_sided) return surface;
        if (!two_sided->is_bool()) wrong_type(*two_sided, what + " two_sided", "true or false");
        if (surface.light < 0)
            fail(two_sided->pos(), what + " has \"two_sided\" but emits nothing; expected it only on an emitting shape");
        if (two_sided->as_bool()) return surface;
        Light& light = m_scene.lights[static_cast<std::size_t>(surface.light)];
        if (!light_can_be_one_sided(light))
            fail(two_sided->pos(), what + " always emits from both sides; expected \"two_sided\": false only on a "
                                          "quad, triangle, mesh, disk, cylinder or cone");
        light_make_one_sided(light);
        return surface;
    }

    template <typename MakeEmitter>
    Surface surface_of(const ParamValue& v, const std::string& what, const MakeEmitter& make_emitter) {
        const ParamValue* name = v.find("material");
        const ParamValue* emission = v.find("emission");
        if (name && emission) fail(v.pos(), what + " has both \"material\" and \"emission\"; expected one of them");
        Surface surface;
        if (emission) {
            Material m;
            m.name = what + " emission";
            m.bsdf = DiffuseBsdf{};  // reflects nothing
            int texture = -1;
            const Spectrum le = emission_value(*emission, what, texture);
            surface.material = add_material(std::move(m), emission->pos());
            m_material_emission.emplace_back();
            m_material_emission_texture.push_back(-1);
            if (!le.is_zero()) surface.light = emitter(make_emitter, le, texture);
            return surface;
        }
        if (!name && (v.find("interior") || v.find("exterior"))) {
            surface.material = interface_material();  // bounds a medium, invisible
            return surface;
        }
        if (!name) {
            misspelt(v, what, {"material", "emission"});
            fail(v.pos(), what + " has neither \"material\" nor \"emission\"; expected one of them");
        }
        const std::string& n = string(*name, what + " material");
        if (auto it = m_material_index.find(n); it != m_material_index.end()) {
            surface.material = it->second;
            const Spectrum& le = m_material_emission[static_cast<std::size_t>(it->second)];
            const int texture = m_material_emission_texture[static_cast<std::size_t>(it->second)];
            if (!le.is_zero()) surface.light = emitter(make_emitter, le, texture);
            return surface;
        }
        std::vector<std::string> known;
        for (const auto& [k, i] : m_material_index) known.push_back(k);
        fail(name->pos(), "unknown material " + quote_text(n) + "." + suggestion(n, known) +
                              (known.empty() ? " Expected a material defined in \"materials\" (there are none)"
                                             : " Expected one of: " + join(known)));
    }

    // ---------------------------- Shapes ----------------------------

    /// A point under a transform (AffineMap, in double), rounded to float once.
    static Vec3 apply(const AffineMap& map, const Vec3& p) {
        const DVec3 q = map.point(DVec3(p.x, p.y, p.z));
        return {static_cast<float>(q.x), static_cast<float>(q.y), static_cast<float>(q.z)};
    }
    /// A normal under a transform: the inverse transpose of A, as its cofactor matrix times the
    /// sign of the determinant (a mirroring scale turns the surface inside out), normalised;
    /// zero for a zero normal.
    static Vec3 apply_normal(const AffineMap& map, const Vec3& n) {
        const double sign = map.determinant() < 0 ? -1.0 : 1.0;
        const DVec3 c = map.cofactor_vector(DVec3(n.x, n.y, n.z));
        const double out[3] = {sign * c.x, sign * c.y, sign * c.z};
        const double len = std::sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2]);
        if (!(len > 0.0) || !std::isfinite(len)) return {};
        return {static_cast<float>(out[0] / len), static_cast<float>(out[1] / len), static_cast<float>(out[2] / len)};
    }

    /// "matrix": 16 numbers, a 4×4 row-major matrix acting on column vectors [x y z 1]ᵀ: an
    /// affine map (last row 0 0 0 1) whose 3×3 part is invertible.
    AffineMap matrix(const ParamValue& v) const {
        const std::vector<double> m = numbers(v, "transform matrix", 16);
        for (double x : m)
            if (!std::isfinite(x)) fail(v.pos(), "transform matrix has the element " + number_text(x) + "; expected finite numbers");
        if (m[12] != 0 || m[13] != 0 || m[14] != 0 || m[15] != 1)
            fail(v.pos(), "transform matrix has the last row [" + number_text(m[12]) + ", " + number_text(m[13]) + ", " +
                              number_text(m[14]) + ", " + number_text(m[15]) +
                              "]: not an affine map; expected [0, 0, 0, 1] (projective maps are not supported)");
        AffineMap tr;
        double size = 0;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 4; ++j) {
                tr.a[i][j] = m[static_cast<std::size_t>(4 * i + j)];
                if (j < 3) size = std::max(size, std::fabs(tr.a[i][j]));
            }
        if (!(std::fabs(tr.determinant()) > 1e-12 * size * size * size))
            fail(v.pos(), "transform matrix is singular (its 3x3 part has determinant " + number_text(tr.determinant()) +
                              "); expected an invertible map");
        return tr;
    }

    /// Scale, then rotate about an axis through the origin, then translate; or a "matrix".
    AffineMap transform(const ParamValue* v) const {
        AffineMap tr;
        if (!v) return tr;
        object(*v, "transform");
        if (const ParamValue* m = v->find("matrix")) {
            for (const char* key : {"scale", "rotate", "translate"})
                if (const ParamValue* other = v->find(key))
                    fail(other->pos(), std::string("transform has both \"matrix\" and \"") + key +
                                           "\"; expected one of them (a matrix is the whole map)");
            tr = matrix(*m);
            all_read(*v, "transform");
            return tr;
        }
        double s[3] = {1, 1, 1};
        if (const ParamValue* sv = v->find("scale")) {
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
        if (const ParamValue* rv = v->find("rotate")) {
            object(*rv, "transform rotate");
            const Vec3 a = direction(required(*rv, "axis", "transform rotate"), "transform rotate axis");
            const double deg = number_in(required(*rv, "degrees", "transform rotate"), "transform rotate degrees", -36000, 36000);
            const double len = std::sqrt(double(a.x) * a.x + double(a.y) * a.y + double(a.z) * a.z);
            const double x = a.x / len, y = a.y / len, z = a.z / len;
            const double th = deg * 3.14159265358979323846 / 180.0, c = std::cos(th), sn = std::sin(th), k = 1 - c;
            const double rot[3][3] = {{c + x * x * k, x * y * k - z * sn, x * z * k + y * sn},
                                      {y * x * k + z * sn, c + y * y * k, y * z * k - x * sn},
                                      {z * x * k - y * sn, z * y * k + x * sn, c + z * z * k}};
            std::copy(&rot[0][0], &rot[0][0] + 9, &r[0][0]);
            all_read(*rv, "transform rotate");
        }
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) tr.a[i][j] = r[i][j] * s[j];
        if (const ParamValue* tv = v->find("translate")) {
            const Vec3 t = point(*tv, "transform translate");
            tr.a[0][3] = t.x, tr.a[1][3] = t.y, tr.a[2][3] = t.z;
        }
        all_read(*v, "transform");
        return tr;
    }

    /// The mesh of the PLY file named by `v`; `display` becomes the file's name for messages.
    PlyMesh ply_mesh(const ParamValue& v, const std::string& what, std::string& display) const {
        const std::string& file = string(v, what + " file");
        std::string contents, error;
        if (file.empty() || !m_read_relative(file, contents, display, error))
            fail(v.pos(), "cannot read mesh " + quote_text(file) + (error.empty() ? "" : ": " + error) +
                              "; expected a PLY file path relative to the scene file");
        return parse_ply(contents, display);
    }

    /// A flat array of finite numbers, a multiple of `group` long.
    std::vector<double> flat_numbers(const ParamValue& v, const std::string& what, std::size_t group) const {
        if (!v.is_array()) wrong_type(v, what, "a flat array of numbers");
        if (v.items().size() % group != 0)
            fail(v.pos(), what + " has " + std::to_string(v.items().size()) + " numbers; expected a multiple of " +
                              std::to_string(group));
        std::vector<double> out;
        out.reserve(v.items().size());
        for (const ParamValue& x : v.items()) {
            out.push_back(number(x, "an element of " + what));
            if (!std::isfinite(out.back())) fail(x.pos(), what + " has " + number_text(out.back()) + "; expected finite numbers");
        }
        return out;
    }

    /// The mesh given in the scene: "positions" (x y z per vertex), "indices" (three per
    /// triangle), optional "normals" and "uv" per vertex; the data a PLY file gives.
    PlyMesh inline_mesh(const ParamValue& v, const ParamValue& positions, const std::string& what) const {
        PlyMesh mesh;
        const std::vector<double> p = flat_numbers(positions, what + " positions", 3);
        const std::size_t n = p.size() / 3;
        for (std::size_t i = 0; i < n; ++i)
            mesh.positions.emplace_back(static_cast<float>(p[3 * i]), static_cast<float>(p[3 * i + 1]), static_cast<float>(p[3 * i + 2]));
        auto per_vertex = [&](const char* key, std::size_t group) {
            const ParamValue* a = v.find(key);
            if (!a) return std::vector<double>{};
            std::vector<double> x = flat_numbers(*a, what + " " + key, group);
            if (x.size() != group * n)
                fail(a->pos(), what + " " + key + " has " + std::to_string(x.size()) + " numbers; expected " +
                                   std::to_string(group) + " per vertex (" + std::to_string(group * n) + ")");
            return x;
        };
        const std::vector<double> normals = per_vertex("normals", 3), uv = per_vertex("uv", 2);
        for (std::size_t i = 0; i < normals.size() / 3; ++i)
            mesh.normals.emplace_back(static_cast<float>(normals[3 * i]), static_cast<float>(normals[3 * i + 1]),
                                      static_cast<float>(normals[3 * i + 2]));
        for (std::size_t i = 0; i < uv.size() / 2; ++i)
            mesh.uvs.push_back({static_cast<float>(uv[2 * i]), static_cast<float>(uv[2 * i + 1])});
        const ParamValue& iv = required(v, "indices", what);
        const std::vector<double> indices = flat_numbers(iv, what + " indices", 3);
        for (std::size_t t = 0; t < indices.size() / 3; ++t) {
            std::array<std::uint32_t, 3> tri{};
            for (std::size_t k = 0; k < 3; ++k) {
                const double x = indices[3 * t + k];
                if (x != std::floor(x) || x < 0 || x >= static_cast<double>(n))
                    fail(iv.items()[3 * t + k].pos(), what + " indices: triangle " + std::to_string(t) + " has the index " +
                                                          number_text(x) + "; expected an integer from 0 to below the vertex count, " +
                                                          std::to_string(n));
                tri[k] = static_cast<std::uint32_t>(x);
            }
            mesh.triangles.push_back(tri);
        }
        return mesh;
    }

    void add_triangle(const Vec3& a, const Vec3& b, const Vec3& c, Surface surface, SourcePos pos,
                      const std::string& what) {
        Triangle t{a, b, c, surface.material};
        t.light = surface.light;
        if (!is_finite(a) || !is_finite(b) || !is_finite(c))
            fail(pos, what + " has a vertex that is not finite after its transform; expected finite coordinates");
        if (t.is_degenerate()) fail(pos, what + " has zero area; expected three vertices that are not collinear");
        m_scene.triangles.push_back(t);
    }

    /// A direction (non-zero) normalised; an error at the value if it cannot be.
    Vec3 unit_direction(const ParamValue& v, const std::string& what) const {
        const Vec3 n = normalize(direction(v, what));
        if (!is_finite(n)) fail(v.pos(), what + " cannot be normalised; expected a direction of moderate length");
        return n;
    }

    /// A length > 0 that stays > 0 in single precision.
    float positive_size(const ParamValue& shape, const char* key, const std::string& what) const {
        const ParamValue& v = required(shape, key, what);
        const auto x = static_cast<float>(number_in(v, what + " " + key, 0, kMaxSceneCoordinate, true));
        if (!(x > 0.f)) fail(v.pos(), what + " " + key + " rounds to 0 in single precision; expected a larger value");
        return x;
    }

    void shape(const ParamValue& v) {
        const std::string index = std::to_string(m_shape_count++);
        object(v, "shape " + index);
        const std::string& type = string(required(v, "type", "shape " + index), "shape " + index + " type");
        const std::string what = type + " (shape " + index + ")";
        const ParamValue* motion_key = v.find("motion");
        const ShapeCounts first = m_scene.shape_counts();
        shape_of_type(v, type, what);
        if (motion_key) make_moving(*motion_key, what, first);
        record_medium_interface(v);
        all_read(v, what);
    }

    // ---------------------------- Media ----------------------------

    void media_section(const ParamValue& v) {
        object(v, "media");
        const MediumParser parser(files(), m_spectra, m_read_relative);
        for (const auto& [name, def] : v.members()) {
            if (name == "vacuum") fail(def.pos(), "medium name \"vacuum\" is reserved (no medium); expected another name");
            m_scene.media.push_back(parser.medium(name, def));
        }
    }

    /// A medium by name ("vacuum": none, −1), as the value of `what`.
    int medium_ref(const ParamValue& v, const std::string& what) const {
        const std::string& name = string(v, what);
        if (name == "vacuum") return -1;
        std::vector<std::string> known = {"vacuum"};
        for (std::size_t i = 0; i < m_scene.media.size(); ++i) {
            if (m_scene.media[i].name == name) return static_cast<int>(i);
            known.push_back(m_scene.media[i].name);
        }
        fail(v.pos(), "unknown medium " + quote_text(name) + "." + suggestion(name, known) +
                          " Expected one of: " + join(known) + " (defined in \"media\")");
    }

    /// The shape's two sides ("interior", "exterior"; by default vacuum inside and the
    /// camera's medium outside) for each primitive the shape added. Scenes without media keep
    /// no interfaces.
    void record_medium_interface(const ParamValue& v) {
        const ParamValue* in = v.find("interior");
        const ParamValue* out = v.find("exterior");
        if (m_scene.media.empty()) {
            if (in || out) fail((in ? in : out)->pos(), "a shape names a medium but the scene defines none; "
                                                         "expected a \"media\" section");
            return;
        }
        MediumInterface mi{-1, m_scene.camera_medium};
        if (in) mi.interior = medium_ref(*in, "interior");
        if (out) mi.exterior = medium_ref(*out, "exterior");
        m_scene.extend_shape_media(mi);
    }

    /// The material of shapes without a surface (made once).
    int interface_material() {
        if (m_scene.interface_material < 0) {
            Material m;
            m.name = "interface (no surface)";
            m.bsdf = DiffuseBsdf{};
            m_scene.interface_material = add_material(std::move(m), {});
            m_material_emission.emplace_back();
        }
        return m_scene.interface_material;
    }

    /// The shapes just added (from `first` on) become one moving shape.
    void make_moving(const ParamValue& motion_key, const std::string& what, const ShapeCounts& first) {
        if (!m_scene.can_move_since(first))
            fail(motion_key.pos(), what + " cannot move; expected \"motion\" on a bounded shape (not a plane)");
        if (m_scene.emits_since(first)) fail(motion_key.pos(), what + " emits light and moves; expected a shape without emission to move (moving emitters are not supported)");
        m_scene.make_moving(first, motion(motion_key, what, m_scene.pivot_box_since(first).centroid()));
    }

    void shape_of_type(const ParamValue& v, const std::string& type, const std::string& what) {
        if (type == "sphere") {
            Sphere s;
            s.center = point(required(v, "center", what), what + " center");
            s.radius = static_cast<float>(number_in(required(v, "radius", what), what + " radius", 0, kMaxSceneCoordinate, true));
            if (!(s.radius > 0.f)) fail(v.find("radius")->pos(), what + " radius rounds to 0 in single precision; expected a larger radius");
            const Surface surface = shape_surface(v, what, ShapeKind::sphere);
            s.material = surface.material;
            s.light = surface.light;
            m_scene.spheres.push_back(s);
        } else if (type == "plane") {
            const ParamValue& nv = required(v, "normal", what);
            const Vec3 n = normalize(direction(nv, what + " normal"));
            const Vec3 p = point(required(v, "point", what), what + " point");
            if (!is_finite(n)) fail(nv.pos(), what + " normal cannot be normalised; expected a normal of moderate length");
            Plane plane;
            plane.normal = n;
            plane.offset = static_cast<float>(double(n.x) * p.x + double(n.y) * p.y + double(n.z) * p.z);
            const Surface surface = shape_surface(v, what, ShapeKind::plane);
            plane.material = surface.material;
            plane.light = surface.light;
            m_scene.planes.push_back(plane);
        } else if (type == "quad") {
            look_up(v, {"edge1", "edge2"});
            const Vec3 o = point(required(v, "origin", what), what + " origin");
            const Vec3 e1 = direction(required(v, "edge1", what), what + " edge1");
            const Vec3 e2 = direction(required(v, "edge2", what), what + " edge2");
            const AffineMap tr = transform(v.find("transform"));
            const Vec3 a = apply(tr, o), b = apply(tr, o + e1), c = apply(tr, o + e1 + e2), d = apply(tr, o + e2);
            const Surface m = shape_surface(
                v, what, [&](const Spectrum& le) { return m_scene.add_quad_emitter(a, b - a, d - a, le); });
            add_triangle(a, b, c, m, v.pos(), what);
            add_triangle(a, c, d, m, v.pos(), what);
            // (u, v) = the position along edge1 and edge2, each in [0, 1] (Scene::surface_uv),
            // for quads with a texture: vertex attributes on other quads would cost a look-up
            // at every hit (Scene::triangle_hit) for coordinates nothing reads.
            const bool textured = m_scene.materials[static_cast<std::size_t>(m.material)].textured ||
                                  (m.light >= 0 && m_scene.light_textured(m.light));
            const float uv[2][3][2] = {{{0, 0}, {1, 0}, {1, 1}}, {{0, 0}, {1, 1}, {0, 1}}};
            for (int k = 0; k < 2 && textured; ++k) {
                TriangleAttributes attr;
                std::memcpy(attr.uv, uv[k], sizeof attr.uv);
                attr.has_uv = true;
                m_scene.triangles[m_scene.triangles.size() - 2 + static_cast<std::size_t>(k)].attributes =
                    static_cast<int>(m_scene.triangle_attributes.size());
                m_scene.triangle_attributes.push_back(attr);
            }
        } else if (type == "triangle") {
            const ParamValue& vs = required(v, "vertices", what);
            if (!vs.is_array() || vs.items().size() != 3)
                fail(vs.pos(), what + " vertices is not an array of 3 points; expected [[x, y, z], [x, y, z], [x, y, z]]");
            const Vec3 a = point(vs.items()[0], what + " vertex"), b = point(vs.items()[1], what + " vertex"),
                       c = point(vs.items()[2], what + " vertex");
            add_triangle(a, b, c, shape_surface(v, what, ShapeKind::triangle), v.pos(), what);
        } else if (type == "mesh") {
            const ParamValue* file = v.find("file");
            const ParamValue* positions = v.find("positions");
            if (file && positions) fail(positions->pos(), what + " has both \"file\" and \"positions\"; expected one of them");
            if (!file && !positions) {
                misspelt(v, what, {"file", "positions"});
                fail(v.pos(), what + " has neither \"file\" nor \"positions\"; expected one of them");
            }
            const ParamValue& fv = file ? *file : *positions;
            // Instances: the triangles are kept once, in the file's space, and placed by each
            // transform (two-level BVH); otherwise they are transformed into the scene's list.
            const ParamValue* instances = v.find("instances");
            if (instances && v.find("transform"))
                fail(instances->pos(), what + " has both \"transform\" and \"instances\"; expected one of them (each instance is a transform)");
            if (instances && (!instances->is_array() || instances->items().empty()))
                fail(instances->pos(), what + " instances is not a non-empty array; expected [TRANSFORM, ...] (objects like \"transform\")");
            const AffineMap tr = transform(v.find("transform"));
            const Surface m = shape_surface(v, what, ShapeKind::triangle);
            if (instances && m.light >= 0)
                fail(instances->pos(), what + " emits light and has instances; expected a non-emitting material (an emitter is one mesh per placement)");
            std::vector<Triangle> object_triangles;
            std::vector<Triangle>& target = instances ? object_triangles : m_scene.triangles;
            std::string display = "inline mesh";
            const PlyMesh mesh = file ? ply_mesh(*file, what, display) : inline_mesh(v, *positions, what);
            std::vector<Vec3> p;
            p.reserve(mesh.positions.size());
            for (const Vec3& x : mesh.positions) {
                if (std::fabs(x.x) > kMaxSceneCoordinate || std::fabs(x.y) > kMaxSceneCoordinate || std::fabs(x.z) > kMaxSceneCoordinate)
                    fail(fv.pos(), what + ": a vertex of " + quote_text(display) + " has a coordinate beyond 1e15; expected smaller coordinates");
                p.push_back(apply(tr, x));
            }
            std::vector<Vec3> normals;
            normals.reserve(mesh.normals.size());
            for (const Vec3& n : mesh.normals) normals.push_back(apply_normal(tr, n));
            std::size_t added = 0;
            for (const auto& t : mesh.triangles) {
                Triangle tri{p[t[0]], p[t[1]], p[t[2]], m.material};
                tri.light = m.light;
                if (tri.is_degenerate()) continue;  // zero-area faces are common in scanned meshes: never hit
                if (!is_finite(tri.p0) || !is_finite(tri.p1) || !is_finite(tri.p2))
                    fail(fv.pos(), what + " has a vertex that is not finite after its transform; expected finite coordinates");
                if (!mesh.normals.empty() || !mesh.uvs.empty()) {
                    TriangleAttributes a;
                    for (int k = 0; k < 3; ++k) {
                        if (!normals.empty()) a.n[k] = normals[t[k]];
                        if (!mesh.uvs.empty()) a.uv[k][0] = mesh.uvs[t[k]][0], a.uv[k][1] = mesh.uvs[t[k]][1];
                    }
                    // A vertex without a usable normal (zero length) leaves its triangles flat.
                    a.has_normals = !normals.empty() && a.n[0] != Vec3{} && a.n[1] != Vec3{} && a.n[2] != Vec3{};
                    a.has_uv = !mesh.uvs.empty();
                    tri.attributes = static_cast<int>(m_scene.triangle_attributes.size());
                    m_scene.triangle_attributes.push_back(a);
                }
                target.push_back(tri);
                ++added;
            }
            if (added == 0) fail(fv.pos(), what + ": " + quote_text(display) + " has no triangle of non-zero area; expected at least one");
            // A mesh that names its media says which side is which: it may be one piece of a
            // closed boundary (a glass's wall against the liquid), so it need not close alone.
            const bool sides_named = v.find("interior") || v.find("exterior");
            if (m_scene.materials[m.material].flags.has(BsdfFlags::transmission) && !sides_named)
                check_refracting_mesh(p, mesh, m.material, what, display);
            if (instances) {
                const int mesh_index = static_cast<int>(m_scene.instanced_meshes.size());
                m_scene.instanced_meshes.push_back({std::move(object_triangles), {}, {}});
                for (const ParamValue& item : instances->items())
                    m_scene.instances.emplace_back(mesh_index, transform(&item));
            }
        } else if (type == "disk") {
            Disk d;
            d.center = point(required(v, "center", what), what + " center");
            d.normal = unit_direction(required(v, "normal", what), what + " normal");
            d.radius = positive_size(v, "radius", what);
            const Surface surface = shape_surface(v, what, ShapeKind::disk);
            d.material = surface.material, d.light = surface.light;
            m_scene.disks.push_back(d);
        } else if (type == "cylinder" || type == "cone") {
            look_up(v, {"axis", "radius", "height"});
            const Vec3 base = point(required(v, "base", what), what + " base");
            const Vec3 axis = unit_direction(required(v, "axis", what), what + " axis");
            const float radius = positive_size(v, "radius", what), height = positive_size(v, "height", what);
            const Surface surface = shape_surface(v, what, type == "cone" ? ShapeKind::cone : ShapeKind::cylinder);
            if (type == "cone") m_scene.cones.push_back({base, axis, radius, height, surface.material, surface.light});
            else m_scene.cylinders.push_back({base, axis, radius, height, surface.material, surface.light});
        } else {
            const std::vector<std::string> types = {"sphere", "plane",    "quad",     "triangle",
                                                    "mesh",   "disk",     "cylinder", "cone"};
            fail(v.find("type")->pos(), "unknown shape type " + quote_text(type) + "." + suggestion(type, types) +
                                            " Expected one of: " + join(types));
        }
    }
    int m_shape_count = 0;

    /// {"type": "spot", "position", "direction", "intensity", "cone_degrees", "falloff_degrees"}.
    void spot_light(const ParamValue& v) {
        SpotLight s;
        look_up(v, {"cone_degrees", "falloff_degrees"});
        s.position = point(required(v, "position", "spot light"), "spot light position");
        s.direction = unit_direction(required(v, "direction", "spot light"), "spot light direction");
        s.intensity = spectrum(required(v, "intensity", "spot light"), "spot light intensity", SpectrumUse::Emission);
        const double cone = number_in(required(v, "cone_degrees", "spot light"), "spot light cone_degrees", 0, 180, true);
        double falloff = cone;
        if (const ParamValue* f = v.find("falloff_degrees"))
            falloff = number_in(*f, "spot light falloff_degrees", 0, cone);
        constexpr double kRadians = 3.14159265358979323846 / 180.0;
        s.cos_cone = static_cast<float>(std::cos(cone * kRadians));
        s.cos_falloff = static_cast<float>(std::cos(falloff * kRadians));
        m_scene.lights.emplace_back(std::move(s));
        all_read(v, "spot light");
    }

    void point_light(const ParamValue& v) {
        const ParamValue* motion_key = v.find("motion");
        const Vec3 position = point(required(v, "position", "point light"), "point light position");
        m_scene.add_point_light(position, spectrum(required(v, "intensity", "point light"), "point light intensity",
                                                   SpectrumUse::Emission));
        if (motion_key) std::get<PointLight>(m_scene.lights.back()).motion = motion(*motion_key, "point light", position);
        all_read(v, "point light");
    }

    /// A light type of the "lights" section: its name and its create function. Area lights
    /// are not here: they are shapes with "emission".
    struct LightType {
        const char* name;
        void (Builder::*create)(const ParamValue& v);
    };

    void light(const ParamValue& v) {
        static constexpr LightType kLightTypes[] = {
            {"point", &Builder::point_light},
            {"spot", &Builder::spot_light},
        };
        object(v, "light");
        const std::string& type = string(required(v, "type", "light"), "light type");
        std::vector<std::string> names;
        for (const LightType& t : kLightTypes) {
            if (type == t.name) return (this->*t.create)(v);
            names.emplace_back(t.name);
        }
        fail(v.find("type")->pos(), "unknown light type " + quote_text(type) + "." + suggestion(type, names) +
                                        " Expected " + quoted_alternatives(names) + " (area lights are shapes with \"emission\")");
    }
};

/// The bins the scene's lights need (spectral/line_spectra.h): the most any light with one
/// spectrum (area lights, point and spot lights, a constant background) needs.
int bins_for_lights(const Scene& scene) {
    // Each distinct spectrum once: bins_for_light renders a colour chart (0.1 ms), and a
    // scene of ten thousand emitting triangles has a handful of spectra.
    std::vector<const SpectrumSource*> seen;
    int bins = SpectralResolution::kDefaultBins;
    auto consider = [&](const SpectrumSource& source) {
        if (std::ranges::any_of(seen, [&](const SpectrumSource* s) { return *s == source; })) return;
        seen.push_back(&source);
        bins = std::max(bins, bins_for_light(source));
    };
    for (const Light& light : scene.lights)
        std::visit([&](const auto& l) {
            if constexpr (requires { l.Le.source(); }) consider(l.Le.source());
            if constexpr (requires { l.intensity.source(); }) consider(l.intensity.source());
        }, light);
    return bins;
}

}  // namespace

Scene build_scene(const SceneDescription& description, SpectralResolution resolution,
                  const RelativeFileReader& read_relative) {
    Scene scene = Builder(description.files, resolution, read_relative).load(description.root, description.name);
    SpectralResolution used = resolution;
    std::string why;
    if (scene.effects.fluorescence && resolution.bins != SpectralResolution::kExact) {
        // Fluorescence carries light from the UV (model/fluorescence.h: transport from 300
        // nm) but bins stop at 380 nm, where a 365 nm lamp would read its 380 nm value: such
        // scenes evaluate every spectrum exactly.
        used.bins = SpectralResolution::kExact;
        why = "fluorescence reaches below the bins' 380 nm";
    } else if (resolution.automatic && resolution.bins != SpectralResolution::kExact) {
        used.bins = std::max(resolution.bins, bins_for_lights(scene));
        if (used.bins != resolution.bins) why = "the lights' narrow lines need them";
    }
    if (used.bins != resolution.bins)
        scene = Builder(description.files, used, read_relative).load(description.root, description.name);
    scene.spectral_resolution = used;
    scene.spectral_resolution_reason = why;
    return scene;
}

}  // namespace spt

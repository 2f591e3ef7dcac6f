// Environment maps in scene files and renders: the JSON background {"type": "image", ...}
// (file relative to the scene, mapping, scale, illuminance, transform, sampling options), its
// malformed inputs (one located line each), pbrt-v4's `LightSource "infinite"` with a
// `filename`, and renders that must agree: light sampling only, BSDF sampling only and MIS
// in the path tracer; importance against uniform sampling; bdpt, vcm and the volumetric
// path tracer against the path tracer. The maps are tiny PFMs written here.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "io/image.h"
#include "io/image_encoders.h"
#include "io/image_writer.h"
#include "scene/pbrt_scene_writer.h"
#include "scene/scene_loader.h"
#include "spectral/rgb_texels.h"
#include "test_scenes.h"
#include "vcm_passes.h"

namespace spt {
namespace {

using test::compare;
using test::Comparison;
using test::describe;
using test::render_film;
using test::small_settings;

/// A fresh folder for this test's files.
std::filesystem::path folder(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / ("spt_envmap_" + name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

void write_file(const std::filesystem::path& p, const std::string& bytes) {
    std::ofstream out(p, std::ios::binary);
    out << bytes;
}

/// A w × h PFM of linear RGB texels f(x, y) (row 0 the top), by the renderer's own writer.
template <class F>
void write_pfm(const std::filesystem::path& p, int w, int h, F f) {
    Image img;
    img.width = w, img.height = h;
    img.rgb.resize(std::size_t(w) * std::size_t(h) * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::array<float, 3> c = f(x, y);
            std::copy(c.begin(), c.end(), img.pixel(x, y));
        }
    write_file(p, encode_pfm(img, ImageWriteOptions{}));
}

/// A sky of the given colour with a sun of a few texels (50× brighter) up and to the side.
std::array<float, 3> sky(int x, int y, int w, int h) {
    if (std::abs(x - w / 3) <= 1 && std::abs(y - h / 4) <= 1) return {40.f, 36.f, 30.f};
    return {0.3f, 0.45f, 0.8f * (1.f - 0.5f * float(y) / float(h))};
}

std::string scene_text(const std::string& background, const std::string& extra = "", const std::string& shapes = "") {
    return R"({"camera": {"position": [0, 0.4, 3], "look_at": [0, 0.1, 0], "vfov_degrees": 50},
      "materials": {"white": {"type": "diffuse", "kd": 0.7}, "plastic": {"kd": 0.4, "ks": 0.3}},
      "background": )" + background + extra + R"(,
      "shapes": [)" + shapes + R"({"type": "sphere", "center": [-0.45, 0.3, 0], "radius": 0.4, "material": "white"},
                 {"type": "sphere", "center": [0.5, 0.25, 0.2], "radius": 0.3, "material": "plastic"},
                 {"type": "quad", "origin": [-2, -0.1, -2], "edge1": [0, 0, 4], "edge2": [4, 0, 0], "material": "white"}]})";
}

Scene load(const std::filesystem::path& dir, const std::string& text, const std::string& name = "scene.json") {
    write_file(dir / name, text);
    return load_scene_file((dir / name).string(), {});
}

std::string error_of(const std::filesystem::path& dir, const std::string& text) {
    try {
        load(dir, text);
    } catch (const LocatedError& e) {
        return e.what();
    }
    return "(no error)";
}

struct ErrorCase {
    std::string text, expected;
};

/// Each case's scene text (written into `dir`) fails to load with one line starting with
/// `expected` (file names compared from the folder on: the command line gave them absolute).
void expect_located_errors(const std::filesystem::path& dir, const std::vector<ErrorCase>& cases) {
    for (const ErrorCase& c : cases) {
        std::string e = error_of(dir, c.text);
        for (std::size_t at; (at = e.find(dir.string() + "/")) != std::string::npos;) e.erase(at, dir.string().size() + 1);
        EXPECT_EQ(e.rfind(c.expected, 0), 0u) << "got: " << e << "\nexpected it to start with: " << c.expected;
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    }
}

/// The pbrt-v4 text this program writes for the scene file `file` (written next to it).
std::string exported_pbrt(const std::filesystem::path& dir, const std::string& file) {
    const std::optional<SceneSource> src = read_scene_source((dir / file).string());
    EXPECT_TRUE(src.has_value());
    if (!src) return "";
    PbrtExportSettings settings;
    settings.output_path = (dir / "out.pbrt").string();
    settings.scene_folder = src->folder;
    settings.read_relative = src->read_relative;
    return export_pbrt(src->description, settings).text;
}

const EnvironmentMapLight& map_of(const Scene& s) {
    EXPECT_EQ(s.infinite_light_indices.size(), 1u);
    return std::get<EnvironmentMapLight>(s.lights.at(std::size_t(s.infinite_light_indices.at(0))));
}

TEST(EnvironmentMapScene, JsonBackgroundImageReadsItsOptions) {
    const auto dir = folder("options");
    write_pfm(dir / "sky.pfm", 16, 8, [](int x, int y) { return sky(x, y, 16, 8); });
    write_pfm(dir / "square.pfm", 8, 8, [](int x, int y) { return sky(x, y, 8, 8); });
    const SampledWavelengths lambda = SampledWavelengths::sample(0.3f);
    const Scene plain = load(dir, scene_text(R"({"type": "image", "file": "sky.pfm"})"));
    const EnvironmentMapLight& a = map_of(plain);
    EXPECT_EQ(a.map->mapping, EnvironmentMapping::equirect);
    EXPECT_EQ(a.sampling, EnvironmentSampling::importance);
    EXPECT_FALSE(a.mis_compensation);
    // "scale" multiplies the radiance; "transform" turns the map (90° about y: what was seen
    // along +x is seen along −z).
    const Scene turned = load(dir, scene_text(R"({"type": "image", "file": "sky.pfm", "scale": 2.5,
        "transform": {"rotate": {"axis": [0, 1, 0], "degrees": 90}}, "sampling": "uniform", "mis_compensation": true})"));
    const EnvironmentMapLight& b = map_of(turned);
    EXPECT_EQ(b.sampling, EnvironmentSampling::uniform);
    EXPECT_TRUE(b.mis_compensation);
    const Vec3 d = normalize(Vec3{1.f, 0.3f, 0.2f});
    const Vec3 d_turned{d.z, d.y, -d.x};
    EXPECT_NEAR(b.arriving(d_turned, lambda)[0], 2.5f * a.arriving(d, lambda)[0], 1e-5f * a.arriving(d, lambda)[0]);
    // "illuminance" sets the scale so that a surface facing the map's up receives it.
    const Scene lit = load(dir, scene_text(R"({"type": "image", "file": "square.pfm", "mapping": "equal_area", "illuminance": 3})"));
    const EnvironmentMapLight& c = map_of(lit);
    EXPECT_EQ(c.map->mapping, EnvironmentMapping::equal_area);
    EXPECT_NEAR(c.scale * c.map->up_illuminance, 3.0, 1e-5);
    // The constant background is unchanged.
    const Scene constant = load(dir, scene_text("0.5"));
    EXPECT_TRUE(std::holds_alternative<EnvironmentLight>(constant.lights.at(std::size_t(constant.infinite_light_indices.at(0)))));
}

TEST(EnvironmentMapScene, MalformedMapsAreOneLocatedLine) {
    const auto dir = folder("malformed");
    write_file(dir / "text.pfm", "not an image at all");
    write_pfm(dir / "nan.pfm", 4, 2, [](int x, int y) { return x == 2 && y == 1 ? std::array<float, 3>{1.f, std::nanf(""), 1.f} : std::array<float, 3>{1.f, 1.f, 1.f}; });
    write_pfm(dir / "inf.pfm", 4, 2, [](int x, int) { return x == 3 ? std::array<float, 3>{INFINITY, 1.f, 1.f} : std::array<float, 3>{1.f, 1.f, 1.f}; });
    write_pfm(dir / "negative.pfm", 4, 2, [](int x, int) { return x == 0 ? std::array<float, 3>{1.f, -0.5f, 1.f} : std::array<float, 3>{1.f, 1.f, 1.f}; });
    write_pfm(dir / "black.pfm", 4, 2, [](int, int) { return std::array<float, 3>{0.f, 0.f, 0.f}; });
    write_pfm(dir / "wide.pfm", 4, 2, [](int, int) { return std::array<float, 3>{1.f, 1.f, 1.f}; });
    // The background's "file" value is on line 3 of scene_text, after `"background": `.
    const auto bg = [](const std::string& members) { return scene_text("{\"type\": \"image\", " + members + "}"); };
    expect_located_errors(dir, {
        {bg(R"("file": "text.pfm")"), "scene.json:3:47: environment map \"text.pfm\": "},
        {bg(R"("file": "nan.pfm")"), "scene.json:3:47: environment map \"nan.pfm\": texel (2, 1) is NaN; expected finite radiance"},
        {bg(R"("file": "inf.pfm")"), "scene.json:3:47: environment map \"inf.pfm\": texel (3, 0) is infinite; expected finite radiance"},
        {bg(R"("file": "negative.pfm")"), "scene.json:3:47: environment map \"negative.pfm\": texel (0, 0) is negative"},
        {bg(R"("file": "black.pfm")"), "scene.json:3:47: environment map \"black.pfm\": every texel is black; expected a map that emits light"},
        {bg(R"("file": "wide.pfm", "mapping": "equal_area")"), "scene.json:3:47: environment map \"wide.pfm\": an equal-area map of 4 x 2 texels; expected a square image"},
        {bg(R"("file": "missing.pfm")"), "scene.json:3:47: cannot read environment map \"missing.pfm\""},
        {bg(R"("file": "wide.pfm", "mapping": "polar")"), "scene.json:3:70: unknown background image mapping \"polar\""},
        {bg(R"("file": "wide.pfm", "scale": 1, "illuminance": 2)"), "scene.json:3:86: background image has both \"scale\" and \"illuminance\""},
        {bg(R"("file": "wide.pfm", "transform": {"scale": [1, 2, 1]})"), "scene.json:3:72: background image transform shears or stretches directions"},
        {bg(R"("file": "wide.pfm", "sampling": "cosine")"), "scene.json:3:71: unknown background image sampling \"cosine\""},
        {bg(R"("file": "wide.pfm", "colour": 1)"), "scene.json:3:59: unknown key \"colour\" in background image"},
    });
}

TEST(EnvironmentMapScene, PbrtInfiniteLightWithAFilename) {
    // pbrt-v4: an equal-area map in light space (+z up), turned by the CTM at the LightSource,
    // times scale; "illuminance" as pbrt-v4 renders it.
    const auto dir = folder("pbrt");
    write_pfm(dir / "sky.pfm", 8, 8, [](int x, int y) { return sky(x, y, 8, 8); });
    const std::string camera = "LookAt 0 0 3  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 45\nWorldBegin\n";
    const Scene plain = load(dir, camera + "LightSource \"infinite\" \"string filename\" \"sky.pfm\"\n", "a.pbrt");
    const EnvironmentMapLight& a = map_of(plain);
    EXPECT_EQ(a.map->mapping, EnvironmentMapping::equal_area);
    EXPECT_FLOAT_EQ(a.scale, 1.f);
    const Scene turned = load(dir, camera + "AttributeBegin\nRotate -90 1 0 0\nLightSource \"infinite\" \"string filename\" \"sky.pfm\" \"float scale\" 3\nAttributeEnd\n", "b.pbrt");
    const EnvironmentMapLight& b = map_of(turned);
    EXPECT_FLOAT_EQ(b.scale, 3.f);
    // Rotate −90 about x takes the map's +z (its up) to +y.
    const SampledWavelengths lambda = SampledWavelengths::sample(0.5f);
    const Vec3 d = normalize(Vec3{0.3f, 0.2f, 0.9f});
    const Vec3 d_world{d.x, d.z, -d.y};
    EXPECT_NEAR(b.arriving(d_world, lambda)[0], 3.f * a.arriving(d, lambda)[0], 1e-5f * a.arriving(d, lambda)[0]);
    const Scene lit = load(dir, camera + "LightSource \"infinite\" \"string filename\" \"sky.pfm\" \"float illuminance\" 2\n", "c.pbrt");
    // pbrt-v4 weighs each texel of the upper hemisphere by 2π/N where it covers 4π/N: the map
    // it renders has twice the illuminance the file asks for.
    EXPECT_NEAR(map_of(lit).scale * map_of(lit).map->up_illuminance, 4.0, 1e-4);
}

TEST(EnvironmentMapScene, ExportedToPbrtReadsBackAsTheSameMap) {
    // An equal-area map is written as pbrt-v4's image infinite light under its transform and
    // reads back equal; a lat-long map has no pbrt-v4 form: a comment naming the converter.
    const auto dir = folder("export");
    write_pfm(dir / "square.pfm", 8, 8, [](int x, int y) { return sky(x, y, 8, 8); });
    write_pfm(dir / "sky.pfm", 16, 8, [](int x, int y) { return sky(x, y, 16, 8); });
    write_file(dir / "scene.json", scene_text(R"({"type": "image", "file": "square.pfm", "mapping": "equal_area", "scale": 1.5,
        "transform": {"rotate": {"axis": [1, 0.5, 0], "degrees": -70}}})"));
    const std::string text = exported_pbrt(dir, "scene.json");
    EXPECT_NE(text.find("LightSource \"infinite\" \"string filename\" \"square.pfm\" \"float scale\" 1.5"), std::string::npos) << text;
    write_file(dir / "out.pbrt", text);
    const Scene original = load_scene_file((dir / "scene.json").string(), {});
    const Scene back = load_scene_file((dir / "out.pbrt").string(), {});
    const EnvironmentMapLight& a = map_of(original);
    const EnvironmentMapLight& b = map_of(back);
    EXPECT_FLOAT_EQ(a.scale, b.scale);
    const SampledWavelengths lambda = SampledWavelengths::sample(0.2f);
    for (const Vec3& d : {Vec3{0, 1, 0}, normalize(Vec3{0.3f, -0.2f, 0.9f}), normalize(Vec3{-0.7f, 0.1f, -0.2f})})
        EXPECT_NEAR(a.arriving(d, lambda)[2], b.arriving(d, lambda)[2], 1e-4f * a.arriving(d, lambda)[2]);
    write_file(dir / "scene.json", scene_text(R"({"type": "image", "file": "sky.pfm"})"));
    const std::string t2 = exported_pbrt(dir, "scene.json");
    EXPECT_EQ(t2.find("LightSource \"infinite\""), std::string::npos);
    EXPECT_NE(t2.find("imgtool makeequiarea"), std::string::npos);
}

// ---- Renders ----

RenderSettings mode(RenderSettings s, LightSampling m) {
    s.integrator.light_sampling = m;
    return s;
}

TEST(EnvironmentMapScene, LightBsdfAndMisSamplingAgree) {
    const auto dir = folder("mis");
    write_pfm(dir / "sky.pfm", 32, 16, [](int x, int y) { return sky(x, y, 32, 16); });
    for (const std::string& extra : {std::string(), std::string(R"(, "mis_compensation": true)")}) {
        const Scene scene = load(dir, scene_text(R"({"type": "image", "file": "sky.pfm")" + extra + "}"));
        const auto mis = render_film(scene, mode(small_settings(20, 20, 256, 1), LightSampling::mis));
        const auto bsdf = render_film(scene, mode(small_settings(20, 20, 2048, 2), LightSampling::bsdf));
        const Comparison c = compare(*mis, *bsdf, [](int, int) { return true; });
        EXPECT_LE(c.max_z, 5.0) << "bsdf" << extra << ": " << describe(c);
        EXPECT_NEAR(c.mean_a, c.mean_b, 4 * c.se) << "bsdf" << extra << ": " << describe(c);
        if (!extra.empty()) continue;  // the compensated density needs BSDF sampling beside it
        const auto light = render_film(scene, mode(small_settings(20, 20, 256, 3), LightSampling::light));
        const Comparison l = compare(*mis, *light, [](int, int) { return true; });
        EXPECT_LE(l.max_z, 5.0) << "light: " << describe(l);
        EXPECT_NEAR(l.mean_a, l.mean_b, 4 * l.se) << "light: " << describe(l);
    }
}

TEST(EnvironmentMapScene, ImportanceAndUniformSamplingAgree) {
    const auto dir = folder("uniform");
    write_pfm(dir / "sky.pfm", 32, 16, [](int x, int y) { return sky(x, y, 32, 16); });
    const Scene importance = load(dir, scene_text(R"({"type": "image", "file": "sky.pfm"})"));
    const Scene uniform = load(dir, scene_text(R"({"type": "image", "file": "sky.pfm", "sampling": "uniform"})"));
    const auto a = render_film(importance, small_settings(20, 20, 256, 1));
    const auto b = render_film(uniform, small_settings(20, 20, 1024, 2));
    const Comparison c = compare(*a, *b, [](int, int) { return true; });
    EXPECT_LE(c.max_z, 5.0) << describe(c);
    EXPECT_NEAR(c.mean_a, c.mean_b, 4 * c.se) << describe(c);
}

TEST(EnvironmentMapScene, BdptAndVcmAgreeWithThePathTracer) {
    // Light subpaths from the map (its disk), s = 0 on escaped camera paths, s = 1 towards
    // sampled directions: every strategy of an infinite light.
    const auto dir = folder("bdpt");
    write_pfm(dir / "sky.pfm", 16, 16, [](int x, int y) { return sky(x, y, 16, 16); });
    const Scene scene = load(dir, scene_text(R"({"type": "image", "file": "sky.pfm", "mapping": "equal_area",
        "transform": {"rotate": {"axis": [1, 0, 0], "degrees": -90}}})"));
    const auto path = test::expect_bdpt_matches_path(scene, 11);
    RenderSettings rs = small_settings(24, 24, 512, 13);
    rs.integrator.kind = IntegratorKind::vcm;
    const test::PassImages vcm = test::render_passes(scene, rs);
    EXPECT_EQ(vcm.film->rejected_samples(), 0u);
    const Comparison c = compare(*path, *vcm.film, [](int, int) { return true; });
    EXPECT_LE(c.max_z, 5.0) << "vcm: " << describe(c);
    EXPECT_NEAR(c.mean_a, c.mean_b, 5 * c.se) << "vcm: " << describe(c);
}

TEST(EnvironmentMapScene, VolumetricPathAgreesWithBdptThroughFog) {
    // A ball of homogeneous fog between the camera and the spheres (bounded: an unbounded
    // medium lets no light arrive from infinity): the volumetric path tracer's light samples
    // from inside a medium and its rays that leave it and escape, against bdpt's (which
    // reads homogeneous media).
    const auto dir = folder("fog");
    write_pfm(dir / "sky.pfm", 32, 16, [](int x, int y) { return sky(x, y, 32, 16); });
    const Scene scene = load(dir, scene_text(R"({"type": "image", "file": "sky.pfm"})",
                                             R"(, "media": {"fog": {"type": "homogeneous", "sigma_a": 0.1, "sigma_s": 1.5}})",
                                             R"({"type": "sphere", "center": [0, 0.35, 1.6], "radius": 0.5, "interior": "fog"}, )"));
    ASSERT_FALSE(scene.media.empty());
    test::expect_bdpt_matches_path(scene, 21);
}

// ---- Portals ----

/// A closed white room [−1, 1]³ with a window (y in [−0.1, 0.3], z in [−0.3, 0.3]) in its
/// wall x = 1, a ball on the floor, seen from inside; `portal` adds the window as the map's
/// portal (its front, edge1 × edge2 = +x, facing out).
std::string room_text(bool portal, const std::string& extra = "") {
    const std::string wall = R"({"type": "quad", "material": "white", )";
    return std::string(R"({"camera": {"position": [-0.9, 0.2, 0.6], "look_at": [0.5, -0.4, -0.2], "vfov_degrees": 70},
      "materials": {"white": {"type": "diffuse", "kd": 0.7}},
      "background": {"type": "image", "file": "sky.pfm")") +
           (portal ? R"(, "portal": {"origin": [1, -0.1, -0.3], "edge1": [0, 0.4, 0], "edge2": [0, 0, 0.6]})" : "") + extra + R"(},
      "shapes": [)" + wall + R"("origin": [-1, -1, -1], "edge1": [2, 0, 0], "edge2": [0, 0, 2]},
                 )" + wall + R"("origin": [-1, 1, -1], "edge1": [2, 0, 0], "edge2": [0, 0, 2]},
                 )" + wall + R"("origin": [-1, -1, -1], "edge1": [0, 2, 0], "edge2": [0, 0, 2]},
                 )" + wall + R"("origin": [-1, -1, -1], "edge1": [2, 0, 0], "edge2": [0, 2, 0]},
                 )" + wall + R"("origin": [-1, -1, 1], "edge1": [2, 0, 0], "edge2": [0, 2, 0]},
                 )" + wall + R"("origin": [1, -1, -1], "edge1": [0, 0.9, 0], "edge2": [0, 0, 2]},
                 )" + wall + R"("origin": [1, 0.3, -1], "edge1": [0, 0.7, 0], "edge2": [0, 0, 2]},
                 )" + wall + R"("origin": [1, -0.1, -1], "edge1": [0, 0.4, 0], "edge2": [0, 0, 0.7]},
                 )" + wall + R"("origin": [1, -0.1, 0.3], "edge1": [0, 0.4, 0], "edge2": [0, 0, 0.7]},
                 {"type": "sphere", "center": [0.2, -0.7, -0.3], "radius": 0.3, "material": "white"}]})";
}

/// A sky whose sun (low, towards +x) shines in through the window.
void write_room_sky(const std::filesystem::path& dir) {
    write_pfm(dir / "sky.pfm", 64, 32, [](int x, int y) {
        if (std::abs(x - 16) <= 1 && std::abs(y - 13) <= 1) return std::array<float, 3>{400.f, 360.f, 300.f};
        return sky(x, y, 64, 32);
    });
}

double mean_standard_error(const Film& f) {
    double sum = 0;
    for (int y = 0; y < f.height(); ++y)
        for (int x = 0; x < f.width(); ++x) sum += f.pixel_y_standard_error(x, y);
    return sum / (f.width() * f.height());
}

TEST(EnvironmentMapScene, PortalChangesTheNoiseNotTheImage) {
    // The same room with and without the portal: equal images (MIS, and light sampling alone
    // through the portal, which a room closed but for it allows), and less noise with it.
    const auto dir = folder("portal");
    write_room_sky(dir);
    const Scene plain = load(dir, room_text(false));
    const Scene portal = load(dir, room_text(true));
    ASSERT_TRUE(std::holds_alternative<PortalLight>(portal.lights.at(std::size_t(portal.infinite_light_indices.at(0)))));
    const auto reference = render_film(plain, small_settings(20, 20, 1024, 1));
    const auto mis = render_film(portal, small_settings(20, 20, 256, 2));
    const auto light = render_film(portal, mode(small_settings(20, 20, 256, 3), LightSampling::light));
    for (const auto* f : {mis.get(), light.get()}) {
        const Comparison c = compare(*reference, *f, [](int, int) { return true; });
        EXPECT_LE(c.max_z, 5.0) << (f == mis.get() ? "mis: " : "light: ") << describe(c);
        EXPECT_NEAR(c.mean_a, c.mean_b, 4 * c.se) << (f == mis.get() ? "mis: " : "light: ") << describe(c);
    }
    const auto plain_256 = render_film(plain, small_settings(20, 20, 256, 4));
    EXPECT_LT(mean_standard_error(*mis), 0.7 * mean_standard_error(*plain_256))
        << "with the portal " << mean_standard_error(*mis) << ", without " << mean_standard_error(*plain_256);
}

TEST(EnvironmentMapScene, BdptAndVcmThroughAPortalAgreeWithThePathTracer) {
    // Light subpaths start on the portal: every strategy of bdpt, and vcm's merging.
    const auto dir = folder("portal_bdpt");
    write_room_sky(dir);
    const Scene scene = load(dir, room_text(true));
    const auto path = test::expect_bdpt_matches_path(scene, 31);
    RenderSettings rs = small_settings(24, 24, 512, 33);
    rs.integrator.kind = IntegratorKind::vcm;
    const test::PassImages vcm = test::render_passes(scene, rs);
    const Comparison c = compare(*path, *vcm.film, [](int, int) { return true; });
    EXPECT_LE(c.max_z, 5.0) << "vcm: " << describe(c);
    EXPECT_NEAR(c.mean_a, c.mean_b, 5 * c.se) << "vcm: " << describe(c);
}

TEST(EnvironmentMapScene, MalformedPortalsAreOneLocatedLine) {
    const auto dir = folder("portal_malformed");
    write_room_sky(dir);
    auto room = [](const std::string& portal, const std::string& extra = "") {
        return R"({"camera": {"position": [0, 0, 2], "look_at": [0, 0, 0]}, "materials": {"white": {"kd": 0.7}},
  "background": {"type": "image", "file": "sky.pfm", "portal": )" + portal + extra + R"(},
  "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.3, "material": "white"}]})";
    };
    expect_located_errors(dir, {
        {room(R"({"origin": [1, 0, 0], "edge1": [0, 1, 0], "edge2": [0, 0.5, 1]})"),
         "scene.json:2:64: background image portal: the portal's edges are not perpendicular; expected a rectangle"},
        {room(R"({"origin": [1, 0, 0], "edge1": [0, 0, 0], "edge2": [0, 0, 1]})"),
         "scene.json:2:95: background image portal edge1 is the zero vector"},
        {room(R"({"origin": [1, 0, 0], "edge1": [0, 1, 0]})"), "scene.json:2:64: background image portal has no \"edge2\""},
        {room("[1, 0, 0]"), "scene.json:2:64: background image portal is an array"},
        {room(R"({"origin": [1, 0, 0], "edge1": [0, 1, 0], "edge2": [0, 0, 1]})", R"(, "sampling": "uniform")"),
         "scene.json:2:64: background image has a \"portal\" and \"sampling\": \"uniform\""},
    });
}

TEST(EnvironmentMapScene, PbrtPortalsReadAndWriteInPbrtsFrame) {
    // pbrt-v4's four corners p0 p1 p2 p3: x = p3 − p0, y = p1 − p0, the map on the side of
    // x × y; written back as the same corners.
    const auto dir = folder("pbrt_portal");
    write_pfm(dir / "sky.pfm", 8, 8, [](int x, int y) { return sky(x, y, 8, 8); });
    const std::string text = "LookAt 0 0 0  -1 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
                             "LightSource \"infinite\" \"string filename\" \"sky.pfm\" \"point3 portal\" "
                             "[ -1 -0.1 -0.3  -1 0.3 -0.3  -1 0.3 0.3  -1 -0.1 0.3 ]\n"
                             "Shape \"sphere\" \"float radius\" 0.2\n";
    write_file(dir / "a.pbrt", text);
    const Scene scene = load_scene_file((dir / "a.pbrt").string(), {});
    const PortalLight& p = std::get<PortalLight>(scene.lights.at(std::size_t(scene.infinite_light_indices.at(0))));
    EXPECT_NEAR(p.portal().origin.x, -1.f, 1e-6f);
    EXPECT_NEAR(p.portal().x.z, 1.f, 1e-6f);
    EXPECT_NEAR(p.portal().y.y, 1.f, 1e-6f);
    EXPECT_NEAR(p.portal().z.x, -1.f, 1e-6f);  // (0, 0, 1) × (0, 1, 0): the map lies at −x
    EXPECT_FLOAT_EQ(p.portal().width, 0.6f);
    EXPECT_FLOAT_EQ(p.portal().height, 0.4f);
    const std::string out = exported_pbrt(dir, "a.pbrt");
    EXPECT_NE(out.find("\"point3 portal\" [ -1 -0.1 -0.3 -1 0.3 -0.3 -1 0.3 0.3 -1 -0.1 0.3 ]"), std::string::npos) << out;
}

}  // namespace
}  // namespace spt

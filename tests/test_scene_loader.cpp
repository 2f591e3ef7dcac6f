// Scene files: every spectrum form and shape, the checks with their file:line:column
// messages, and the Cornell boxes as files rendering bit-identically to their C++ definitions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "cornell_reference.h"
#include "model/camera.h"
#include "scene/scene_loader.h"
#include "spectral/cie.h"
#include "spectral/rgb_texels.h"
#include "spectral/rgb_to_spectrum.h"
#include "test_scenes.h"

namespace spt {
namespace {

const RelativeFileReader kNoFiles = [](const std::string&, std::string&, std::string&, std::string& why) {
    why = "no files in this test";
    return false;
};

/// A scene with a camera, the given materials and shapes (JSON fragments).
std::string scene_json(const std::string& materials, const std::string& shapes, const std::string& extra = "") {
    return "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]},\n\"materials\": {" + materials +
           "},\n\"shapes\": [" + shapes + "]" + extra + "}";
}

Scene load(const std::string& text, const RelativeFileReader& reader = kNoFiles) {
    return load_scene_text(text, "s.json", "s", SpectralResolution{SpectralResolution::kExact}, reader);
}

std::string error_of(const std::string& text, const RelativeFileReader& reader = kNoFiles) {
    try {
        load(text, reader);
    } catch (const LocatedError& e) {
        return e.what();
    }
    return "(no error)";
}

double kd_at(const std::string& spectrum, double lambda) {
    const Scene s = load(scene_json("\"m\": {\"kd\": " + spectrum + "}", "{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, \"material\": \"m\"}"));
    return test::kd_of(s.materials[0]).source().eval(lambda);
}
double emission_at(const std::string& spectrum, double lambda) {
    const Scene s = load(scene_json("", "{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, \"emission\": " + spectrum + "}"));
    // The sphere's emitter (the shape's own "emission": a material that reflects nothing).
    EXPECT_TRUE(s.materials[0].flags.is_black());
    return std::get<SphereLight>(s.lights.at(static_cast<std::size_t>(s.spheres[0].light))).Le.source().eval(lambda);
}

TEST(SceneLoader, EverySpectrumForm) {
    EXPECT_DOUBLE_EQ(kd_at("0.25", 500), 0.25);
    EXPECT_DOUBLE_EQ(kd_at("{\"type\": \"constant\", \"value\": 0.5}", 700), 0.5);
    EXPECT_DOUBLE_EQ(kd_at("{\"type\": \"gaussian\", \"center_nm\": 540, \"width_nm\": 40, \"scale\": 0.55, \"offset\": 0.05}", 540), 0.6);
    EXPECT_DOUBLE_EQ(kd_at("{\"type\": \"sigmoid\", \"center_nm\": 600, \"width_nm\": 12, \"scale\": 0.65, \"offset\": 0.05}", 600), 0.375);
    EXPECT_DOUBLE_EQ(kd_at("{\"type\": \"table\", \"points\": [[400, 0.2], [600, 0.6]]}", 500), 0.4);
    EXPECT_NEAR(kd_at("{\"type\": \"colorchecker\", \"patch\": \"white_9_5_05_d\"}", 550), 0.9, 0.05);
    EXPECT_NEAR(emission_at("{\"type\": \"blackbody\", \"temperature_k\": 6500, \"scale\": 4}", 560), 4.0, 1e-12);
    EXPECT_NEAR(emission_at("{\"type\": \"illuminant\", \"name\": \"D65\"}", 560), 1.0, 1e-12);
    EXPECT_NEAR(emission_at("{\"type\": \"illuminant\", \"name\": \"A\", \"scale\": 2}", 560), 2.0, 1e-12);
    // RGB: the fitted spectrum, in both forms, and scaled for emission.
    const SpectrumSource fit = rgb_to_spectrum({0.8, 0.2, 0.1});
    EXPECT_DOUBLE_EQ(kd_at("[0.8, 0.2, 0.1]", 650), fit.eval(650));
    EXPECT_DOUBLE_EQ(kd_at("{\"type\": \"rgb\", \"value\": [0.8, 0.2, 0.1]}", 450), fit.eval(450));
    EXPECT_DOUBLE_EQ(emission_at("{\"type\": \"rgb\", \"value\": [0.8, 0.2, 0.1], \"scale\": 10}", 650), 10 * fit.eval(650));
}

TEST(SceneLoader, IndexOfRefractionForms) {
    auto eta = [](const std::string& ior, double lambda) {
        const Scene s = load(scene_json("\"g\": {\"kt\": 1, \"ior\": " + ior + "}",
                                        "{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, \"material\": \"g\"}"));
        return std::get<LobeMixBsdf>(s.materials[0].bsdf).eta.source().eval(lambda);
    };
    EXPECT_DOUBLE_EQ(eta("1.5", 500), 1.5);
    EXPECT_NEAR(eta("{\"type\": \"cauchy\", \"a\": 1.5046, \"b_um2\": 0.0042}", 587.6), 1.51676, 1e-5);
    EXPECT_NEAR(eta("{\"type\": \"sellmeier\", \"b\": [1.03961212, 0.231792344, 1.01046945], \"c_um2\": [0.00600069867, 0.0200179144, 103.560653]}", 587.6),
                1.51680, 1e-5);
}

TEST(SceneLoader, EveryShapeAndLight) {
    const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                            "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    const RelativeFileReader reader = [&](const std::string& rel, std::string& contents, std::string& display, std::string&) {
        display = rel;
        contents = ply;
        return rel == "tri.ply";
    };
    const Scene s = load(scene_json(
        "\"m\": {\"kd\": 0.5}",
        "{\"type\": \"sphere\", \"center\": [0, 1, 0], \"radius\": 0.5, \"material\": \"m\"},"
        "{\"type\": \"plane\", \"normal\": [0, 2, 0], \"point\": [0, -1, 0], \"material\": \"m\"},"
        "{\"type\": \"quad\", \"origin\": [0, 0, 0], \"edge1\": [1, 0, 0], \"edge2\": [0, 1, 0], \"emission\": 3,"
        " \"transform\": {\"scale\": 2, \"rotate\": {\"axis\": [0, 0, 1], \"degrees\": 90}, \"translate\": [0, 0, 1]}},"
        "{\"type\": \"triangle\", \"vertices\": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], \"material\": \"m\"},"
        "{\"type\": \"mesh\", \"file\": \"tri.ply\", \"material\": \"m\", \"transform\": {\"translate\": [5, 0, 0]}}",
        ", \"lights\": [{\"type\": \"point\", \"position\": [0, 2, 0], \"intensity\": 10}], \"background\": 0.1,"
        " \"image\": {\"width\": 64, \"height\": 32, \"spp\": 8}"), reader);
    ASSERT_EQ(s.spheres.size(), 1u);
    ASSERT_EQ(s.planes.size(), 1u);
    EXPECT_EQ(s.planes[0].normal, Vec3(0, 1, 0));
    EXPECT_EQ(s.planes[0].offset, -1.f);
    ASSERT_EQ(s.triangles.size(), 4u);  // quad (2) + triangle + mesh
    // Quad corner (1, 0, 0): scaled to (2, 0, 0), rotated to (0, 2, 0), translated to (0, 2, 1).
    EXPECT_NEAR(s.triangles[0].p1.x, 0, 1e-6);
    EXPECT_NEAR(s.triangles[0].p1.y, 2, 1e-6);
    EXPECT_NEAR(s.triangles[0].p1.z, 1, 1e-6);
    EXPECT_EQ(s.triangles[3].p1, Vec3(6, 0, 0));
    // The quad emits: its two triangles share one emitter; the other shapes emit nothing.
    EXPECT_GE(s.triangles[0].light, 0);
    EXPECT_EQ(s.triangles[1].light, s.triangles[0].light);
    EXPECT_EQ(s.triangles[2].light, -1);
    EXPECT_EQ(s.spheres[0].light, -1);
    ASSERT_EQ(s.point_light_indices.size(), 1u);
    EXPECT_EQ(s.width, 64);
    EXPECT_EQ(s.height, 32);
    EXPECT_EQ(s.spp, 8);
    EXPECT_TRUE(s.effects.background);
    EXPECT_TRUE(s.effects.point_lights);
    EXPECT_TRUE(s.effects.emissive_surfaces);
}

TEST(SceneLoader, ErrorsNameFileLineColumnAndSuggest) {
    const std::string sphere = "{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, \"material\": \"m\"}";
    EXPECT_EQ(error_of(scene_json("\"m\": {\"kd\": 0.5}", "{\"type\": \"sphere\", \"center\": [0,0,0], \"radus\": 1, \"material\": \"m\"}")),
              "s.json:3:50: unknown key \"radus\" in sphere (shape 0). Did you mean \"radius\"? Expected \"radius\", which sphere (shape 0) needs");
    // An unknown key beside every key the shape needs: found after the shape is built, with the
    // keys its create function read or looked for.
    EXPECT_EQ(error_of(scene_json("\"m\": {\"kd\": 0.5}", "{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, \"radiuss\": 1, \"material\": \"m\"}")),
              "s.json:3:63: unknown key \"radiuss\" in sphere (shape 0). Did you mean \"radius\"? Expected one of: type, motion, center, radius, material, emission, two_sided, interior, exterior");
    EXPECT_NE(error_of(scene_json("\"m\": {\"kd\": 0.5}", "{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": -1, \"material\": \"m\"}"))
                  .find("s.json:3:60: sphere (shape 0) radius is -1; expected a number in (0, 1e+15]"), std::string::npos);
    EXPECT_NE(error_of(scene_json("\"m\": {\"kd\": 0.7, \"ks\": 0.4}", sphere)).find("kd + ks + kt = 1.1"), std::string::npos);
    EXPECT_NE(error_of(scene_json("\"m\": {\"kd\": 0.5}", "{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, \"material\": \"n\"}"))
                  .find("unknown material \"n\". Did you mean \"m\"?"), std::string::npos);
    EXPECT_NE(error_of(scene_json("\"m\": {\"kt\": 1, \"ior\": 0.9}", sphere)).find("expected an index of refraction in [1, 100]"), std::string::npos);
    EXPECT_NE(error_of(scene_json("\"m\": {\"kd\": [1.5, 0, 0]}", sphere)).find("out of range"), std::string::npos);
    EXPECT_NE(error_of(scene_json("\"m\": {\"kd\": {\"type\": \"gausian\"}}", sphere)).find("Did you mean \"gaussian\"?"), std::string::npos);
    EXPECT_NE(error_of(scene_json("\"m\": {\"kd\": 0.5}", "{\"type\": \"plane\", \"normal\": [0,0,0], \"point\": [0,0,0], \"material\": \"m\"}"))
                  .find("zero vector"), std::string::npos);
    EXPECT_NE(error_of(scene_json("\"m\": {\"kd\": 0.5}", "{\"type\": \"mesh\", \"file\": \"nope.ply\", \"material\": \"m\"}"))
                  .find("cannot read mesh \"nope.ply\""), std::string::npos);
}

TEST(SceneLoader, BuiltinNamesComeFromTheEmbeddedFiles) {
    const auto names = builtin_scene_names();
    ASSERT_GE(names.size(), 2u);
    EXPECT_EQ(names[0], kDefaultScene);
    EXPECT_NE(std::find(names.begin(), names.end(), "cornell-point"), names.end());
    for (const std::string& n : names) EXPECT_TRUE(load_builtin_scene(n, {}).has_value()) << n;
    EXPECT_FALSE(load_builtin_scene("no-such-scene", {}).has_value());
    EXPECT_EQ(load_builtin_scene("cornell", {})->spp, 128);
}

/// The complete example of scenes/README.md loads (with its mesh from scenes/).
TEST(SceneLoader, ReadmeExampleLoads) {
    const std::filesystem::path dir = std::filesystem::path(SPT_TEST_DIR) / ".." / "scenes";
    std::ifstream in(dir / "README.md");
    const std::string readme((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t start = readme.find("```json\n");
    ASSERT_NE(start, std::string::npos);
    const std::size_t end = readme.find("```", start + 8);
    const RelativeFileReader reader = [&](const std::string& rel, std::string& contents, std::string& display, std::string&) {
        display = rel;
        std::ifstream f(dir / rel);
        contents.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
        return static_cast<bool>(f);
    };
    const Scene s = load(readme.substr(start + 8, end - start - 8), reader);
    EXPECT_EQ(s.spheres.size(), 1u);
    EXPECT_EQ(s.triangles.size(), 8u + 2u);
}

/// "s.json:LINE:COLUMN" of the first occurrence of `needle` in `text` (the position an error
/// about that value must name).
std::string position_of(const std::string& text, const std::string& needle) {
    // Past the first line (the camera of scene_json) when the needle is there.
    std::size_t at = text.find(needle, text.find('\n'));
    if (at == std::string::npos) at = text.find(needle);
    EXPECT_NE(at, std::string::npos) << needle;
    const std::size_t line_start = text.rfind('\n', at);
    const std::size_t line = 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
    const std::size_t column = at - (line_start == std::string::npos ? 0 : line_start + 1) + 1;
    return "s.json:" + std::to_string(line) + ":" + std::to_string(column) + ": ";
}

/// The error of `text` starts at the position of `needle` and contains `message`.
void expect_error_at(const std::string& text, const std::string& needle, const std::string& message,
                     const RelativeFileReader& reader = kNoFiles) {
    const std::string e = error_of(text, reader);
    EXPECT_EQ(e.rfind(position_of(text, needle), 0), 0u) << e;
    EXPECT_NE(e.find(message), std::string::npos) << e;
}

TEST(SceneLoader, ProductSpectrumIsTheProductOfItsFactors) {
    const std::string gaussian = R"({"type": "gaussian", "center_nm": 550, "width_nm": 40, "scale": 0.5, "offset": 0.1})";
    const std::string product = R"({"type": "product", "factors": [0.8, )" + gaussian + R"(], "scale": 0.5})";
    for (double l : {380.0, 470.0, 550.0, 563.5, 640.0, 800.0}) {
        const double g = 0.1 + 0.5 * std::exp(-std::pow((l - 550) / 40, 2));
        EXPECT_NEAR(kd_at(product, l), 0.5 * 0.8 * g, 1e-15) << l;
        // Any form is a factor, products too; the scale defaults to 1.
        EXPECT_NEAR(kd_at(R"({"type": "product", "factors": [)" + product + R"(, [0.8, 0.2, 0.1]]})", l),
                    0.5 * 0.8 * g * rgb_to_spectrum({0.8, 0.2, 0.1}).eval(l), 1e-15) << l;
    }
    auto kd_constant = [](const std::string& spectrum) {
        const Scene s = load(scene_json("\"m\": {\"kd\": " + spectrum + "}", "{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, \"material\": \"m\"}"));
        return test::kd_of(s.materials[0]).source().is_constant();
    };
    EXPECT_TRUE(kd_constant(R"({"type": "product", "factors": [0.5, {"type": "constant", "value": 0.5}]})"));
    EXPECT_FALSE(kd_constant(product));
    // The RGB illuminant of pbrt-v4: an RGB colour times D65.
    const std::string rgb_d65 = R"({"type": "product", "factors": [{"type": "rgb", "value": [1, 0.5, 0.2]}, {"type": "illuminant", "name": "D65"}]})";
    EXPECT_NEAR(emission_at(rgb_d65, 600), rgb_to_spectrum({1, 0.5, 0.2}).eval(600) * emission_at(R"({"type": "illuminant", "name": "D65"})", 600), 1e-12);
}

TEST(SceneLoader, NormalizedSpectrumHasTheGivenLuminance) {
    // The film's luminance, computed here from the observer the film uses (Y over ∫ȳ).
    auto film_luminance = [](const std::string& spectrum) {
        const Scene s = load(scene_json("", "{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, \"emission\": " + spectrum + "}"));
        const SpectrumSource& e = std::get<SphereLight>(s.lights.at(0)).Le.source();
        const Observer& cie = Cie1931::get();
        double y = 0;
        for (int l = 360; l < 830; ++l)
            y += 0.5 * (cie.cmf(static_cast<float>(l)).y * e.eval(l) + cie.cmf(static_cast<float>(l + 1)).y * e.eval(l + 1));
        return y / cie.y_integral();
    };
    const std::string d65 = R"({"type": "normalized", "spectrum": {"type": "illuminant", "name": "D65"}, "luminance": 1})";
    EXPECT_NEAR(film_luminance(d65), 1.0, 1e-4);
    // The same unit D65 that an RGB texel's white emits.
    for (double l : {400.0, 555.0, 700.0}) EXPECT_NEAR(emission_at(d65, l), d65_unit_luminance(l), 1e-12 * d65_unit_luminance(l));
    EXPECT_NEAR(film_luminance(R"({"type": "normalized", "spectrum": {"type": "blackbody", "temperature_k": 3000}, "luminance": 7.5})"),
                7.5, 7.5e-4);
    EXPECT_DOUBLE_EQ(emission_at(R"({"type": "normalized", "spectrum": 0.3, "luminance": 2})", 500), 2.0);
    EXPECT_EQ(kd_at(R"({"type": "normalized", "spectrum": 0.3, "luminance": 0})", 500), 0.0);
}

// Lamps with lines (spectra/cie_f*.csv, cie_led_b3.csv) are named illuminants of luminance 1
// × scale (560 nm may fall between their lines), their 5 nm tables kept point for point: F11's
// green line is 72.84 at 545 nm against 39.59 and 32.61 at 540 and 550 in its table.
TEST(SceneLoader, NamedLampsWithLinesHaveLuminanceOneAndKeepTheirLines) {
    for (const char* name : {"F2", "F7", "F11", "LED-B3"}) {
        const std::string s = std::string(R"({"type": "illuminant", "name": ")") + name + R"(", "scale": 3})";
        const Scene scene = load(scene_json("", "{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, \"emission\": " + s + "}"));
        EXPECT_NEAR(cie_luminance(std::get<SphereLight>(scene.lights.at(0)).Le.source()), 3.0, 3e-12) << name;
    }
    const std::string f11 = R"({"type": "illuminant", "name": "F11"})";
    const double at545 = emission_at(f11, 545);
    EXPECT_NEAR(emission_at(f11, 540) / at545, 39.59 / 72.84, 1e-12);
    EXPECT_NEAR(emission_at(f11, 550) / at545, 32.61 / 72.84, 1e-12);
    EXPECT_NEAR(emission_at(f11, 542.5) / at545, (39.59 + 72.84) / 2 / 72.84, 1e-12);  // linear between points
    // D65 and A stay 1 at 560 nm (EverySpectrumForm), so the two rules coexist.
    expect_error_at(scene_json("", "{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, \"emission\": "
                                   R"({"type": "illuminant", "name": "F12"})"
                                   "}"),
                    "\"F12\"", "Expected one of: D65, A, F2, F7, F11, LED-B3");
}

TEST(SceneLoader, ProductAndNormalizedErrorsAreLocated) {
    auto emitter = [](const std::string& spectrum) {
        return scene_json("", "{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, \"emission\": " + spectrum + "}");
    };
    expect_error_at(emitter(R"({"type": "product", "factors": []})"), "[]", "factors is not a non-empty array");
    expect_error_at(emitter(R"({"type": "product", "factors": [1, {"type": "gausian"}]})"), "\"gausian\"", "Did you mean \"gaussian\"?");
    expect_error_at(emitter(R"({"type": "normalized", "spectrum": {"type": "constant", "value": 0}, "luminance": 1})"),
                    "{\"type\": \"constant\"", "spectrum has luminance 0; expected a spectrum of positive luminance");
    expect_error_at(emitter(R"({"type": "normalized", "spectrum": 1, "luminance": -2})"), "-2",
                    "luminance is -2; expected a finite number >= 0");
    expect_error_at(emitter(R"({"type": "normalized", "luminance": 1})"), "{\"type\": \"normalized\"", "has no \"spectrum\"");
    // The product is checked for its use as a whole: a reflectance above 1.
    expect_error_at(scene_json("\"m\": {\"kd\": {\"type\": \"product\", \"factors\": [0.9, 2]}}", ""), "{\"type\": \"product\"",
                    "expected a reflectance in [0, 1]");
}

/// The triangles' vertices of `a` and `b` agree within `tolerance`.
void expect_same_triangles(const Scene& a, const Scene& b, float tolerance) {
    ASSERT_EQ(a.triangles.size(), b.triangles.size());
    for (std::size_t i = 0; i < a.triangles.size(); ++i)
        for (const auto& [p, q] : {std::pair{a.triangles[i].p0, b.triangles[i].p0}, std::pair{a.triangles[i].p1, b.triangles[i].p1},
                                  std::pair{a.triangles[i].p2, b.triangles[i].p2}}) {
            EXPECT_NEAR(p.x, q.x, tolerance) << i;
            EXPECT_NEAR(p.y, q.y, tolerance) << i;
            EXPECT_NEAR(p.z, q.z, tolerance) << i;
        }
}

Scene quad_under(const std::string& transform) {
    return load(scene_json("\"m\": {\"kd\": 0.5}", "{\"type\": \"quad\", \"origin\": [0.5, -1, 2], \"edge1\": [1, 0.25, 0], "
                                                   "\"edge2\": [0, 1, -0.5], \"material\": \"m\", \"transform\": " + transform + "}"));
}

TEST(SceneLoader, MatrixTransformEqualsScaleRotateTranslate) {
    // Rz(90°)·diag(2, 0.5, 1.5), then the translation (0.3, −0.2, 0.1), row-major.
    expect_same_triangles(
        quad_under(R"({"scale": [2, 0.5, 1.5], "rotate": {"axis": [0, 0, 1], "degrees": 90}, "translate": [0.3, -0.2, 0.1]})"),
        quad_under(R"({"matrix": [0, -0.5, 0, 0.3,  2, 0, 0, -0.2,  0, 0, 1.5, 0.1,  0, 0, 0, 1]})"), 1e-6f);
    // A rotation about another axis: Rx(90°) maps y to z.
    expect_same_triangles(quad_under(R"({"rotate": {"axis": [1, 0, 0], "degrees": 90}})"),
                          quad_under(R"({"matrix": [1, 0, 0, 0,  0, 0, -1, 0,  0, 1, 0, 0,  0, 0, 0, 1]})"), 1e-6f);
    // Not the transpose (the translation is in the last column).
    const Scene moved = quad_under(R"({"matrix": [1, 0, 0, 5,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0, 0, 1]})");
    EXPECT_EQ(moved.triangles[0].p0, Vec3(5.5f, -1, 2));
}

/// A closed tetrahedron, faces counter-clockwise seen from outside, with vertex normals.
const std::string kTetrahedron =
    R"("positions": [0, 0, 0,  1, 0, 0,  0, 1, 0,  0, 0, 1], "indices": [0, 2, 1,  0, 1, 3,  0, 3, 2,  1, 2, 3],
       "normals": [-1, -1, -1,  1, 0, 0,  0, 1, 0,  0, 0, 1])";

TEST(SceneLoader, MirroringMatrixMirrorsAsAMirroringScale) {
    auto glass_tetrahedron = [](const std::string& transform) {
        return load(scene_json("\"g\": {\"kt\": 1, \"ior\": 1.5}",
                               "{\"type\": \"mesh\", " + kTetrahedron + ", \"material\": \"g\", \"transform\": " + transform + "}"));
    };
    const Scene scaled = glass_tetrahedron(R"({"scale": [-1.25, 1.25, 1.25], "translate": [1, 2, 3]})");
    const Scene matrix = glass_tetrahedron(R"({"matrix": [-1.25, 0, 0, 1,  0, 1.25, 0, 2,  0, 0, 1.25, 3,  0, 0, 0, 1]})");
    expect_same_triangles(scaled, matrix, 0);
    ASSERT_EQ(scaled.triangle_attributes.size(), matrix.triangle_attributes.size());
    for (std::size_t i = 0; i < scaled.triangle_attributes.size(); ++i)
        for (int k = 0; k < 3; ++k) EXPECT_EQ(scaled.triangle_attributes[i].n[k], matrix.triangle_attributes[i].n[k]);
    // Mirrored, the closed mesh's faces point inward: both warn, the unmirrored one does not.
    for (const Scene* s : {&scaled, &matrix}) {
        ASSERT_EQ(s->warnings.size(), 1u);
        EXPECT_NE(s->warnings[0].find("faces pointing inward"), std::string::npos) << s->warnings[0];
    }
    EXPECT_TRUE(glass_tetrahedron(R"({"matrix": [1.25, 0, 0, 1,  0, 1.25, 0, 2,  0, 0, 1.25, 3,  0, 0, 0, 1]})").warnings.empty());
}

TEST(SceneLoader, MatrixErrorsAreLocated) {
    auto quad = [](const std::string& transform) {
        return scene_json("\"m\": {\"kd\": 0.5}", "{\"type\": \"quad\", \"origin\": [0, 0, 0], \"edge1\": [1, 0, 0], "
                                                  "\"edge2\": [0, 1, 0], \"material\": \"m\", \"transform\": " + transform + "}");
    };
    expect_error_at(quad(R"({"matrix": [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0.5, 0, 1]})"), "[1, 0, 0, 0,", "not an affine map; expected [0, 0, 0, 1]");
    expect_error_at(quad(R"({"matrix": [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0, 0, 2]})"), "[1, 0, 0, 0,", "not an affine map");
    expect_error_at(quad(R"({"matrix": [1, 2, 3, 0,  2, 4, 6, 0,  0, 0, 1, 0,  0, 0, 0, 1]})"), "[1, 2", "singular");
    expect_error_at(quad(R"({"matrix": [1e9, 0, 0, 0,  0, 1e-9, 0, 0,  0, 0, 1e-9, 0,  0, 0, 0, 1]})"), "[1e9", "singular");
    expect_error_at(quad(R"({"matrix": [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0]})"), "[1, 0, 0, 0,", "expected an array of 16 numbers");
    expect_error_at(quad(R"({"matrix": [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0, 0, 1], "scale": 2})"), "2}",
                    "transform has both \"matrix\" and \"scale\"");
    expect_error_at(quad(R"({"translate": [1, 2, 3], "matrix": [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0, 0, 1]})"), "[1, 2, 3]",
                    "transform has both \"matrix\" and \"translate\"");
    // A small but well-conditioned matrix is not singular.
    EXPECT_EQ(error_of(quad(R"({"matrix": [1e-7, 0, 0, 0,  0, 1e-7, 0, 0,  0, 0, 1e-7, 0,  0, 0, 0, 1]})")), "(no error)");
}

const std::string kQuadPly =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "property float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\n"
    "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0 0 0 1 0 0\n1 0 0 0 0.6 0.8 1 0\n1 1 0.5 0 0 1 1 1\n0 1 0 0.6 0 0.8 0 1\n3 0 1 2\n3 0 2 3\n";
const std::string kQuadInline =
    R"("positions": [0, 0, 0,  1, 0, 0,  1, 1, 0.5,  0, 1, 0], "indices": [0, 1, 2,  0, 2, 3],
       "normals": [0, 0, 1,  0, 0.6, 0.8,  0, 0, 1,  0.6, 0, 0.8], "uv": [0, 0,  1, 0,  1, 1,  0, 1])";

TEST(SceneLoader, InlineMeshBuildsAsTheSamePlyMesh) {
    const RelativeFileReader reader = [&](const std::string& rel, std::string& contents, std::string& display, std::string&) {
        display = rel;
        contents = kQuadPly;
        return rel == "quad.ply";
    };
    for (const std::string& placement : {std::string(R"("transform": {"matrix": [0, -2, 0, 1,  2, 0, 0, 0,  0, 0, -2, 3,  0, 0, 0, 1]})"),
                                        std::string(R"("instances": [{}, {"translate": [3, 0, 0]}])")}) {
        const std::string rest = ", \"material\": \"m\", " + placement + "}";
        const Scene a = load(scene_json("\"m\": {\"kd\": 0.5}", "{\"type\": \"mesh\", \"file\": \"quad.ply\"" + rest), reader);
        const Scene b = load(scene_json("\"m\": {\"kd\": 0.5}", "{\"type\": \"mesh\", " + kQuadInline + rest));
        expect_same_triangles(a, b, 0);
        ASSERT_EQ(a.instanced_meshes.size(), b.instanced_meshes.size());
        for (std::size_t m = 0; m < a.instanced_meshes.size(); ++m) {
            ASSERT_EQ(a.instanced_meshes[m].triangles.size(), b.instanced_meshes[m].triangles.size());
            for (std::size_t i = 0; i < a.instanced_meshes[m].triangles.size(); ++i) {
                EXPECT_EQ(a.instanced_meshes[m].triangles[i].p0, b.instanced_meshes[m].triangles[i].p0);
                EXPECT_EQ(a.instanced_meshes[m].triangles[i].p2, b.instanced_meshes[m].triangles[i].p2);
            }
        }
        EXPECT_EQ(a.instances.size(), b.instances.size());
        ASSERT_EQ(a.triangle_attributes.size(), b.triangle_attributes.size());
        ASSERT_FALSE(a.triangle_attributes.empty());
        for (std::size_t i = 0; i < a.triangle_attributes.size(); ++i) {
            const TriangleAttributes &x = a.triangle_attributes[i], &y = b.triangle_attributes[i];
            EXPECT_TRUE(y.has_normals && y.has_uv);
            for (int k = 0; k < 3; ++k) {
                EXPECT_EQ(x.n[k], y.n[k]);
                EXPECT_EQ(x.uv[k][0], y.uv[k][0]);
                EXPECT_EQ(x.uv[k][1], y.uv[k][1]);
            }
        }
    }
    // An emitting one-sided inline mesh: the mesh's emitter, as for a file.
    const Scene e = load(scene_json("", "{\"type\": \"mesh\", " + kQuadInline + ", \"emission\": 2, \"two_sided\": false}"));
    ASSERT_EQ(e.triangles.size(), 2u);
    EXPECT_GE(e.triangles[0].light, 0);
}

TEST(SceneLoader, InlineMeshErrorsAreLocated) {
    auto mesh = [](const std::string& keys) { return scene_json("\"m\": {\"kd\": 0.5}", "{\"type\": \"mesh\", " + keys + ", \"material\": \"m\"}"); };
    expect_error_at(mesh(R"("positions": [0, 0, 0,  1, 0, 0,  0, 1], "indices": [0, 1, 2])"), "[0, 0, 0", "positions has 8 numbers; expected a multiple of 3");
    expect_error_at(mesh(R"("positions": [0, 0, 0,  1, 0, 0,  0, 1, 0], "indices": [0, 1, 2, 0])"), "[0, 1, 2, 0]", "indices has 4 numbers; expected a multiple of 3");
    expect_error_at(mesh(R"("positions": [0, 0, 0,  1, 0, 0,  0, 1, 0], "indices": [0, 1, 2,  2, 1, 3])"), "3]",
                    "indices: triangle 1 has the index 3; expected an integer from 0 to below the vertex count, 3");
    expect_error_at(mesh(R"("positions": [0, 0, 0,  1, 0, 0,  0, 1, 0], "indices": [0, 1.5, 2])"), "1.5", "triangle 0 has the index 1.5");
    expect_error_at(mesh(R"("positions": [0, 0, 0,  1, 0, 0,  0, 1, 0], "indices": [0, -1, 2])"), "-1", "triangle 0 has the index -1");
    expect_error_at(mesh(R"("positions": [0, 0, 0,  1, 0, 0,  0, 1, 0], "indices": [0, 1, 2], "uv": [0, 0, 1, 0, 1])"), "[0, 0, 1, 0, 1]",
                    "uv has 5 numbers; expected a multiple of 2");
    expect_error_at(mesh(R"("positions": [0, 0, 0,  1, 0, 0,  0, 1, 0], "indices": [0, 1, 2], "normals": [0, 0, 1])"), "[0, 0, 1]",
                    "normals has 3 numbers; expected 3 per vertex (9)");
    expect_error_at(mesh(R"("positions": [0, 0, 0,  1, 0, "x",  0, 1, 0], "indices": [0, 1, 2])"), "\"x\"", "an element of mesh (shape 0) positions is a string");
    expect_error_at(mesh(R"("positions": [0, 0, 0,  1, 0, 0,  0, 1, 0])"), "{\"type\": \"mesh\"", "has no \"indices\"");
    expect_error_at(mesh(R"("file": "a.ply", "positions": [0, 0, 0], "indices": [0, 0, 0])"), "[0, 0, 0]", "has both \"file\" and \"positions\"");
    expect_error_at(mesh(R"("positons": [0, 0, 0], "indices": [0, 0, 0])"), "\"positons\"", "Did you mean \"positions\"?");
    expect_error_at(mesh(R"("positions": [0, 0, 0,  1, 0, 0,  2, 0, 0], "indices": [0, 1, 2])"), "[0, 0, 0",
                    "\"inline mesh\" has no triangle of non-zero area");
}

/// The camera of a scene with the given camera keys, at the given image size.
Camera camera_of(const std::string& camera_keys, int width, int height) {
    const Scene s = load("{\"camera\": {\"position\": [1, 2, 3], \"look_at\": [0, 0.5, 0], \"up\": [0, 1, 0.2]" + camera_keys +
                         "}, \"shapes\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, \"emission\": 1}]}");
    return Camera(s.camera, width, height);
}

double angle_degrees(const Vec3& a, const Vec3& b) {
    return std::acos(std::clamp(double(dot(normalize(a), normalize(b))), -1.0, 1.0)) * 180 / 3.14159265358979323846;
}

TEST(SceneLoader, FieldOfViewAlongTheNamedAxisOfTheRenderedImage) {
    auto same = [](const Camera& a, const Camera& b, int w, int h) {
        for (float x : {0.f, 0.3f * w, float(w)})
            for (float y : {0.f, 0.7f * h, float(h)}) EXPECT_EQ(a.generate_ray(x, y).d, b.generate_ray(x, y).d) << x << " " << y;
    };
    // The smaller axis of 200×100 is the vertical: the same camera as vfov_degrees.
    same(camera_of(R"(, "fov_degrees": 60, "fov_axis": "smaller")", 200, 100), camera_of(R"(, "vfov_degrees": 60)", 200, 100), 200, 100);
    same(camera_of(R"(, "fov_degrees": 60)", 200, 100), camera_of(R"(, "vfov_degrees": 60)", 200, 100), 200, 100);
    same(camera_of(R"(, "fov_degrees": 60, "fov_axis": "larger")", 100, 200), camera_of(R"(, "vfov_degrees": 60)", 100, 200), 100, 200);
    // Of 100×200 it is the horizontal: 60° across, 2·atan(tan 30°·200/100) from top to bottom.
    for (const char* axis : {"smaller", "horizontal"}) {
        const Camera c = camera_of(std::string(R"(, "fov_degrees": 60, "fov_axis": ")") + axis + "\"", 100, 200);
        EXPECT_NEAR(angle_degrees(c.generate_ray(0, 100).d, c.generate_ray(100, 100).d), 60, 1e-4) << axis;
        EXPECT_NEAR(angle_degrees(c.generate_ray(50, 0).d, c.generate_ray(50, 200).d),
                    2 * std::atan(std::tan(30 * 3.14159265358979323846 / 180) * 2) * 180 / 3.14159265358979323846, 1e-4) << axis;
    }
    const Camera larger = camera_of(R"(, "fov_degrees": 60, "fov_axis": "larger")", 200, 100);
    EXPECT_NEAR(angle_degrees(larger.generate_ray(0, 50).d, larger.generate_ray(200, 50).d), 60, 1e-4);
}

TEST(SceneLoader, LeftHandedCameraIsTheMirrorImage) {
    const int w = 64, h = 32;
    const Camera right = camera_of("", w, h), left = camera_of(R"(, "handedness": "left")", w, h);
    // Film position x of one sees what W − x of the other sees.
    for (float x : {0.5f, 5.5f, 31.f, 50.25f, 63.5f})
        for (float y : {0.5f, 12.5f, 31.5f}) {
            const Vec3 d = left.generate_ray(x, y).d, e = right.generate_ray(w - x, y).d;
            EXPECT_NEAR(d.x, e.x, 1e-6f);
            EXPECT_NEAR(d.y, e.y, 1e-6f);
            EXPECT_NEAR(d.z, e.z, 1e-6f);
            // Light paths land where the camera's rays leave (bdpt, vcm): the inverse mirrors too.
            float px = -1, py = -1;
            ASSERT_TRUE(left.raster_position(d, px, py)) << x << " " << y;
            EXPECT_NEAR(px, x, 1e-3f);
            EXPECT_NEAR(py, y, 1e-3f);
            ASSERT_TRUE(right.raster_position(d, px, py)) << x << " " << y;
            EXPECT_NEAR(px, w - x, 1e-3f);
        }
    // The image's right is forward × up for "right", up × forward for "left".
    const Vec3 forward = normalize(Vec3(0, 0.5f, 0) - Vec3(1, 2, 3));
    const Vec3 side = normalize(cross(forward, Vec3(0, 1, 0.2f)));
    EXPECT_GT(dot(right.generate_ray(63.5f, 16).d, side), 0.1f);
    EXPECT_LT(dot(right.generate_ray(0.5f, 16).d, side), -0.1f);
    EXPECT_LT(dot(left.generate_ray(63.5f, 16).d, side), -0.1f);
    EXPECT_GT(dot(left.generate_ray(0.5f, 16).d, side), 0.1f);
}

/// Largest |a(x, y) − b(W−1−x, y)|/σ over the pixels (or b(x, y) unmirrored).
double max_mirror_z(const Film& a, const Film& b, bool mirrored) {
    double worst = 0;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            const int bx = mirrored ? a.width() - 1 - x : x;
            const double d = std::fabs(a.pixel_xyz(x, y).y - b.pixel_xyz(bx, y).y);
            const double s = std::hypot(a.pixel_y_standard_error(x, y), b.pixel_y_standard_error(bx, y));
            worst = std::max(worst, d <= 1e-9 ? 0.0 : d / s);
        }
    return worst;
}

TEST(SceneLoader, LeftHandedCameraRendersTheMirrorImageWithEveryIntegrator) {
    auto scene = [](const std::string& handedness) {
        return load(R"({"camera": {"position": [0, 0.5, 3], "look_at": [0, -0.5, 0], "vfov_degrees": 50, "handedness": ")" + handedness + R"("},
            "materials": {"m": {"kd": 0.7}},
            "shapes": [{"type": "quad", "origin": [-2, -1, 2], "edge1": [4, 0, 0], "edge2": [0, 0, -4], "material": "m"},
                       {"type": "sphere", "center": [-0.6, -0.5, 0], "radius": 0.5, "material": "m"}],
            "lights": [{"type": "point", "position": [0.8, 1, 1], "intensity": 10}]})");
    };
    const Scene right = scene("right"), left = scene("left");
    for (IntegratorKind kind : {IntegratorKind::path, IntegratorKind::bdpt}) {
        RenderSettings rs = test::small_settings(20, 16, 64, 3, 2);
        rs.integrator.kind = kind;
        const auto a = test::render_film(right, rs);
        rs.seed = 4;
        const auto b = test::render_film(left, rs);
        EXPECT_LE(max_mirror_z(*a, *b, true), 5.0) << static_cast<int>(kind);
        // Each quarter of the image against the mirrored quarter: a bias too small to see in one
        // pixel (light paths splatted to the unmirrored pixel) adds up over a quarter.
        for (int q = 0; q < 4; ++q) {
            const test::ImageMean ma = test::region_mean_y(*a, [&](int x, int) { return x * 4 / 20 == q; });
            const test::ImageMean mb = test::region_mean_y(*b, [&](int x, int) { return (19 - x) * 4 / 20 == q; });
            EXPECT_LE(std::fabs(ma.mean - mb.mean), 5 * std::hypot(ma.standard_error, mb.standard_error))
                << static_cast<int>(kind) << " quarter " << q << ": " << ma.mean << " " << mb.mean;
        }
        EXPECT_GT(max_mirror_z(*a, *b, false), 10.0) << static_cast<int>(kind);  // the scene is not symmetric
    }
}

TEST(SceneLoader, CameraFieldOfViewAndHandednessErrors) {
    auto camera = [](const std::string& keys) {
        return "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]" + keys +
               "},\n\"shapes\": [{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, \"emission\": 1}]}";
    };
    expect_error_at(camera(R"(, "vfov_degrees": 40, "fov_degrees": 50)"), "50", "camera has both vfov_degrees and fov_degrees");
    expect_error_at(camera(R"(, "fov_degrees": 50, "fov_axis": "diagonal")"), "\"diagonal\"",
                    "Expected \"vertical\", \"horizontal\", \"smaller\" or \"larger\"");
    expect_error_at(camera(R"(, "fov_axis": "smaller")"), "\"smaller\"", "camera fov_axis goes with fov_degrees");
    expect_error_at(camera(R"(, "fov_degrees": 180)"), "180", "camera fov_degrees is 180; expected a number in (0, 179.9]");
    expect_error_at(camera(R"(, "handedness": "lft")"), "\"lft\"", "unknown camera handedness \"lft\". Did you mean \"left\"?");
}

/// scenes/cornell*.json against the C++ definitions of DESIGN.md: identical films.
TEST(SceneLoader, CornellFilesRenderBitIdenticallyToTheCppDefinitions) {
    for (const char* name : {"cornell", "cornell-point"})
        for (int bins : {SpectralResolution::kDefaultBins, SpectralResolution::kExact}) {
            const SpectralResolution res{bins};
            const Scene from_file = *load_builtin_scene(name, res);
            const Scene reference = *test::make_cornell_reference(name, res);
            EXPECT_EQ(from_file.camera.position, reference.camera.position);
            EXPECT_EQ(from_file.camera.fov_degrees, reference.camera.fov_degrees);
            const RenderSettings settings = test::small_settings(24, 24, 4, 7, 2);
            const auto a = test::render_film(from_file, settings);
            const auto b = test::render_film(reference, settings);
            for (int y = 0; y < 24; ++y)
                for (int x = 0; x < 24; ++x) {
                    const Xyz p = a->pixel_xyz(x, y), q = b->pixel_xyz(x, y);
                    ASSERT_EQ(p.x, q.x) << name << " " << x << "," << y;
                    ASSERT_EQ(p.y, q.y);
                    ASSERT_EQ(p.z, q.z);
                }
        }
}

}  // namespace
}  // namespace spt

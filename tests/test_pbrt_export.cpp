// The pbrt-v4 writer (scene/pbrt_scene_writer.h): a description built in code is written with
// the directives and values pbrt-v4 needs to render the same image (the camera mirrored into
// pbrt-v4's left-handed camera space, its fov on the shorter image axis, light spectra
// tabulated with scale = luminance, two-sided area lights, the transform's column order),
// what pbrt-v4 cannot express is a comment, and the command line replaces an output only
// with a complete file.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "scene/pbrt_scene_writer.h"
#include "scene/scene_builder.h"
#include "scene/spectrum_parser.h"
#include "spectral/cie.h"

#ifndef SPT_PATHTRACER
#error "SPT_PATHTRACER must name the pathtracer program"
#endif

namespace spt {
namespace {

namespace fs = std::filesystem;

ParamValue str(const char* s) { return ParamValue::string(s); }
ParamValue num(double x) { return ParamValue::number(x); }

/// A camera, a diffuse material, an emitting quad (a 3000 K blackbody), a sphere and a point
/// light, on a width × height image.
SceneDescription small_scene(int width, int height) {
    SceneDescription d;
    d.files = {"code"};
    d.name = "small";
    d.root.set("camera", ParamValue::dict({{"position", ParamValue::numbers({0, 1, 5})},
                                           {"look_at", ParamValue::numbers({0, 0, 0})},
                                           {"vfov_degrees", num(40)}}));
    d.root.set("image", ParamValue::dict({{"width", num(width)}, {"height", num(height)}, {"spp", num(16)}}));
    d.root.set("materials", ParamValue::dict({{"white", ParamValue::dict({{"type", str("diffuse")}, {"kd", num(0.5)}})}}));
    const ParamValue emission = ParamValue::dict({{"type", str("blackbody")}, {"temperature_k", num(3000)}, {"scale", num(5)}});
    d.root.set("shapes",
               ParamValue::list({ParamValue::dict({{"type", str("quad")},
                                                   {"origin", ParamValue::numbers({-0.5, 2, -0.5})},
                                                   {"edge1", ParamValue::numbers({1, 0, 0})},
                                                   {"edge2", ParamValue::numbers({0, 0, 1})},
                                                   {"emission", emission}}),
                                 ParamValue::dict({{"type", str("sphere")},
                                                   {"center", ParamValue::numbers({0, 0.5, 0})},
                                                   {"radius", num(0.5)},
                                                   {"material", str("white")}})}));
    d.root.set("lights", ParamValue::list({ParamValue::dict({{"type", str("point")},
                                                             {"position", ParamValue::numbers({1, 2, 3})},
                                                             {"intensity", num(2)}})}));
    return d;
}

std::string export_text(const SceneDescription& d) {
    PbrtExportSettings settings;
    settings.output_path = "out.pbrt";
    return export_pbrt(d, settings).text;
}

/// The number after `key` (the first occurrence).
double number_after(const std::string& text, const std::string& key) {
    const auto at = text.find(key);
    EXPECT_NE(at, std::string::npos) << key;
    if (at == std::string::npos) return NAN;
    return std::stod(text.substr(at + key.size()));
}

TEST(PbrtExport, TheDescriptionBuildsAndItsExportHasTheDirectives) {
    const SceneDescription d = small_scene(64, 48);
    const RelativeFileReader none = [](const std::string&, std::string&, std::string&, std::string& why) {
        why = "no files";
        return false;
    };
    build_scene(d, SpectralResolution{}, none);  // the scene is one the renderer accepts
    const std::string t = export_text(d);
    EXPECT_NE(t.find("Film \"rgb\" \"integer xresolution\" 64 \"integer yresolution\" 48 \"string filename\" \"out.exr\""),
              std::string::npos) << t;
    EXPECT_NE(t.find("Sampler \"zsobol\" \"integer pixelsamples\" 16"), std::string::npos);
    EXPECT_NE(t.find("Integrator \"path\" \"integer maxdepth\" 100"), std::string::npos);
    EXPECT_NE(t.find("PixelFilter \"box\" \"float xradius\" 0.5 \"float yradius\" 0.5"), std::string::npos);
    // The mirror is part of the camera transform: right before LookAt, and before WorldBegin.
    const auto scale = t.find("\nScale -1 1 1\nLookAt 0 1 5  0 0 0  0 1 0\n");
    ASSERT_NE(scale, std::string::npos) << t;
    EXPECT_LT(scale, t.find("WorldBegin"));
    EXPECT_EQ(t.find("Scale", scale + 2), std::string::npos) << "the world must not be mirrored";
    EXPECT_NE(t.find("MakeNamedMaterial \"white\" \"string type\" \"diffuse\" \"spectrum reflectance\" [ 360 0.5 830 0.5 ]"),
              std::string::npos);
    EXPECT_NE(t.find("NamedMaterial \"white\"\n  Translate 0 0.5 0\n  Rotate 90 1 0 0\n  Shape \"sphere\" \"float radius\" 0.5"), std::string::npos);
    // The quad keeps its winding (pbrt-v4's triangle normal is (p1 - p0) x (p2 - p0), as ours).
    EXPECT_NE(t.find("Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -0.5 2 -0.5 0.5 2 -0.5 0.5 2 0.5 -0.5 2 0.5 ]"),
              std::string::npos) << t;
    EXPECT_NE(t.find("LightSource \"point\" \"point3 from\" [ 1 2 3 ] \"spectrum I\" [ 360 2 830 2 ] \"float scale\" 2"),
              std::string::npos) << t;
}

TEST(PbrtExport, AnAreaLightIsItsTabulatedSpectrumWithItsLuminanceAsScaleAndTwoSided) {
    SceneDescription d = small_scene(64, 48);
    const std::string t = export_text(d);
    const auto at = t.find("AreaLightSource \"diffuse\" \"spectrum L\" [");
    ASSERT_NE(at, std::string::npos) << t;
    const std::string rest = t.substr(at);
    const std::string table = rest.substr(rest.find('[') + 1, rest.find(']') - rest.find('[') - 1);
    std::istringstream in(table);
    std::vector<std::pair<double, double>> pairs;
    for (double l, v; in >> l >> v;) pairs.emplace_back(l, v);
    ASSERT_EQ(pairs.size(), 95u);  // 360, 365, ... 830 nm
    const SpectrumSource bb = SpectrumSource::blackbody(3000, 5, 560);
    for (const auto& [l, v] : pairs) EXPECT_NEAR(v, bb.eval(l), 1e-8 * bb.eval(l)) << l;
    EXPECT_EQ(pairs.front().first, 360);
    EXPECT_EQ(pairs.back().first, 830);
    // pbrt-v4 divides L by its luminance; the scale restores ours.
    EXPECT_NEAR(number_after(rest, "\"float scale\" "), cie_luminance(bb), 1e-8 * cie_luminance(bb));
    EXPECT_NE(rest.find("\"bool twosided\" true"), std::string::npos);
    EXPECT_LT(rest.find("\"bool twosided\" true"), rest.find("Shape"));

    // One-sided emitters stay one-sided.
    ParamValue shapes = *d.root.peek("shapes");
    ParamValue quad = shapes.items()[0];
    quad.set("two_sided", ParamValue::boolean(false));
    d.root.set("shapes", ParamValue::list({quad}));
    EXPECT_NE(export_text(d).find("\"bool twosided\" false"), std::string::npos);
}

TEST(PbrtExport, LuminanceIsTheFilmsYRelativeToAConstantOne) {
    EXPECT_DOUBLE_EQ(cie_luminance(SpectrumSource::constant(1)), 1.0);
    EXPECT_NEAR(cie_luminance(SpectrumSource::constant(3.5)), 3.5, 1e-12);
    // ȳ peaks at 555 nm: a narrow line there is brighter than the mean, one at 450 nm darker.
    EXPECT_GT(cie_luminance(SpectrumSource::gaussian(555, 10, 1)), cie_luminance(SpectrumSource::gaussian(450, 10, 1)));
}

TEST(PbrtExport, TheFovIsThatOfTheShorterImageAxis) {
    // Landscape: the vertical axis is the shorter one, so pbrt-v4's fov is our vertical fov.
    EXPECT_NEAR(number_after(export_text(small_scene(400, 200)), "\"float fov\" "), 40, 1e-6);
    // Portrait: the horizontal axis is shorter: tan(fov/2) = tan(20°)·w/h.
    const double expected = 2 * std::atan(std::tan(20 * M_PI / 180) * 200.0 / 400.0) * 180 / M_PI;
    EXPECT_NEAR(number_after(export_text(small_scene(200, 400)), "\"float fov\" "), expected, 1e-6);
    EXPECT_NEAR(expected, 20.6, 0.1);  // the formula is not the identity
    EXPECT_NEAR(pbrt_fov_degrees(40, 300, 300), 40, 1e-12);
}

TEST(PbrtExport, ALeftHandedCameraIsNotMirroredAndKeepsItsFov) {
    SceneDescription d = small_scene(200, 400);
    d.root.set("camera", ParamValue::dict({{"position", ParamValue::numbers({0, 0, 0})},
                                           {"look_at", ParamValue::numbers({0, 0, 1})},
                                           {"up", ParamValue::numbers({0, 1, 0})},
                                           {"handedness", str("left")},
                                           {"fov_degrees", num(50)},
                                           {"fov_axis", str("smaller")}}));
    const std::string t = export_text(d);
    EXPECT_EQ(t.find("Scale -1 1 1"), std::string::npos);
    EXPECT_NEAR(number_after(t, "\"float fov\" "), 50, 1e-6);
}

TEST(PbrtExport, TransformsAreWrittenColumnByColumn) {
    SceneDescription d = small_scene(64, 48);
    ParamValue quad = d.root.peek("shapes")->items()[0];
    quad.set("transform", ParamValue::dict({{"translate", ParamValue::numbers({1, 2, 3})}}));
    d.root.set("shapes", ParamValue::list({quad}));
    EXPECT_NE(export_text(d).find("ConcatTransform [ 1 0 0 0 0 1 0 0 0 0 1 0 1 2 3 1 ]"), std::string::npos);
}

TEST(PbrtExport, WhatPbrtCannotExpressIsAComment) {
    SceneDescription d = small_scene(64, 48);
    ParamValue shapes = *d.root.peek("shapes");
    ParamValue plane = ParamValue::dict({{"type", str("plane")},
                                         {"normal", ParamValue::numbers({0, 1, 0})},
                                         {"point", ParamValue::numbers({0, 0, 0})},
                                         {"material", str("white")}});
    std::vector<ParamValue> list = shapes.items();
    list.push_back(plane);
    d.root.set("shapes", ParamValue::list(list));
    d.root.set("media", ParamValue::dict({{"fog", ParamValue::dict({{"type", str("homogeneous")},
                                                                    {"sigma_a", num(0.1)},
                                                                    {"sigma_s", num(0.1)}})}}));
    d.root.set("medium", str("fog"));
    d.root.set("background", ParamValue::dict({{"type", str("sky")}, {"sun_elevation_degrees", num(30)}}));
    ParamValue materials = *d.root.peek("materials");
    materials.set("ink", ParamValue::dict({{"type", str("fluorescent")},
                                           {"dye", str("fluorescein")},
                                           {"surface", ParamValue::dict({{"type", str("conductor")},
                                                                         {"metal", str("Au")}})}}));
    d.root.set("materials", materials);
    const std::string t = export_text(d);
    EXPECT_TRUE(std::regex_search(t, std::regex("\n# material \"ink\": its fluorescent dye layer[^\n]*\n"
                                                "MakeNamedMaterial \"ink\" \"string type\" \"conductor\"")));
    EXPECT_TRUE(std::regex_search(t, std::regex("\n# the background's Hosek-Wilkie sky and sun are not exported[^\n]*\n")));
    EXPECT_TRUE(std::regex_search(t, std::regex("\n# plane \\(shape 2\\): pbrt-v4 has no infinite plane[^\n]*\n")));
    EXPECT_TRUE(std::regex_search(t, std::regex("\n# participating media[^\n]*not exported[^\n]*\n")));
    // Every line is a comment, a directive or a continuation of one: nothing else.
    std::istringstream in(t);
    for (std::string line; std::getline(in, line);) {
        const auto first = line.find_first_not_of(' ');
        if (first == std::string::npos) continue;
        EXPECT_TRUE(line[first] == '#' || std::isupper(static_cast<unsigned char>(line[first]))) << line;
    }
}

// ---- the command line ----

struct RunResult {
    int exit_code = -1;
    std::string err;
};

RunResult run_in(const fs::path& dir, const std::string& args) {
    const std::string cmd = "cd '" + dir.string() + "' && '" SPT_PATHTRACER "' " + args + " 2>err.txt";
    const int status = std::system(cmd.c_str());
    std::ifstream in(dir / "err.txt");
    return {(status != -1 && WIFEXITED(status)) ? WEXITSTATUS(status) : -1,
            std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>())};
}

std::string read_all(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(PbrtExportCli, WritesTheFileAndItsMeshesReplacesOnlyWithACompleteFileAndRendersNothing) {
    const fs::path dir = fs::temp_directory_path() / ("spt_pbrt_export_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    {
        std::ofstream(dir / "out.pbrt") << "old";
    }
    // A scene that fails to load leaves the old file as it was.
    {
        std::ofstream(dir / "bad.json") << "{\"camera\": {\"position\": [0, 0, 1]}, \"shapes\": []}";
    }
    RunResult r = run_in(dir, "bad.json --export-pbrt out.pbrt");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(read_all(dir / "out.pbrt"), "old");
    // A built-in scene with PLY meshes: the file is replaced, the meshes are written beside it.
    r = run_in(dir, "showcase --export-pbrt out.pbrt --width 32 --height 24 --spp 4");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const std::string t = read_all(dir / "out.pbrt");
    EXPECT_NE(t.find("Film \"rgb\" \"integer xresolution\" 32 \"integer yresolution\" 24"), std::string::npos);
    EXPECT_NE(t.find("Shape \"plymesh\" \"string filename\" \"prism.ply\""), std::string::npos);
    EXPECT_TRUE(fs::exists(dir / "prism.ply"));
    EXPECT_NE(r.err.find("wrote out.pbrt"), std::string::npos) << r.err;
    // No render: no image, and no temporary file left behind.
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string name = e.path().filename().string();
        EXPECT_TRUE(name.ends_with(".pbrt") || name.ends_with(".ply") || name.ends_with(".json") || name == "err.txt")
            << name;
    }
    EXPECT_NE(run_in(dir, "cornell --export-pbrt out.txt").exit_code, 0);
    fs::remove_all(dir);
}

TEST(PbrtExportCli, AnExportedSceneReadBackRendersTheSameImage) {
    // colorchecker: diffuse patches (tabulated spectra), an environment and a camera; the
    // export expresses all of it, so reading it back gives the same scene, bit for bit.
    const fs::path dir = fs::temp_directory_path() / ("spt_pbrt_roundtrip_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    ASSERT_EQ(run_in(dir, "colorchecker --export-pbrt cc.pbrt").exit_code, 0);
    const std::string settings = " --width 24 --height 16 --spp 4 --seed 5 --threads 2 --quiet";
    ASSERT_EQ(run_in(dir, "colorchecker -o a.pfm" + settings).exit_code, 0);
    const RunResult back = run_in(dir, "cc.pbrt -o b.pfm" + settings);
    ASSERT_EQ(back.exit_code, 0) << back.err;
    EXPECT_EQ(back.err.find("warning"), std::string::npos) << back.err;
    const std::string a = read_all(dir / "a.pfm"), b = read_all(dir / "b.pfm");
    ASSERT_GT(a.size(), 24u * 16u * 12u);
    EXPECT_TRUE(a == b) << "the exported colorchecker renders differently";
    fs::remove_all(dir);
}

}  // namespace
}  // namespace spt

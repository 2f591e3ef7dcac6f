// The pbrt-v4 reader: what each directive becomes in the scene description (pbrt-v4's camera
// space, transforms, defaults, spectra, area lights, instancing), warnings for what is not
// supported, and a located error for every malformed file.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "scene/pbrt_scene_reader.h"

namespace spt {
namespace {

/// Reads `text` as "s.pbrt"; Include and other files come from `files`.
SceneDescription read(const std::string& text, const std::map<std::string, std::string>& files = {}) {
    const RelativeFileReader reader = [&](const std::string& rel, std::string& contents, std::string& display,
                                          std::string& why) {
        const auto it = files.find(rel);
        if (it == files.end()) {
            why = "no such file";
            return false;
        }
        contents = it->second;
        display = rel;
        return true;
    };
    return read_pbrt_scene(text, "s.pbrt", "s", reader);
}

const ParamValue& at(const ParamValue& v, const std::string& key) {
    const ParamValue* m = v.peek(key);
    if (!m) throw std::runtime_error("no key " + key);
    return *m;
}

std::vector<double> numbers(const ParamValue& v) {
    std::vector<double> xs;
    for (const ParamValue& x : v.items()) xs.push_back(x.as_number());
    return xs;
}

void expect_near(const std::vector<double>& a, const std::vector<double>& b, double tol = 1e-12) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], tol) << "element " << i;
}

const ParamValue& shape(const SceneDescription& d, std::size_t i) { return at(d.root, "shapes").items().at(i); }

TEST(PbrtReader, LookAtGivesPbrtsLeftHandedCameraAndFovOfTheShorterAxis) {
    const SceneDescription d = read("LookAt 1 2 3  1 2 0  0 1 0\nCamera \"perspective\" \"float fov\" 45\nWorldBegin\n");
    const ParamValue& c = at(d.root, "camera");
    expect_near(numbers(at(c, "position")), {1, 2, 3});
    expect_near(numbers(at(c, "look_at")), {1, 2, 2});
    expect_near(numbers(at(c, "up")), {0, 1, 0});
    EXPECT_EQ(at(c, "handedness").as_string(), "left");
    EXPECT_EQ(at(c, "fov_degrees").as_number(), 45);
    EXPECT_EQ(at(c, "fov_axis").as_string(), "smaller");
    EXPECT_TRUE(d.warnings.empty());
}

TEST(PbrtReader, AMirroringCameraTransformGivesARightHandedCamera) {
    const SceneDescription d = read("Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n");
    const ParamValue& c = at(d.root, "camera");
    EXPECT_EQ(at(c, "handedness").as_string(), "right");
    expect_near(numbers(at(c, "position")), {0, 0, 5});
    expect_near(numbers(at(c, "look_at")), {0, 0, 4});
    EXPECT_EQ(at(c, "fov_degrees").as_number(), 90);  // pbrt-v4's default
}

TEST(PbrtReader, FilmSamplerAndIntegratorKeepPbrtsDefaults) {
    const SceneDescription defaults = read("WorldBegin\n");
    EXPECT_EQ(at(at(defaults.root, "image"), "width").as_number(), 1280);
    EXPECT_EQ(at(at(defaults.root, "image"), "height").as_number(), 720);
    EXPECT_EQ(at(at(defaults.root, "image"), "spp").as_number(), 16);
    EXPECT_EQ(at(at(defaults.root, "integrator"), "max_depth").as_number(), 5);
    EXPECT_EQ(at(at(defaults.root, "integrator"), "type").as_string(), "path");

    const SceneDescription d = read(
        "Film \"rgb\" \"integer xresolution\" [ 200 ] \"integer yresolution\" 100\n"
        "Sampler \"stratified\" \"integer xsamples\" 3 \"integer ysamples\" 5\n"
        "Integrator \"bdpt\" \"integer maxdepth\" 12\nWorldBegin\n");
    EXPECT_EQ(at(at(d.root, "image"), "width").as_number(), 200);
    EXPECT_EQ(at(at(d.root, "image"), "height").as_number(), 100);
    EXPECT_EQ(at(at(d.root, "image"), "spp").as_number(), 15);
    EXPECT_EQ(at(at(d.root, "integrator"), "type").as_string(), "bdpt");
    EXPECT_EQ(at(at(d.root, "integrator"), "max_depth").as_number(), 12);
}

TEST(PbrtReader, ASphereTakesItsCentreAndRadiusFromASimilarityTransform) {
    const SceneDescription d =
        read("WorldBegin\nTranslate 1 2 3\nRotate 30 0 1 0\nScale 2 2 2\nShape \"sphere\" \"float radius\" 0.5\n");
    const ParamValue& s = shape(d, 0);
    EXPECT_EQ(at(s, "type").as_string(), "sphere");
    expect_near(numbers(at(s, "center")), {1, 2, 3});
    EXPECT_NEAR(at(s, "radius").as_number(), 1.0, 1e-12);
    EXPECT_EQ(at(s, "material").as_string(), "@default");
    const ParamValue& m = at(at(d.root, "materials"), "@default");
    EXPECT_EQ(at(m, "type").as_string(), "diffuse");
    EXPECT_EQ(at(m, "kd").as_number(), 0.5);
}

TEST(PbrtReader, TransformListsTheMatrixColumnByColumn) {
    // pbrt-v4's Transform takes the 16 values column-major: the last four hold the translation.
    const SceneDescription d =
        read("WorldBegin\nTransform [1 0 0 0  0 1 0 0  0 0 1 0  4 5 6 1]\nShape \"sphere\"\n"
             "AttributeBegin\nConcatTransform [2 0 0 0  0 2 0 0  0 0 2 0  0 0 0 1]\nShape \"sphere\"\nAttributeEnd\n");
    expect_near(numbers(at(shape(d, 0), "center")), {4, 5, 6});
    expect_near(numbers(at(shape(d, 1), "center")), {4, 5, 6});
    EXPECT_EQ(at(shape(d, 1), "radius").as_number(), 2);
}

TEST(PbrtReader, ATriangleMeshKeepsItsWindingUnlessReversedOrMirrored) {
    const std::string mesh = "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2]\n";
    const auto indices = [](const SceneDescription& d) { return numbers(at(shape(d, 0), "indices")); };
    expect_near(indices(read("WorldBegin\n" + mesh)), {0, 1, 2});
    expect_near(indices(read("WorldBegin\nReverseOrientation\n" + mesh)), {0, 2, 1});
    expect_near(indices(read("WorldBegin\nScale 1 1 -1\n" + mesh)), {0, 2, 1});
    expect_near(indices(read("WorldBegin\nReverseOrientation\nScale 1 1 -1\n" + mesh)), {0, 1, 2});
    // With shading normals pbrt-v4 faces each triangle towards them, whatever the winding.
    const std::string with_n = "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2] "
                               "\"normal N\" [0 0 -1 0 0 -1 0 0 -1]\n";
    expect_near(indices(read("WorldBegin\n" + with_n)), {0, 2, 1});
    expect_near(indices(read("WorldBegin\nReverseOrientation\n" + with_n)), {0, 2, 1});
    const SceneDescription d = read("WorldBegin\nTranslate 0 0 2\n" + mesh);
    expect_near(numbers(at(at(shape(d, 0), "transform"), "matrix")), {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 2, 0, 0, 0, 1});
    expect_near(numbers(at(shape(d, 0), "positions")), {0, 0, 0, 1, 0, 0, 0, 1, 0});
}

TEST(PbrtReader, AnAreaLightMakesAOneSidedEmitterOfTheShapesMaterial) {
    const SceneDescription d = read(
        "WorldBegin\nMaterial \"diffuse\" \"rgb reflectance\" [0.2 0.3 0.4]\n"
        "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [4 2 1] \"float scale\" 3\n"
        "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\nAttributeEnd\n"
        "Shape \"sphere\"\n");
    const ParamValue& light = shape(d, 0);
    EXPECT_FALSE(at(light, "two_sided").as_bool());
    const std::string emitting = at(light, "material").as_string();
    EXPECT_EQ(at(shape(d, 1), "material").as_string(), "@1");
    const ParamValue& m = at(at(d.root, "materials"), emitting);
    expect_near(numbers(at(m, "kd")), {0.2, 0.3, 0.4});
    // pbrt-v4's RGB illuminant: the unbounded fit of the colour times D65 at luminance 1, times scale.
    const ParamValue& e = at(m, "emission");
    EXPECT_EQ(at(e, "type").as_string(), "product");
    EXPECT_EQ(at(e, "scale").as_number(), 3);
    const ParamValue& rgb_illuminant = at(e, "factors").items().at(0);
    EXPECT_EQ(at(rgb_illuminant, "type").as_string(), "product");
    const ParamValue& rgb = at(rgb_illuminant, "factors").items().at(0);
    expect_near(numbers(at(rgb, "value")), {0.5, 0.25, 0.125});
    EXPECT_EQ(at(rgb, "scale").as_number(), 8);
    const ParamValue& white = at(rgb_illuminant, "factors").items().at(1);
    EXPECT_EQ(at(white, "type").as_string(), "normalized");
    EXPECT_EQ(at(white, "luminance").as_number(), 1);
    EXPECT_EQ(at(at(white, "spectrum"), "name").as_string(), "D65");
}

TEST(PbrtReader, TwoSidedAreaLightsAndLightsWithoutASpectrumEmitD65) {
    const SceneDescription d =
        read("WorldBegin\nAreaLightSource \"diffuse\" \"bool twosided\" true\nShape \"disk\" \"float radius\" 2\n"
             "LightSource \"point\" \"point3 from\" [1 2 3] \"blackbody I\" 3000\n");
    EXPECT_EQ(shape(d, 0).peek("two_sided"), nullptr);
    EXPECT_EQ(at(shape(d, 0), "radius").as_number(), 2);
    const ParamValue& e = at(at(at(d.root, "materials"), at(shape(d, 0), "material").as_string()), "emission");
    EXPECT_EQ(at(at(e, "factors").items().at(0), "type").as_string(), "normalized");
    const ParamValue& l = at(d.root, "lights").items().at(0);
    expect_near(numbers(at(l, "position")), {1, 2, 3});
    const ParamValue& bb = at(at(at(l, "intensity"), "factors").items().at(0), "spectrum");
    EXPECT_EQ(at(bb, "type").as_string(), "blackbody");
    EXPECT_NEAR(at(bb, "normalize_nm").as_number(), 2.8977721e6 / 3000, 1e-9);
}

TEST(PbrtReader, PbrtsFluorescentIlluminantsAreOurNamedOnes) {
    for (const auto& [pbrt, ours] : {std::pair<std::string, std::string>{"stdillum-F2", "F2"},
                                     {"stdillum-F7", "F7"},
                                     {"stdillum-F11", "F11"}}) {
        const SceneDescription d = read("WorldBegin\nLightSource \"point\" \"spectrum I\" \"" + pbrt + "\"\n");
        const ParamValue& l = at(d.root, "lights").items().at(0);
        const ParamValue& s = at(at(at(l, "intensity"), "factors").items().at(0), "spectrum");
        EXPECT_EQ(at(s, "type").as_string(), "illuminant") << pbrt;
        EXPECT_EQ(at(s, "name").as_string(), ours) << pbrt;
    }
}

TEST(PbrtReader, SpotLightsFollowTheTransformAndPbrtsFalloff) {
    const SceneDescription d = read("WorldBegin\nTranslate 0 1 0\nLightSource \"spot\" \"point3 from\" [0 0 0] "
                                    "\"point3 to\" [0 -1 0] \"float coneangle\" 40 \"float conedeltaangle\" 10\n");
    const ParamValue& l = at(d.root, "lights").items().at(0);
    expect_near(numbers(at(l, "position")), {0, 1, 0});
    expect_near(numbers(at(l, "direction")), {0, -1, 0});
    EXPECT_EQ(at(l, "cone_degrees").as_number(), 40);
    EXPECT_EQ(at(l, "falloff_degrees").as_number(), 30);
}

TEST(PbrtReader, ConductorsMapMeasuredMetalsAndRemapRoughness) {
    const SceneDescription d = read(
        "WorldBegin\nMakeNamedMaterial \"gold\" \"string type\" \"conductor\" \"spectrum eta\" \"metal-Au-eta\" "
        "\"spectrum k\" \"metal-Au-k\" \"float roughness\" 0.04\n"
        "MakeNamedMaterial \"copper\" \"string type\" \"conductor\" \"float uroughness\" 0.01 \"float vroughness\" 0.09 "
        "\"bool remaproughness\" false\n"
        "MakeNamedMaterial \"glass\" \"string type\" \"dielectric\" \"spectrum eta\" \"glass-BK7\"\n");
    const ParamValue& gold = at(at(d.root, "materials"), "gold");
    EXPECT_EQ(at(gold, "metal").as_string(), "Au");
    EXPECT_NEAR(at(gold, "roughness").as_number(), 0.2, 1e-12);  // pbrt-v4: alpha = sqrt(roughness)
    const ParamValue& copper = at(at(d.root, "materials"), "copper");
    EXPECT_EQ(at(copper, "metal").as_string(), "Cu");  // pbrt-v4's default conductor
    EXPECT_EQ(at(copper, "roughness_u").as_number(), 0.01);
    EXPECT_EQ(at(copper, "roughness_v").as_number(), 0.09);
    EXPECT_EQ(at(at(at(d.root, "materials"), "glass"), "ior").peek("name")->as_string(), "N-BK7");
}

TEST(PbrtReader, ObjectInstancesOfAMeshBecomeInstancesOfOneMesh) {
    const SceneDescription d = read(
        "WorldBegin\nObjectBegin \"tri\"\nTranslate 1 0 0\n"
        "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2]\nObjectEnd\n"
        "ObjectInstance \"tri\"\nTranslate 0 5 0\nObjectInstance \"tri\"\n");
    ASSERT_EQ(at(d.root, "shapes").items().size(), 1u);
    const ParamValue& inst = at(shape(d, 0), "instances");
    ASSERT_EQ(inst.items().size(), 2u);
    expect_near(numbers(at(inst.items()[0], "matrix")), {1, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
    expect_near(numbers(at(inst.items()[1], "matrix")), {1, 0, 0, 1, 0, 1, 0, 5, 0, 0, 1, 0, 0, 0, 0, 1});
}

TEST(PbrtReader, IncludedFilesAreReadAndNamedInMessages) {
    const SceneDescription d =
        read("WorldBegin\nInclude \"geometry.pbrt\"\n", {{"geometry.pbrt", "# spheres\nShape \"sphere\"\n"}});
    EXPECT_EQ(at(d.root, "shapes").items().size(), 1u);
    EXPECT_EQ(d.files.at(shape(d, 0).pos().file), "geometry.pbrt");
    EXPECT_EQ(shape(d, 0).pos().line, 2);
    try {
        read("WorldBegin\nInclude \"g.pbrt\"\n", {{"g.pbrt", "\n  Shape \"sphere\" \"float radius\" [1 2]\n"}});
        FAIL() << "two radii were accepted";
    } catch (const LocatedError& e) {
        EXPECT_EQ(e.origin(), "g.pbrt");
        EXPECT_EQ(e.pos().line, 2);
        EXPECT_EQ(e.pos().column, 18);
    }
}

TEST(PbrtReader, WhatIsNotSupportedIsALocatedWarningNeverSilence) {
    const SceneDescription d = read(
        "WorldBegin\nShape \"sphere\" \"float zmax\" 0.5 \"float frobnicate\" 1\n"
        "Material \"hair\"\nLightSource \"goniometric\"\nPixelFilter \"gaussian\"\nPixelFilter \"box\"\n");
    ASSERT_EQ(d.warnings.size(), 5u);
    EXPECT_NE(d.warnings[0].find("s.pbrt:2:16: \"zmax\" (a partial shape) is not supported"), std::string::npos) << d.warnings[0];
    EXPECT_NE(d.warnings[1].find("s.pbrt:2:33: parameter \"float frobnicate\""), std::string::npos) << d.warnings[1];
    EXPECT_NE(d.warnings[2].find("s.pbrt:3:10: Material \"hair\" is approximated"), std::string::npos) << d.warnings[2];
    EXPECT_NE(d.warnings[3].find("s.pbrt:4:1: LightSource \"goniometric\" is not supported"), std::string::npos) << d.warnings[3];
    EXPECT_NE(d.warnings[4].find("s.pbrt:5:1: PixelFilter"), std::string::npos) << d.warnings[4];
}

/// Each malformed file: one located error, and the words that say what is wrong.
struct Malformed {
    const char* text;
    const char* where;  ///< "line:column"
    const char* says;
};

class PbrtMalformed : public testing::TestWithParam<Malformed> {};

TEST_P(PbrtMalformed, IsOneLocatedError) {
    const Malformed& m = GetParam();
    try {
        read(m.text, {{"self.pbrt", "Include \"self.pbrt\"\n"}, {"bad.ply", "ply\n"}});
        FAIL() << "accepted: " << m.text;
    } catch (const LocatedError& e) {
        const std::string where = std::to_string(e.pos().line) + ":" + std::to_string(e.pos().column);
        EXPECT_EQ(where, m.where) << e.what();
        EXPECT_NE(std::string(e.what()).find(m.says), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("; expected"), std::string::npos) << e.what();
    }
}

const Malformed kMalformed[] = {
    {"Shape \"sphere", "1:7", "string never closed"},
    {"Shape \"sphere\nradius\"", "1:7", "past the end of its line"},
    {"WorldBegin\nShape \"sphere\" \"float radius\" [ 1", "2:31", "'[' never closed"},
    {"Frobnicate 1 2 3", "1:1", "unknown directive 'Frobnicate'"},
    {"WorldBegin\nShape \"sphere\" \"complex radius\" 1", "2:16", "unknown parameter type \"complex\""},
    {"WorldBegin\nShape \"sphere\" \"radius\" 1", "2:16", "is not a type and a name"},
    {"WorldBegin\nShape \"sphere\" \"float radius\"", "2:30", "expected its value"},
    {"WorldBegin\nShape \"sphere\" \"float radius\" [1 2]", "2:16", "has 2 values; expected 1"},
    {"WorldBegin\nShape \"sphere\" \"float radius\" \"big\"", "2:31", "a string for the float parameter"},
    {"WorldBegin\nShape \"sphere\" \"float radius\" 1x", "2:31", "is not a finite number"},
    {"WorldBegin\nShape \"sphere\" \"float radius\" nan", "2:31", "is not a finite number"},
    {"WorldBegin\nShape \"sphere\" \"float radius\" 1 \"float radius\" 2", "2:33", "given twice"},
    {"WorldBegin\nShape \"sphere\" \"float radius\" -1", "2:16", "expected > 0"},
    {"WorldBegin\nShape \"sphere\" \"integer radius\" 1.5", "2:33", "expected an integer"},
    {"WorldBegin\nShape \"sphere\" \"bool radius\" maybe", "2:30", "expected true or false"},
    {"WorldBegin\nShape \"sphere\" \"string radius\" 3", "2:32", "expected a string in double quotes"},
    {"Translate 1 2", "1:14", "end of the file"},
    {"Translate 1 2 x", "1:15", "Translate takes 3 numbers; got 'x'"},
    {"Rotate 90 0 0 0", "1:1", "non-zero axis"},
    {"Scale 1 1 1e999", "1:11", "got '1e999'"},
    {"LookAt 0 0 0 0 0 0 0 1 0", "1:1", "eye at the point looked at"},
    {"LookAt 0 0 0 0 1 0 0 1 0", "1:1", "up vector along the view direction"},
    {"Transform [1 0 0 0 0 1 0 0 0 0 0 0 0 0 0 1]", "1:1", "singular matrix"},
    {"Transform [1 0 0 1 0 1 0 0 0 0 1 0 0 0 0 1]", "1:1", "projective matrix"},
    {"Transform [1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1", "1:43", "expected ']' after them"},
    {"AttributeEnd", "1:1", "AttributeEnd without AttributeBegin"},
    {"WorldBegin\nAttributeBegin\nShape \"sphere\"\n", "2:1", "AttributeBegin without a matching AttributeEnd"},
    {"TransformEnd", "1:1", "TransformEnd without TransformBegin"},
    {"WorldBegin\nObjectInstance \"nothing\"", "2:16", "unknown object \"nothing\""},
    {"WorldBegin\nObjectEnd", "2:1", "ObjectEnd without ObjectBegin"},
    {"WorldBegin\nObjectBegin \"a\"\nObjectBegin \"b\"", "3:13", "ObjectBegin inside the object"},
    {"WorldBegin\nObjectBegin \"a\"\nShape \"sphere\"", "2:13", "without ObjectEnd"},
    {"WorldBegin\nNamedMaterial \"nothing\"", "2:15", "unknown material \"nothing\""},
    {"WorldBegin\nMakeNamedMaterial \"m\" \"float roughness\" 1", "2:19", "has no \"string type\""},
    {"WorldBegin\nInclude \"missing.pbrt\"", "2:9", "cannot read \"missing.pbrt\""},
    {"WorldBegin\nInclude \"self.pbrt\"", "1:9", "includes itself"},
    {"WorldBegin\nCamera \"perspective\"", "2:1", "Camera inside the world"},
    {"WorldBegin\nWorldBegin", "2:1", "WorldBegin inside the world"},
    {"WorldBegin\nCoordSysTransform \"nowhere\"", "2:19", "unknown coordinate system"},
    {"WorldBegin\nScale 1 2 1\nShape \"sphere\"", "3:1", "an ellipsoid is not a shape here"},
    {"WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 3]", "2:53",
     "index 3 is outside the 3 vertices"},
    {"WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1]", "2:22", "expected a multiple of 3"},
    {"WorldBegin\nShape \"trianglemesh\" \"integer indices\" [0 1 2]", "2:1", "without \"point3 P\""},
    {"WorldBegin\nShape \"plymesh\"", "2:1", "without \"string filename\""},
    {"WorldBegin\nMaterial \"diffuse\" \"rgb reflectance\" [0.5 1.5 0.5]", "2:20", "component above 1"},
    {"WorldBegin\nMaterial \"diffuse\" \"rgb reflectance\" [0.5 0.5]", "2:20", "expected 3"},
    {"WorldBegin\nMaterial \"dielectric\" \"spectrum eta\" \"glass-Unobtainium\"", "2:23", "named spectrum \"glass-Unobtainium\""},
    {"WorldBegin\nMaterial \"dielectric\" \"spectrum eta\" [400 1.5 500]", "2:23", "pairs of wavelength"},
    {"WorldBegin\nMaterial \"conductor\" \"spectrum eta\" \"metal-TiO2-eta\" \"spectrum k\" \"metal-TiO2-k\"", "2:22",
     "the metal \"TiO2\" is not available"},
    {"WorldBegin\nMaterial \"diffuse\" \"texture reflectance\" \"nothing\"", "2:20", "unknown texture \"nothing\""},
    {"WorldBegin\nAreaLightSource \"goniometric\"", "2:1", "expected \"diffuse\""},
    {"WorldBegin\nLightSource \"spot\" \"point3 from\" [0 0 0] \"point3 to\" [0 0 0]", "2:1", "\"from\" equal to \"to\""},
    {"Integrator \"path\" \"integer maxdepth\" -1", "1:19", "expected at least 0"},
    {"ActiveTransform Sometimes", "1:1", "expected All, StartTime or EndTime"},
    {"WorldBegin\nTexture \"t\" \"color\" \"imagemap\"", "2:9", "expected \"spectrum\" or \"float\""},
    {"WorldBegin\nTexture \"t\" \"spectrum\" \"imagemap\"", "2:9", "has no \"string filename\""},
    {"WorldBegin\n]", "2:1", "unexpected ']'"},
};

INSTANTIATE_TEST_SUITE_P(Files, PbrtMalformed, testing::ValuesIn(kMalformed));

}  // namespace
}  // namespace spt

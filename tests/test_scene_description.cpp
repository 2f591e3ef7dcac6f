// The format-neutral scene description: scenes built in code without any file format, the
// JSON reader keeping every position, errors naming the position a description recorded,
// the read tracking of the parameter bag, and the reader table.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>

#include "scene/json_scene_reader.h"
#include "scene/material_types.h"
#include "scene/scene_builder.h"
#include "scene/scene_loader.h"

namespace spt {
namespace {

const RelativeFileReader kNoFiles = [](const std::string&, std::string&, std::string&, std::string& why) {
    why = "no files in this test";
    return false;
};

/// A camera looking at the origin and one sphere of material "m" (a grey diffuse), in code.
SceneDescription sphere_scene(ParamValue radius) {
    SceneDescription d;
    d.origin = "code";
    d.name = "in-code";
    d.root.set("camera", ParamValue::dict({{"position", ParamValue::numbers({0, 0, 5})},
                                           {"look_at", ParamValue::numbers({0, 0, 0})}}));
    d.root.set("materials", ParamValue::dict({{"m", ParamValue::dict({{"type", ParamValue::string("diffuse")},
                                                                       {"kd", ParamValue::number(0.5)}})}}));
    d.root.set("shapes", ParamValue::list({ParamValue::dict({{"type", ParamValue::string("sphere")},
                                                             {"center", ParamValue::vec3({1, 2, 3})},
                                                             {"radius", std::move(radius)},
                                                             {"material", ParamValue::string("m")}})}));
    return d;
}

TEST(SceneDescription, SceneBuiltInCodeWithoutAnyFileFormat) {
    const Scene s = build_scene(sphere_scene(ParamValue::number(0.75)), SpectralResolution{}, kNoFiles);
    ASSERT_EQ(s.spheres.size(), 1u);
    EXPECT_EQ(s.spheres[0].center, Vec3(1, 2, 3));
    EXPECT_EQ(s.spheres[0].radius, 0.75f);
    EXPECT_EQ(s.name, "in-code");
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_EQ(s.materials[0].name, "m");
    EXPECT_TRUE(std::holds_alternative<DiffuseBsdf>(s.materials[0].bsdf));
}

TEST(SceneDescription, ErrorsNameThePositionTheDescriptionRecorded) {
    try {
        build_scene(sphere_scene(ParamValue::number(-1, {3, 7})), SpectralResolution{}, kNoFiles);
        FAIL() << "a negative radius was accepted";
    } catch (const LocatedError& e) {
        EXPECT_EQ(e.origin(), "code");
        EXPECT_EQ(e.pos().line, 3);
        EXPECT_EQ(e.pos().column, 7);
        EXPECT_NE(e.message().find("radius is -1; expected a number in (0"), std::string::npos) << e.what();
    }
}

TEST(SceneDescription, JsonReaderKeepsEveryPosition) {
    const SceneDescription d = read_json_scene("{\n  \"shapes\": [\n    {\"radius\": 2}]}", "f.json", "f");
    EXPECT_EQ(d.origin, "f.json");
    EXPECT_EQ(d.name, "f");
    ASSERT_TRUE(d.root.is_object());
    EXPECT_EQ(d.root.key_pos(0).line, 2);
    EXPECT_EQ(d.root.key_pos(0).column, 3);
    const ParamValue* shapes = d.root.find("shapes");
    ASSERT_TRUE(shapes && shapes->is_array());
    const ParamValue& shape = shapes->items().at(0);
    EXPECT_EQ(shape.pos().line, 3);
    EXPECT_EQ(shape.pos().column, 5);
    const ParamValue* radius = shape.find("radius");
    ASSERT_TRUE(radius && radius->is_number());
    EXPECT_EQ(radius->as_number(), 2.0);
    EXPECT_EQ(radius->pos().column, 16);
}

TEST(SceneDescription, TheBagTracksWhichParametersWereRead) {
    const ParamValue p = ParamValue::dict({{"a", ParamValue::number(1)}, {"b", ParamValue::boolean(true)},
                                           {"c", ParamValue::string("x")}});
    EXPECT_EQ(p.unread_keys(), (std::vector<std::string>{"a", "b", "c"}));
    ASSERT_NE(p.find("b"), nullptr);
    EXPECT_EQ(p.find("nope"), nullptr);
    EXPECT_EQ(p.unread_keys(), (std::vector<std::string>{"a", "c"}));
}

TEST(SceneDescription, SetReplacesAKeyAndBuildersGiveTheirKinds) {
    ParamValue p = ParamValue::dict();
    p.set("k", ParamValue::number(1)).set("k", ParamValue::number(2));
    ASSERT_EQ(p.members().size(), 1u);
    EXPECT_EQ(p.find("k")->as_number(), 2.0);
    const ParamValue v = ParamValue::vec3({1, 2, 3});
    ASSERT_TRUE(v.is_array());
    ASSERT_EQ(v.items().size(), 3u);
    EXPECT_EQ(v.items()[2].as_number(), 3.0);
    EXPECT_STREQ(ParamValue::kind_name(ParamValue::Kind::Dict), "an object");
    EXPECT_STREQ(ParamValue::kind_name(ParamValue::Kind::List), "an array");
}

TEST(SceneDescription, JsonIsTheFirstReaderAndReadsFilesWithoutAKnownEnding) {
    ASSERT_FALSE(scene_readers().empty());
    EXPECT_STREQ(scene_readers().front().extension, ".json");
    // A name without a listed ending is read by the first reader: today's behaviour for any
    // file name.
    const std::string text = R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "emission": 1}]})";
    EXPECT_EQ(load_scene_text(text, "scene.txt", "s", SpectralResolution{}, kNoFiles).spheres.size(), 1u);
}

}  // namespace
}  // namespace spt

namespace spt {
namespace {

/// The smallest parameters each material type accepts.
const std::map<std::string, std::string> kMinimalMaterial = {
    {"diffuse", "{}"},
    {"lobes", R"({"ks": 0.5})"},
    {"conductor", R"({"metal": "Au"})"},
    {"dielectric", R"({"ior": 1.5})"},
    {"plastic", R"({"kd": 0.5})"},
    {"thin_sheet", R"({"thickness_nm": 400, "ior": 1.33})"},
};

TEST(MaterialTypes, EveryRowOfTheTableMakesItsOwnBsdf) {
    // A table row whose create function made another type's BSDF, or a type missing from the
    // table, fails here.
    ASSERT_EQ(material_types().size(), kMinimalMaterial.size());
    std::set<std::size_t> made;
    for (const MaterialType& t : material_types()) {
        ASSERT_TRUE(kMinimalMaterial.count(t.name)) << t.name;
        ASSERT_EQ(find_material_type(t.name), &t);
        ParamValue def = param_value_from_json(parse_json(kMinimalMaterial.at(t.name), "m.json"));
        def.set("type", ParamValue::string(t.name));
        SceneDescription d = sphere_scene(ParamValue::number(1));
        d.root.set("materials", ParamValue::dict({{"m", def}}));
        const Scene s = build_scene(d, SpectralResolution{}, kNoFiles);
        made.insert(s.materials.at(0).bsdf.index());
    }
    EXPECT_EQ(made.size(), material_types().size());
    EXPECT_EQ(find_material_type("velvet"), nullptr);
}

TEST(MaterialTypes, TheUnknownTypeMessageListsTheTable) {
    SceneDescription d = sphere_scene(ParamValue::number(1));
    d.root.set("materials", ParamValue::dict({{"m", ParamValue::dict({{"type", ParamValue::string("conductr", {4, 9})}})}}));
    try {
        build_scene(d, SpectralResolution{}, kNoFiles);
        FAIL() << "an unknown material type was accepted";
    } catch (const LocatedError& e) {
        EXPECT_EQ(e.pos().line, 4);
        EXPECT_EQ(e.pos().column, 9);
        EXPECT_NE(e.message().find("Did you mean \"conductor\"?"), std::string::npos) << e.what();
        for (const MaterialType& t : material_types())
            EXPECT_NE(e.message().find(t.name), std::string::npos) << t.name << ": " << e.what();
    }
}

}  // namespace
}  // namespace spt

namespace spt {
namespace {

TEST(LightTypes, TheUnknownTypeMessageListsTheTable) {
    SceneDescription d = sphere_scene(ParamValue::number(1));
    d.root.set("lights", ParamValue::list({ParamValue::dict({{"type", ParamValue::string("spto", {2, 11})}})}));
    try {
        build_scene(d, SpectralResolution{}, kNoFiles);
        FAIL() << "an unknown light type was accepted";
    } catch (const LocatedError& e) {
        EXPECT_EQ(e.what(), std::string("code:2:11: unknown light type \"spto\". Did you mean \"spot\"? Expected "
                                        "\"point\" or \"spot\" (area lights are shapes with \"emission\")"));
    }
}

}  // namespace
}  // namespace spt

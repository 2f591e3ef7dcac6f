// The format-neutral scene description: scenes built in code without any file format, the
// JSON reader keeping every position, errors naming the position a description recorded,
// the read tracking of the parameter bag, and the reader table.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
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
    d.files = {"code"};
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
    EXPECT_EQ(d.files, SourceFiles{"f.json"});
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

/// The error of building a scene of camera, material "m" and the one shape `shape`, in code.
std::string shape_error(ParamValue shape) {
    SceneDescription d = sphere_scene(ParamValue::number(1));
    d.root.set("shapes", ParamValue::list({std::move(shape)}));
    try {
        build_scene(d, SpectralResolution{}, kNoFiles);
    } catch (const LocatedError& e) {
        return std::to_string(e.pos().line) + ":" + std::to_string(e.pos().column) + ": " + e.message();
    }
    return "(no error)";
}

TEST(SceneDescription, NonFiniteNumbersAReaderGivesAreRefusedWhereTheyAre) {
    // JSON has no infinities, but other readers' numbers may overflow: each is refused at its
    // own position.
    const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
    auto mesh = [](ParamValue positions, ParamValue transform) {
        return ParamValue::dict({{"type", ParamValue::string("mesh")}, {"positions", std::move(positions)},
                                 {"indices", ParamValue::numbers({0, 1, 2})}, {"material", ParamValue::string("m")},
                                 {"transform", std::move(transform)}});
    };
    const ParamValue identity = ParamValue::dict({{"scale", ParamValue::number(1)}});
    EXPECT_EQ(shape_error(mesh(ParamValue::numbers({0, 0, 0, 1, 0, 0, 0, 1, 0}), identity)), "(no error)");
    std::vector<ParamValue> p;
    for (int i = 0; i < 9; ++i) p.push_back(ParamValue::number(i == 4 ? nan : (i == 3 || i == 7) ? 1 : 0, {4, 10 + i}));
    EXPECT_EQ(shape_error(mesh(ParamValue::list(std::move(p)), identity)).rfind("4:14: mesh (shape 0) positions has nan; expected finite numbers", 0), 0u);
    const ParamValue matrix = ParamValue::dict({{"matrix", ParamValue::numbers({1, 0, 0, inf, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, {6, 2})}});
    EXPECT_NE(shape_error(mesh(ParamValue::numbers({0, 0, 0, 1, 0, 0, 0, 1, 0}), matrix)).find("6:2: transform matrix has the element inf"),
              std::string::npos);
    ParamValue emitter = ParamValue::dict({{"type", ParamValue::string("sphere")}, {"center", ParamValue::vec3({0, 0, 0})},
                                           {"radius", ParamValue::number(1)},
                                           {"emission", ParamValue::dict({{"type", ParamValue::string("normalized")},
                                                                          {"spectrum", ParamValue::number(1)},
                                                                          {"luminance", ParamValue::number(inf, {8, 3})}})}});
    EXPECT_NE(shape_error(std::move(emitter)).find("8:3: sphere (shape 0) emission (normalized) luminance is inf"), std::string::npos);
}

TEST(SceneDescription, EachPositionNamesItsOwnFile) {
    // A scene from two files, as a reader of a format with includes makes it: the second
    // file's shape is appended with positions naming the second file. An error in either
    // names its own file and line:column; a table that named only the scene file would put
    // the second error in a.json.
    const std::string scene = R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
  "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "emission": 1}]})";
    const std::string bad_radius = "{\"type\": \"sphere\", \"center\": [0, 0, 0],\n \"radius\": -2, \"emission\": 1}";
    const std::string bad_center = "{\"type\": \"sphere\",\n  \"center\": [0, 0], \"radius\": 1, \"emission\": 1}";
    SceneDescription d = read_json_scene(scene, "a.json", "two-files");
    const std::uint32_t b = d.add_file("b.json");
    EXPECT_EQ(b, 1u);
    EXPECT_EQ(d.add_file("a.json"), 0u);  // a file already in the table keeps its index
    ParamValue shapes = *d.root.find("shapes");
    shapes.push(read_json_value(bad_radius, "b.json", b));
    d.root.set("shapes", shapes);
    try {
        build_scene(d, SpectralResolution{}, kNoFiles);
        FAIL() << "a negative radius in the second file was accepted";
    } catch (const LocatedError& e) {
        EXPECT_EQ(e.origin(), "b.json");
        EXPECT_EQ(std::string(e.what()).rfind("b.json:2:12: sphere (shape 1) radius is -2; expected ", 0), 0u) << e.what();
    }
    // The same mistake in the first file names the first file.
    SceneDescription first = read_json_scene(R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
  "shapes": [{"type": "sphere", "center": [0, 0], "radius": 1, "emission": 1}]})", "a.json", "one");
    first.add_file("b.json");
    try {
        build_scene(first, SpectralResolution{}, kNoFiles);
        FAIL() << "a center of two numbers was accepted";
    } catch (const LocatedError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("a.json:2:43: ", 0), 0u) << e.what();
    }
    // And a second-file value in the middle of a first-file entity: the value's file.
    SceneDescription mixed = read_json_scene(scene, "a.json", "mixed");
    const ParamValue second = read_json_value(bad_center, "b.json", mixed.add_file("b.json"));
    ParamValue shape = mixed.root.find("shapes")->items().at(0);
    shape.set("center", *second.find("center"));
    mixed.root.set("shapes", ParamValue::list({shape}));
    try {
        build_scene(mixed, SpectralResolution{}, kNoFiles);
        FAIL() << "a center of two numbers was accepted";
    } catch (const LocatedError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("b.json:2:13: ", 0), 0u) << e.what();
    }
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
    {"fluorescent", R"({"dye": "fluorescein"})"},
};

TEST(MaterialTypes, EveryRowOfTheTableMakesItsOwnBsdf) {
    // A table row whose create function made another type's BSDF, or a type missing from the
    // table, fails here. A fluorescent material is a diffuse BSDF plus its re-radiation part:
    // the pair tells it apart.
    ASSERT_EQ(material_types().size(), kMinimalMaterial.size());
    std::set<std::pair<std::size_t, bool>> made;
    for (const MaterialType& t : material_types()) {
        ASSERT_TRUE(kMinimalMaterial.count(t.name)) << t.name;
        ASSERT_EQ(find_material_type(t.name), &t);
        ParamValue def = read_json_value(kMinimalMaterial.at(t.name), "m.json");
        def.set("type", ParamValue::string(t.name));
        SceneDescription d = sphere_scene(ParamValue::number(1));
        d.root.set("materials", ParamValue::dict({{"m", def}}));
        const Scene s = build_scene(d, SpectralResolution{}, kNoFiles);
        made.insert({s.materials.at(0).bsdf.index(), s.materials.at(0).fluorescence != nullptr});
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

namespace spt {
namespace {

/// A scene around one entity: `section` is "shapes", "lights" or "media" (then the entity is
/// the medium "fog") or "materials" (the material "m"); `entity` is its JSON.
std::string scene_with(const std::string& section, const std::string& entity) {
    std::string s = R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]}, "materials": {"m": )";
    s += section == "materials" ? entity : R"({"kd": 0.5})";
    s += "}, ";
    if (section == "media") s += R"("media": {"fog": )" + entity + "}, ";
    if (section == "lights") s += R"("lights": [)" + entity + "], ";
    s += R"("shapes": [)";
    s += section == "shapes" ? entity : R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"})";
    return s + "]}";
}

std::string load_error(const std::string& text) {
    try {
        load_scene_text(text, "s.json", "s", SpectralResolution{}, kNoFiles);
    } catch (const LocatedError& e) {
        return e.message();
    }
    return "";
}

/// The entity without its top-level member `key` (the text `"key": value, ` removed).
std::string without(const std::string& json, const std::string& key) {
    std::string text = json;
    const std::size_t at = text.find("\"" + key + "\":");
    std::size_t end = at + key.size() + 3;
    int depth = 0;
    for (; end < text.size(); ++end) {
        const char c = text[end];
        if (c == '[' || c == '{') ++depth;
        if (c == ']' || c == '}') {
            if (depth == 0) break;
            --depth;
        }
        if (c == ',' && depth == 0) {
            ++end;
            break;
        }
    }
    text.erase(at, end - at);
    // A trailing ", " left before the closing brace.
    const std::size_t close = text.rfind('}');
    std::size_t last = close;
    while (last > 0 && (text[last - 1] == ' ' || text[last - 1] == ',')) --last;
    return text.substr(0, last) + text.substr(close);
}

struct Entity {
    std::string section, json;
    std::vector<std::string> required;
};

/// Entities with every optional key they accept beside the keys they need, several of which
/// are each other's near misses (edge1 and edge2, sigma_a and sigma_s, position and motion).
const std::vector<Entity> kEntities = {
    {"shapes", R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m", "motion": {"keyframes": [{"time": 0}, {"time": 1, "translate": [0, 0, 1]}]}})", {"center", "radius"}},
    {"shapes", R"({"type": "quad", "origin": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0], "transform": {"scale": 2}, "material": "m"})", {"origin", "edge1", "edge2"}},
    {"shapes", R"({"type": "cylinder", "base": [0, 0, 0], "axis": [0, 1, 0], "radius": 1, "height": 1, "material": "m"})", {"base", "axis", "radius", "height"}},
    {"shapes", R"({"type": "cone", "base": [0, 0, 0], "axis": [0, 1, 0], "radius": 1, "height": 1, "material": "m"})", {"base", "axis", "radius", "height"}},
    {"shapes", R"({"type": "disk", "center": [0, 0, 0], "normal": [0, 1, 0], "radius": 1, "emission": 1})", {"center", "normal", "radius"}},
    {"shapes", R"({"type": "plane", "normal": [0, 1, 0], "point": [0, 0, 0], "material": "m"})", {"normal", "point"}},
    {"shapes", R"({"type": "mesh", "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, 2], "normals": [0, 0, 1, 0, 0, 1, 0, 0, 1], "uv": [0, 0, 1, 0, 0, 1], "transform": {"matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}, "material": "m"})", {"indices"}},
    {"lights", R"({"type": "point", "position": [0, 1, 0], "intensity": 1, "motion": {"keyframes": [{"time": 0}, {"time": 1, "translate": [0, 0, 1]}]}})", {"position", "intensity"}},
    {"lights", R"({"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0], "intensity": 1, "cone_degrees": 30, "falloff_degrees": 20})", {"position", "direction", "intensity", "cone_degrees"}},
    {"media", R"({"type": "homogeneous", "sigma_a": 0.1, "sigma_s": 0.2, "scale": 1, "g": 0.5})", {"sigma_a", "sigma_s"}},
    {"media", R"({"type": "height_fog", "sigma_a": 0.1, "sigma_s": 0.2, "up": [0, 1, 0], "base": 0, "scale_height": 1, "top": 5})", {"sigma_a", "sigma_s", "scale_height"}},
    {"materials", R"({"type": "thin_sheet", "thickness_nm": 400, "ior": 1.33})", {"thickness_nm", "ior"}},
    {"materials", R"({"type": "dielectric", "ior": 1.5, "film": {"thickness_nm": 300, "ior": 1.4}, "roughness": 0.1})", {"ior"}},
    {"materials", R"({"kd": {"type": "gaussian", "center_nm": 550, "width_nm": 40, "scale": 0.5, "offset": 0.1}})", {}},
};

TEST(ReadTracking, EveryKeyAnEntityReadsIsAcceptedOnItsOwn) {
    // Each entity with all its optional keys builds: a key read only on some branch, or a
    // look-up that stopped marking its key, would be called unknown here.
    for (const Entity& e : kEntities) EXPECT_EQ(load_error(scene_with(e.section, e.json)), "") << e.json;
}

TEST(ReadTracking, AMissingKeyIsNotTakenForAMisspellingOfItsNeighbour) {
    // A needed key left out, next to a present key that is its near miss ("sigma_s" for a
    // missing "sigma_a"): the message is that the key is missing, not that its neighbour is
    // unknown. Fails if a create function requires a key before it looks up its near misses.
    for (const Entity& e : kEntities)
        for (const std::string& key : e.required) {
            const std::string message = load_error(scene_with(e.section, without(e.json, key)));
            EXPECT_NE(message.find("has no \"" + key + "\""), std::string::npos) << e.json << " without " << key << ": " << message;
        }
}

TEST(ReadTracking, AnUnreadKeyIsUnknownAndAMisspeltNeededKeyIsNamed) {
    // An extra key on each entity is refused at its own position, naming the entity.
    for (const Entity& e : kEntities) {
        std::string json = e.json;
        json.insert(json.rfind('}'), ", \"bogus_key\": 1");
        const std::string message = load_error(scene_with(e.section, json));
        EXPECT_EQ(message.rfind("unknown key \"bogus_key\" in ", 0), 0u) << json << ": " << message;
    }
    // A key read on one branch only (a texture binding's "scale" is an emission's) is
    // unknown on the others.
    EXPECT_NE(load_error(R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
        "textures": {"t": {"type": "checkerboard", "even": 0.2, "odd": 0.8}},
        "materials": {"m": {"kd": {"texture": "t", "scale": 2}}},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}]})")
                  .find("unknown key \"scale\" in material \"m\" kd. Expected one of: texture"),
              std::string::npos);
    // A misspelt key the entity needs: reported as the unknown key, suggesting the needed one.
    EXPECT_EQ(load_error(scene_with("shapes", R"({"type": "disk", "center": [0, 0, 0], "normal": [0, 1, 0], "radius": 1, "emision": 1})")),
              "unknown key \"emision\" in disk (shape 0). Did you mean \"emission\"? Expected \"material\" or \"emission\", "
              "which disk (shape 0) needs");
    // A key probed only to refuse it stays unknown to the others' suggestions: "anisotropy"
    // is refused with its own message, not accepted.
    EXPECT_NE(load_error(scene_with("materials", R"({"type": "dielectric", "ior": 1.5, "anisotropy": 0.5})"))
                  .find("anisotropy: anisotropic roughness is given by"), std::string::npos);
}

}  // namespace
}  // namespace spt

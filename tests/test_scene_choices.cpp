// What a scene file says about itself beyond geometry: the integrator it asks for, its
// one-line summary, and the warnings for refracting meshes that do not bound a volume
// (mesh_closure: closedness by directed edges, orientation by the signed volume).
#include <gtest/gtest.h>

#include <string>

#include "geometry/mesh_closure.h"
#include "scene/builtin_scenes.h"
#include "scene/scene_loader.h"

namespace spt {
namespace {

using Faces = std::vector<std::array<std::uint32_t, 3>>;

/// The unit cube [0, 1]³ as 12 triangles, counter-clockwise seen from outside (outward normals).
const std::vector<Vec3> kCubeVertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                         {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
const Faces kCubeFaces = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                          {2, 3, 7}, {2, 7, 6}, {1, 2, 6}, {1, 6, 5}, {0, 4, 7}, {0, 7, 3}};

Faces reversed(Faces faces) {
    for (auto& f : faces) std::swap(f[1], f[2]);
    return faces;
}

TEST(MeshClosure, ClosedCubeHasItsVolumeWithTheSignOfItsOrientation) {
    const MeshClosure out = mesh_closure(kCubeVertices, kCubeFaces);
    EXPECT_TRUE(out.closed);
    EXPECT_NEAR(out.signed_volume, 1.0, 1e-12);
    const MeshClosure in = mesh_closure(kCubeVertices, reversed(kCubeFaces));
    EXPECT_TRUE(in.closed);
    EXPECT_NEAR(in.signed_volume, -1.0, 1e-12);
}

TEST(MeshClosure, MissingFaceOrOneFlippedFaceIsNotClosed) {
    Faces open = kCubeFaces;
    open.pop_back();
    EXPECT_FALSE(mesh_closure(kCubeVertices, open).closed);
    Faces flipped = kCubeFaces;
    std::swap(flipped[3][1], flipped[3][2]);  // inconsistent orientation: an edge traversed twice one way
    EXPECT_FALSE(mesh_closure(kCubeVertices, flipped).closed);
    EXPECT_FALSE(mesh_closure({}, {}).closed);
}

TEST(MeshClosure, VerticesRepeatedPerFaceAreMatchedByPosition) {
    std::vector<Vec3> soup;
    Faces faces;
    for (const auto& f : kCubeFaces) {
        const std::uint32_t base = static_cast<std::uint32_t>(soup.size());
        for (std::uint32_t k : f) soup.push_back(kCubeVertices[k]);
        faces.push_back({base, base + 1, base + 2});
    }
    const MeshClosure c = mesh_closure(soup, faces);
    EXPECT_TRUE(c.closed);
    EXPECT_NEAR(c.signed_volume, 1.0, 1e-12);
    // A face with a repeated vertex (zero area) does not open or close anything.
    faces.push_back({0, 0, 1});
    EXPECT_TRUE(mesh_closure(soup, faces).closed);
}

TEST(MeshClosure, VolumeIsExactFarFromTheOrigin) {
    std::vector<Vec3> far = kCubeVertices;
    for (Vec3& p : far) p = p + Vec3(1e4f, -2e4f, 3e4f);
    EXPECT_NEAR(mesh_closure(far, kCubeFaces).signed_volume, 1.0, 1e-9);
}

// ---------------------------------------------------------------- the loader

std::string ply_of(const std::vector<Vec3>& v, const Faces& f) {
    std::string s = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(v.size()) +
                    "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                    std::to_string(f.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const Vec3& p : v) s += std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
    for (const auto& t : f) s += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
    return s;
}

/// A scene with one mesh (the given PLY) of the given material and `extra` top-level keys.
Scene load_with_mesh(const std::string& ply, const std::string& material, const std::string& extra = "") {
    const RelativeFileReader reader = [&](const std::string& rel, std::string& contents, std::string& display,
                                          std::string&) {
        display = "meshes/" + rel;
        contents = ply;
        return true;
    };
    const std::string text = "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]}," + extra +
                             "\"materials\": {\"glass\": {\"kt\": 1, \"ior\": 1.5}, \"plastic\": {\"kd\": 0.5, "
                             "\"ks\": 0.1}, \"mirror\": {\"ks\": 1}},"
                             "\"shapes\": [{\"type\": \"mesh\", \"file\": \"m.ply\", \"material\": \"" +
                             material + "\"}]}";
    return load_scene_text(text, "s.json", "s", SpectralResolution{}, reader);
}

TEST(SceneWarnings, RefractingMeshThatIsOpenOrInwardIsNamed) {
    EXPECT_TRUE(load_with_mesh(ply_of(kCubeVertices, kCubeFaces), "glass").warnings.empty());

    Faces open = kCubeFaces;
    open.resize(10);
    const Scene o = load_with_mesh(ply_of(kCubeVertices, open), "glass");
    ASSERT_EQ(o.warnings.size(), 1u);
    EXPECT_NE(o.warnings[0].find("mesh (shape 0)"), std::string::npos) << o.warnings[0];
    EXPECT_NE(o.warnings[0].find("meshes/m.ply"), std::string::npos) << o.warnings[0];
    EXPECT_NE(o.warnings[0].find("\"glass\""), std::string::npos) << o.warnings[0];
    EXPECT_NE(o.warnings[0].find("not closed"), std::string::npos) << o.warnings[0];

    const Scene in = load_with_mesh(ply_of(kCubeVertices, reversed(kCubeFaces)), "glass");
    ASSERT_EQ(in.warnings.size(), 1u);
    EXPECT_NE(in.warnings[0].find("inward"), std::string::npos) << in.warnings[0];
}

TEST(SceneWarnings, MirroredTransformTurnsAnOutwardMeshInward) {
    // A mirroring transform (negative scale) reverses the orientation the file gives.
    const RelativeFileReader reader = [&](const std::string&, std::string& contents, std::string& display,
                                          std::string&) {
        display = "m.ply";
        contents = ply_of(kCubeVertices, kCubeFaces);
        return true;
    };
    const std::string text =
        "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]}, \"materials\": {\"glass\": {\"kt\": 1, \"ior\": 1.5}},"
        "\"shapes\": [{\"type\": \"mesh\", \"file\": \"m.ply\", \"material\": \"glass\","
        " \"transform\": {\"scale\": [-1, 1, 1]}}]}";
    const Scene s = load_scene_text(text, "s.json", "s", SpectralResolution{}, reader);
    ASSERT_EQ(s.warnings.size(), 1u);
    EXPECT_NE(s.warnings[0].find("inward"), std::string::npos) << s.warnings[0];
}

TEST(SceneWarnings, OpenMeshesThatDoNotRefractAreFine) {
    Faces open = kCubeFaces;
    open.resize(10);
    EXPECT_TRUE(load_with_mesh(ply_of(kCubeVertices, open), "plastic").warnings.empty());
    EXPECT_TRUE(load_with_mesh(ply_of(kCubeVertices, reversed(kCubeFaces)), "mirror").warnings.empty());
}

TEST(SceneWarnings, BuiltinScenesHaveNone) {
    for (const std::string& name : builtin_scene_names())
        EXPECT_TRUE(load_builtin_scene(name, SpectralResolution{})->warnings.empty()) << name;
}

// ---------------------------------------------------------------- integrator and summary

TEST(ScenePresets, IntegratorAsNameOrObject) {
    const std::string cube = ply_of(kCubeVertices, kCubeFaces);
    EXPECT_FALSE(load_with_mesh(cube, "plastic").integrator.kind.has_value());
    const Scene byname = load_with_mesh(cube, "plastic", "\"integrator\": \"BDPT\",");
    EXPECT_EQ(byname.integrator.kind, IntegratorKind::bdpt);
    EXPECT_FALSE(byname.integrator.max_depth.has_value());
    const Scene vcm = load_with_mesh(cube, "plastic",
                                     "\"integrator\": {\"type\": \"vcm\", \"max_depth\": 7, \"merge_radius\": 0.25},");
    EXPECT_EQ(vcm.integrator.kind, IntegratorKind::vcm);
    EXPECT_EQ(vcm.integrator.max_depth, 7);
    EXPECT_EQ(vcm.integrator.merge_radius, 0.25);
    const Scene path = load_with_mesh(cube, "plastic",
                                      "\"integrator\": {\"type\": \"path\", \"light_sampling\": \"bsdf\"},");
    EXPECT_EQ(path.integrator.light_sampling, LightSampling::bsdf);
}

TEST(ScenePresets, SummaryIsTheKeyOrTheFirstSentenceOfTheDescription) {
    const std::string cube = ply_of(kCubeVertices, kCubeFaces);
    EXPECT_EQ(load_with_mesh(cube, "plastic").summary, "");
    EXPECT_EQ(load_with_mesh(cube, "plastic", "\"description\": \"A box. Lit from above.\",").summary, "A box.");
    EXPECT_EQ(load_with_mesh(cube, "plastic", "\"description\": \"A box\",").summary, "A box");
    EXPECT_EQ(load_with_mesh(cube, "plastic", "\"summary\": \"Short\", \"description\": \"Long. Longer.\",").summary,
              "Short");
    // Every built-in scene has one, short enough for one line of --list-scenes.
    for (const std::string& name : builtin_scene_names()) {
        const std::string summary = load_builtin_scene(name, SpectralResolution{})->summary;
        EXPECT_FALSE(summary.empty()) << name;
        EXPECT_LE(summary.size(), 80u) << name;
    }
}

}  // namespace
}  // namespace spt

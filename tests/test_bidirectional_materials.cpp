// bdpt and vcm against the path tracer on every BSDF type of src/model/bsdfs/ (smooth and
// rough, with and without thin films): a sphere of the material on a diffuse floor under a
// small area light, with a dim environment. The path tracer is the reference: its
// next-event estimation and BSDF sampling do not share code with the bidirectional MIS
// weights (connections, merges), where a density taken at the wrong directions biases the
// image while every single strategy stays unbiased.
//
// Statistics: the bdpt check is test_scenes.h's (every pixel within 5σ, image means within
// 5 standard errors). vcm: means over the pixels that see the sphere, the vcm error from the
// spread of per-pass means (vcm_passes.h: pixels of a pass are correlated), the path
// tracer's from its pixels (independent), |difference| ≤ 5·√(σ_path² + σ_vcm²). The merge
// radius is 0.05, a tenth of the sphere's radius: large enough that merges carry a good
// share of the light (with wrong weights they then bias visibly), small enough that the
// kernel's bias on a mean over the sphere (curvature: of order (r/R)² = 1 % of the merged
// part) stays below the test's resolution.
//
// Planted bug (the state before this test): merge() weighing with the merge point's BSDF
// density taken from the normal instead of the other side's direction (exact only for a
// Lambertian lobe) and skipping photons on the far side of transmitting surfaces. On this
// scene with rough SF11 glass, 24x24, 256 passes at r = 0.05, vcm gave 0.2196 for the
// path tracer's 0.1658 (G over the sphere, +32 %), as on the built-in frosted-glass scene.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "model/camera.h"
#include "scene/builtin_scenes.h"
#include "scene/scene_loader.h"
#include "test_scenes.h"
#include "vcm_passes.h"

namespace spt {
namespace {

using test::compare;
using test::Comparison;
using test::describe;
using test::ImageMean;
using test::render_film;
using test::small_settings;

constexpr double kZ = 5.0;

/// The test scene with the sphere's material `material` (a JSON object).
std::string sphere_scene(const std::string& material) {
    return R"({
  "camera": {"position": [0, 1.1, 2.4], "look_at": [0, 0.45, 0], "vfov_degrees": 30},
  "background": 0.05,
  "materials": {"floor": {"kd": 0.7}, "object": )" +
           material + R"(},
  "shapes": [
    {"type": "plane", "normal": [0, 1, 0], "point": [0, 0, 0], "material": "floor"},
    {"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5, "material": "object"},
    {"type": "quad", "origin": [-0.3, 2.2, -0.6], "edge1": [0.6, 0, 0], "edge2": [0, 0, 0.6],
     "emission": {"type": "illuminant", "name": "D65", "scale": 20}}
  ]
})";
}

/// Pixels whose centre sees material `material` first.
std::vector<char> material_mask(const Scene& scene, int width, int height, int material) {
    const Camera camera(scene.camera, width, height);
    std::vector<char> mask(std::size_t(width) * height, 0);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            if (const auto hit = scene.intersect(camera.generate_ray(x + 0.5f, y + 0.5f)))
                mask[std::size_t(y) * width + x] = hit->material == material;
    return mask;
}

struct MaterialCase {
    const char* name;
    const char* json;
};

const MaterialCase kCases[] = {
    {"diffuse", R"({"kd": 0.6})"},
    {"lobes kd + ks", R"({"kd": 0.4, "ks": 0.3})"},
    {"lobes glass", R"({"kt": 1, "ior": 1.5})"},
    {"conductor smooth", R"({"type": "conductor", "metal": "Cu"})"},
    {"conductor rough", R"({"type": "conductor", "metal": "Au", "roughness": 0.2})"},
    {"conductor anisotropic", R"({"type": "conductor", "metal": "Al", "roughness_u": 0.05, "roughness_v": 0.4})"},
    {"conductor rough + film",
     R"({"type": "conductor", "metal": "Al", "roughness": 0.1, "film": {"thickness_nm": 300, "ior": 1.46}})"},
    {"dielectric rough SF11", R"({"type": "dielectric", "ior": {"type": "glass", "name": "SF11"}, "roughness": 0.15})"},
    {"dielectric rough + film",
     R"({"type": "dielectric", "ior": 1.5, "roughness": 0.3, "film": {"thickness_nm": 400, "ior": 1.38}})"},
    {"dielectric smooth", R"({"type": "dielectric", "ior": 1.5})"},
    {"plastic rough", R"({"type": "plastic", "kd": 0.5, "roughness": 0.2})"},
    {"plastic smooth", R"({"type": "plastic", "kd": 0.5})"},
    {"thin sheet", R"({"type": "thin_sheet", "thickness_nm": 380, "ior": 1.33})"},
};

/// bdpt against the path tracer (test_scenes.h), then vcm (merge radius `radius`) against
/// the same path film: the mean over the pixels that see material `material` (−1: all).
void expect_bidirectional_match(const Scene& scene, const std::string& name, int material, float radius,
                                std::uint64_t seed) {
    const auto path = test::expect_bdpt_matches_path(scene, seed);
    RenderSettings rs = small_settings(path->width(), path->height(), 256, seed + 2);
    rs.integrator.kind = IntegratorKind::vcm;
    rs.integrator.merge_radius = radius;
    const test::PassImages vcm = test::render_passes(scene, rs);
    EXPECT_EQ(vcm.film->rejected_samples(), 0u);
    const std::vector<char> mask = material < 0 ? std::vector<char>(std::size_t(rs.width) * rs.height, 1)
                                                : material_mask(scene, rs.width, rs.height, material);
    const auto in_region = [&](int x, int y) { return mask[std::size_t(y) * rs.width + x] != 0; };
    const ImageMean a = test::region_mean_y(*path, in_region), b = vcm.region(in_region);
    const double sigma = std::hypot(a.standard_error, b.standard_error);
    std::printf("[bidirectional] %s: mean path %.5f ± %.5f, vcm %.5f ± %.5f (z = %.2f)\n", name.c_str(), a.mean,
                a.standard_error, b.mean, b.standard_error, (b.mean - a.mean) / sigma);
    EXPECT_NEAR(a.mean, b.mean, kZ * sigma) << name;
}

class BidirectionalMaterials : public ::testing::TestWithParam<MaterialCase> {};

TEST_P(BidirectionalMaterials, BdptAndVcmAgreeWithThePathTracer) {
    const MaterialCase& c = GetParam();
    const Scene scene = test::load_exact_scene(sphere_scene(c.json), "sphere");
    expect_bidirectional_match(scene, c.name, 1, 0.05f, 61);  // material 1: "object"
}

INSTANTIATE_TEST_SUITE_P(EveryBsdfType, BidirectionalMaterials, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<MaterialCase>& p) {
                             std::string name;
                             for (const char ch : std::string(p.param.name))
                                 if (std::isalnum(static_cast<unsigned char>(ch))) name += ch;
                             return name;
                         });

// ---- Textures: the BSDF of each vertex and the emission of each light point read as the
// path tracer reads them ----

/// The built-in scene: image, checkerboard and gradient kd, an emitting picture (a textured
/// quad light that starts light subpaths). Planted bugs: the material's envelope instead of
/// its texture at a vertex (bsdf_at returning Material::bsdf), or a light origin's radiance
/// without its texture (LightSampler::sample): both brighten the image far beyond 5σ.
TEST(BidirectionalTextures, BuiltinTexturedSceneAgreesWithThePathTracer) {
    std::optional<Scene> scene = load_builtin_scene("textured", {});
    ASSERT_TRUE(scene.has_value());
    expect_bidirectional_match(*scene, "textured", -1, 0.01f, 71);
}

/// The only lights are textured: a quad (checkerboard, 20 and 1) above the floor and a sphere
/// (checkerboard over its (u, v)), over a floor whose kd is a checkerboard too; every light
/// subpath starts at a textured point and every s = 0 path ends on one.
TEST(BidirectionalTextures, TexturedEmittersAgreeWithThePathTracer) {
    const Scene scene = test::load_exact_scene(R"({
  "camera": {"position": [0, 1.6, 2.6], "look_at": [0, 0.4, 0], "vfov_degrees": 45},
  "textures": {
    "glow": {"type": "checkerboard", "even": 1, "odd": 0.05, "uv_scale": [3, 3]},
    "ball": {"type": "checkerboard", "even": [0.9, 0.6, 0.3], "odd": 0.1, "uv_scale": [8, 4]},
    "floor": {"type": "checkerboard", "even": 0.8, "odd": 0.2, "uv_scale": [6, 6]}
  },
  "materials": {"floor": {"kd": {"texture": "floor"}}},
  "shapes": [
    {"type": "quad", "origin": [-2, 0, 2], "edge1": [4, 0, 0], "edge2": [0, 0, -4], "material": "floor"},
    {"type": "quad", "origin": [-0.5, 1.5, -0.8], "edge1": [0, 0, 1], "edge2": [1, 0, 0],
     "emission": {"texture": "glow", "scale": 20}},
    {"type": "sphere", "center": [0.6, 0.35, 0.2], "radius": 0.35, "emission": {"texture": "ball", "scale": 6}}
  ]
})", "glow");
    ASSERT_TRUE(scene.effects.textures);
    expect_bidirectional_match(scene, "textured emitters", -1, 0.01f, 81);
}

}  // namespace
}  // namespace spt

// One-sided area lights ("two_sided": false on an emitting shape) rendered:
//   - seen from the front, where nothing can reach the back, a one-sided quad light renders
//     bit for bit as the two-sided one (constant and textured emission, path tracing);
//   - seen from behind it is black with every integrator, and the two-sided one is not;
//   - a ceiling behind a one-sided light gets no direct light from it: bdpt (whose light
//     subpaths leave by the front only and whose connections from a light origin see only
//     its front) agrees with path tracing there, and the two-sided light lights the ceiling
//     visibly more (the scene can tell the two apart);
//   - the key's errors: not a boolean, on a shape that does not emit, false on a sphere.
#include <gtest/gtest.h>

#include <string>

#include "test_scenes.h"

namespace spt {
namespace {

/// A quad light facing down (edge1 × edge2 = −y) at height 1 over a white floor; `extra`
/// adds shapes, `sides` is "" (the default, two-sided) or a "two_sided" member.
std::string scene_text(const std::string& camera, const std::string& emission, const std::string& sides,
                       const std::string& extra = "") {
    return R"({"camera": )" + camera + R"(,
      "textures": {"c": {"type": "checkerboard", "even": 1, "odd": 4, "uv_scale": [4, 4]}},
      "materials": {"white": {"kd": 0.5}},
      "shapes": [{"type": "quad", "origin": [-3, 0, 3], "edge1": [6, 0, 0], "edge2": [0, 0, -6], "material": "white"},
        {"type": "quad", "origin": [-0.5, 1, -0.5], "edge1": [1, 0, 0], "edge2": [0, 0, 1], "emission": )" +
           emission + sides + "}" + extra + "]}";
}

const std::string kFromBelow = R"({"position": [0, 0.4, 2.5], "look_at": [0, 0.6, 0]})";
const std::string kFromAbove = R"({"position": [0, 2, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "vfov_degrees": 40})";
const std::string kOneSided = R"(, "two_sided": false)";

TEST(OneSidedLights, FrontRendersAsTheTwoSidedLightBitForBit) {
    for (const std::string& emission : {std::string("2"), std::string(R"({"texture": "c"})")}) {
        const Scene two = test::load_exact_scene(scene_text(kFromBelow, emission, ""), "two");
        const Scene one = test::load_exact_scene(scene_text(kFromBelow, emission, kOneSided), "one");
        const auto a = test::render_film(two, test::small_settings(24, 24, 16, 3));
        const auto b = test::render_film(one, test::small_settings(24, 24, 16, 3));
        EXPECT_GT(test::image_mean_y(*a).mean, 0.0) << emission;
        EXPECT_EQ(test::count_differences(*a, *b), 0u) << emission;
    }
}

TEST(OneSidedLights, BackIsBlackWithEveryIntegrator) {
    // From above, the light's back fills the image (its black surface reflects nothing).
    const Scene two = test::load_exact_scene(scene_text(kFromAbove, "2", ""), "two");
    const Scene one = test::load_exact_scene(scene_text(kFromAbove, "2", kOneSided), "one");
    for (IntegratorKind kind : {IntegratorKind::path, IntegratorKind::bdpt, IntegratorKind::vcm}) {
        RenderSettings rs = test::small_settings(16, 16, 8, 5);
        rs.integrator.kind = kind;
        const auto lit = test::render_film(two, rs);
        const auto dark = test::render_film(one, rs);
        int black = 0, bright = 0;
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) {
                black += dark->pixel_xyz(x, y).y == 0.0;
                bright += lit->pixel_xyz(x, y).y > 0.5;
            }
        EXPECT_EQ(black, 256) << static_cast<int>(kind);
        EXPECT_EQ(bright, 256) << static_cast<int>(kind);
    }
}

TEST(OneSidedLights, CeilingBehindTheLightGetsNoDirectLightInBdptEither) {
    const std::string camera = R"({"position": [0, 0.75, 3], "look_at": [0, 0.75, 0], "vfov_degrees": 60})";
    const std::string ceiling =
        R"(, {"type": "quad", "origin": [-3, 1.5, 3], "edge1": [6, 0, 0], "edge2": [0, 0, -6], "material": "white"})";
    const Scene one = test::load_exact_scene(scene_text(camera, "2", kOneSided, ceiling), "one");
    const auto path = test::expect_bdpt_matches_path(one, 7);
    // The top rows see the ceiling: the two-sided light's back lights it directly.
    const Scene two = test::load_exact_scene(scene_text(camera, "2", "", ceiling), "two");
    const auto lit = test::render_film(two, test::small_settings(24, 24, 1024, 9));
    auto top = [](int, int y) { return y < 4; };
    const test::ImageMean dark_top = test::region_mean_y(*path, top), lit_top = test::region_mean_y(*lit, top);
    EXPECT_GT(lit_top.mean, 1.5 * dark_top.mean);
    EXPECT_GT(lit_top.mean - dark_top.mean, 10 * std::hypot(lit_top.standard_error, dark_top.standard_error));
}

TEST(OneSidedLights, KeyErrors) {
    const std::string base = R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]}, "materials": {"white": {"kd": 0.5}},
      "shapes": [)";
    EXPECT_NE(test::scene_error(base + R"({"type": "quad", "origin": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0],
        "emission": 1, "two_sided": 0}]})", "e")
                  .find("e.json:3:37: quad (shape 0) two_sided is a number; expected true or false"),
              std::string::npos)
        << test::scene_error(base + R"({"type": "quad", "origin": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0],
        "emission": 1, "two_sided": 0}]})", "e");
    EXPECT_NE(test::scene_error(base + R"({"type": "disk", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": 1,
        "material": "white", "two_sided": false}]})", "e")
                  .find("disk (shape 0) has \"two_sided\" but emits nothing; expected it only on an emitting shape"),
              std::string::npos);
    EXPECT_NE(test::scene_error(base + R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "emission": 1,
        "two_sided": false}]})", "e")
                  .find("sphere (shape 0) always emits from both sides"),
              std::string::npos);
    // true is what a sphere does: accepted.
    EXPECT_EQ(test::scene_error(base + R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "emission": 1,
        "two_sided": true}]})", "e"),
              "(no error)");
}

}  // namespace
}  // namespace spt

// Bidirectional path tracing with participating media and spot lights (bdpt_media.h): bdpt
// against the path tracer on small scenes where both converge, the analytic transmittance of
// an absorbing medium around the camera (every strategy, light tracing included, must apply
// it), finite pixels, bit-identity over thread counts, and which media bdpt and vcm refuse.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "cli/integrator_choice.h"
#include "test_scenes.h"

namespace spt {
namespace {

/// A closed box [−1, 1]³ of white walls (both sides in `inside`), lit by a small quad under
/// its ceiling, seen from inside; `extra` adds shapes, `media` defines the media.
std::string box_scene(const std::string& media, const std::string& camera_medium, const std::string& extra) {
    const std::string sides = R"(, "interior": ")" + camera_medium + R"(", "exterior": ")" + camera_medium + "\"";
    auto quad = [&](const char* o, const char* e1, const char* e2, const char* what) {
        return std::string(R"({"type": "quad", "origin": )") + o + R"(, "edge1": )" + e1 + R"(, "edge2": )" + e2 +
               ", " + what + sides + "},\n";
    };
    return R"({"camera": {"position": [0, 0, 0.9], "look_at": [0, -0.1, -1], "vfov_degrees": 70},
        "background": 0, "materials": {"white": {"kd": 0.7}, "red": {"kd": [0.7, 0.1, 0.1]}},
        "media": )" + media + R"(, "medium": ")" + camera_medium + R"(",
        "shapes": [)" +
           quad("[-1, -1, -1]", "[2, 0, 0]", "[0, 0, 2]", R"("material": "white")") +
           quad("[-1, 1, -1]", "[2, 0, 0]", "[0, 0, 2]", R"("material": "white")") +
           quad("[-1, -1, -1]", "[0, 2, 0]", "[0, 0, 2]", R"("material": "red")") +
           quad("[1, -1, -1]", "[0, 2, 0]", "[0, 0, 2]", R"("material": "white")") +
           quad("[-1, -1, -1]", "[2, 0, 0]", "[0, 2, 0]", R"("material": "white")") +
           quad("[-1, -1, 1]", "[2, 0, 0]", "[0, 2, 0]", R"("material": "white")") +
           quad("[-0.3, 0.95, -0.3]", "[0.6, 0, 0]", "[0, 0, 0.6]", R"("emission": 6)") + extra + "]}";
}

Scene bdpt_scene(const std::string& json, const std::string& name) {
    Scene scene = test::load_exact_scene(json, name);
    EXPECT_TRUE(scene.effects.media) << name;
    return scene;
}

/// Fog filling a closed box lit by an area light (the camera and every wall in it).
Scene fog_box() {
    return bdpt_scene(box_scene(R"({"fog": {"type": "homogeneous", "sigma_a": 0.1, "sigma_s": 0.6, "g": 0.4}})",
                                "fog", R"({"type": "sphere", "center": [0.3, -0.6, -0.4], "radius": 0.3,
                                            "material": "white", "interior": "fog", "exterior": "fog"})"),
                      "fog box");
}

TEST(BdptMedia, FogInABoxMatchesThePathTracer) {
    const auto film = test::expect_bdpt_matches_path(fog_box(), 11);
    EXPECT_GT(test::image_mean_y(*film).mean, 0.0);
}

TEST(BdptMedia, ScatteringSlabMatchesThePathTracer) {
    // A slab of dense forward-scattering medium bounded by a box without a surface, in a
    // vacuum box: light crosses it many times before it reaches the camera.
    std::string slab;
    const char* faces[6][3] = {{"[-0.8, -0.3, -0.8]", "[1.6, 0, 0]", "[0, 0, 1.2]"},
                               {"[-0.8, 0.1, -0.8]", "[1.6, 0, 0]", "[0, 0, 1.2]"},
                               {"[-0.8, -0.3, -0.8]", "[0, 0.4, 0]", "[0, 0, 1.2]"},
                               {"[0.8, -0.3, -0.8]", "[0, 0.4, 0]", "[0, 0, 1.2]"},
                               {"[-0.8, -0.3, -0.8]", "[1.6, 0, 0]", "[0, 0.4, 0]"},
                               {"[-0.8, -0.3, 0.4]", "[1.6, 0, 0]", "[0, 0.4, 0]"}};
    for (const auto& f : faces)
        slab += std::string(R"(, {"type": "quad", "origin": )") + f[0] + R"(, "edge1": )" + f[1] + R"(, "edge2": )" +
                f[2] + R"(, "interior": "slab", "exterior": "vacuum"})";
    // The box's own walls: vacuum on both sides (the camera's medium).
    const std::string json = box_scene(
        R"({"slab": {"type": "homogeneous", "sigma_a": 0.3, "sigma_s": [4, 2.5, 1.5], "g": 0.6}})", "vacuum",
        slab.substr(2));
    Scene scene = bdpt_scene(json, "scattering slab");
    test::expect_bdpt_matches_path(scene, 21);
}

TEST(BdptMedia, GlassOfAbsorbingLiquidMatchesThePathTracer) {
    // A glass sphere filled with a strongly chromatic absorber (σt differs between the
    // wavelengths: bdpt keeps only the hero on such paths) on a diffuse floor.
    const std::string json = box_scene(
        R"({"liquid": {"type": "homogeneous", "sigma_a": {"type": "table", "points": [[380, 4], [780, 0.2]]},
                        "sigma_s": 0}})",
        "vacuum",
        R"({"type": "sphere", "center": [0, -0.55, -0.3], "radius": 0.45, "material": "glass",
            "interior": "liquid", "exterior": "vacuum"})");
    std::string with_glass = json;
    with_glass.replace(with_glass.find(R"("red": )"), 0, R"("glass": {"kt": 1, "ior": 1.33}, )");
    Scene scene = bdpt_scene(with_glass, "liquid glass");
    test::expect_bdpt_matches_path(scene, 31);
}

/// A spot light in haze over a diffuse floor, the beam seen from the side.
Scene spot_in_haze() {
    return bdpt_scene(R"({"camera": {"position": [0, 0.8, 3], "look_at": [0, 0.6, 0], "vfov_degrees": 50},
        "materials": {"floor": {"kd": 0.6}},
        "media": {"haze": {"type": "homogeneous", "sigma_a": 0.05, "sigma_s": 0.4, "g": 0.5}}, "medium": "haze",
        "shapes": [{"type": "plane", "normal": [0, 1, 0], "point": [0, 0, 0], "material": "floor",
                    "interior": "haze", "exterior": "haze"}],
        "lights": [{"type": "spot", "position": [0, 1.6, 0], "direction": [0.3, -1, 0], "intensity": 8,
                    "cone_degrees": 25, "falloff_degrees": 15}]})",
                      "spot in haze");
}

TEST(BdptMedia, SpotLightThroughHazeMatchesThePathTracer) {
    const auto film = test::expect_bdpt_matches_path(spot_in_haze(), 41);
    EXPECT_GT(test::image_mean_y(*film).mean, 0.0);
}

TEST(BdptSpotLight, ConeAndFalloffMatchThePathTracerWithoutMedia) {
    // A spot over a lit plane seen from above, its whole cone and the fading ring in view:
    // the connections to the spot (s = 1) apply the falloff, light paths leave within the cone.
    Scene scene = test::lit_plane_scene(0.5, 2.0, 1.f, 0.f, 0.f, 0.f, 2.f, 80.f);
    SpotLight spot;
    spot.position = {0.f, 1.f, 0.f};
    spot.direction = normalize(Vec3{0.2f, -1.f, 0.f});
    spot.intensity = test::constant_spectrum(2.0);
    spot.cos_cone = std::cos(35.f * kPi / 180.f);
    spot.cos_falloff = std::cos(15.f * kPi / 180.f);
    scene.lights.clear();
    scene.lights.emplace_back(spot);
    scene.finalize();
    const auto film = test::expect_bdpt_matches_path(scene, 51);
    // The film shows the lit cone and black outside it.
    EXPECT_GT(film->pixel_xyz(12, 12).y, 0.0);
    EXPECT_EQ(film->pixel_xyz(0, 0).y, 0.0);
}

TEST(BdptMedia, AbsorbingMediumAroundTheCameraScalesEveryStrategyByItsTransmittance) {
    // The camera at the centre of a sphere without a surface (radius R) filled with a pure
    // absorber σa, looking at a plane lit by a point light outside it: every path to the
    // camera crosses exactly R of the medium, so the image is exp(−σa·R) times the one in
    // vacuum. A wide view, so that light tracing (t = 1, splats through the medium) carries
    // much of the weight: a strategy that forgot the transmittance would be off by a share of
    // 1 − e⁻¹ of its weight.
    const std::string common = R"("camera": {"position": [0, 1, 0], "look_at": [0, 0, 0], "up": [0, 0, -1],
            "vfov_degrees": 90},
        "materials": {"floor": {"kd": 0.6}},
        "lights": [{"type": "point", "position": [0.3, 0.4, 0], "intensity": 2}],)";
    const std::string floor = R"({"type": "plane", "normal": [0, 1, 0], "point": [0, 0, 0], "material": "floor")";
    const Scene vacuum = test::load_exact_scene("{" + common + R"("shapes": [)" + floor + "}]}", "vacuum");
    const float radius = 0.5f, sigma_a = 2.f;
    const Scene absorbing = test::load_exact_scene(
        "{" + common + R"("media": {"ink": {"type": "homogeneous", "sigma_a": 2, "sigma_s": 0}}, "medium": "ink",
        "shapes": [)" + floor + R"(, "interior": "vacuum", "exterior": "vacuum"},
                   {"type": "sphere", "center": [0, 1, 0], "radius": 0.5, "interior": "ink", "exterior": "vacuum"}]})",
        "absorbing");
    RenderSettings rs = test::small_settings(16, 16, 256, 61);
    rs.integrator.kind = IntegratorKind::bdpt;
    const auto a = test::render_film(absorbing, rs);
    rs.seed = 62;
    const auto v = test::render_film(vacuum, rs);
    EXPECT_EQ(test::count_bad_pixels(*a), 0);
    const double T = std::exp(-static_cast<double>(sigma_a * radius));
    const test::ImageMean ma = test::image_mean_y(*a), mv = test::image_mean_y(*v);
    EXPECT_NEAR(ma.mean, T * mv.mean, 5.0 * std::hypot(ma.standard_error, T * mv.standard_error))
        << "with the medium " << ma.mean << ", in vacuum " << mv.mean << " × T = " << T * mv.mean;
    EXPECT_GT(ma.mean, 0.0);
}

TEST(BdptMedia, ThreadCountDoesNotChangeTheFilmAndEveryPixelIsFinite) {
    const Scene scene = spot_in_haze();
    RenderSettings rs = test::small_settings(16, 16, 8, 71, 1);
    rs.integrator.kind = IntegratorKind::bdpt;
    const auto one = test::render_film(scene, rs);
    rs.threads = 3;
    const auto many = test::render_film(scene, rs);
    EXPECT_EQ(test::count_bad_pixels(*one), 0);
    ASSERT_EQ(one->xyz_sums().size(), many->xyz_sums().size());
    EXPECT_EQ(std::memcmp(one->xyz_sums().data(), many->xyz_sums().data(), one->xyz_sums().size() * sizeof(double)),
              0);
    EXPECT_GT(test::image_mean_y(*one).mean, 0.0);
}

TEST(BdptMedia, BdptRendersHomogeneousMediaAndRefusesHeterogeneousOnes) {
    Options bdpt, vcm;
    bdpt.integrator = IntegratorKind::bdpt;
    vcm.integrator = IntegratorKind::vcm;
    const Scene fog = fog_box();
    EXPECT_NO_THROW(choose_integrator(bdpt, fog));
    auto message = [](const Options& o, const Scene& s) -> std::string {
        try {
            choose_integrator(o, s);
        } catch (const UsageError& e) {
            return e.what();
        }
        return "(no error)";
    };
    const std::string vcm_error = message(vcm, fog);
    EXPECT_NE(vcm_error.find("vcm integrator"), std::string::npos) << vcm_error;
    EXPECT_NE(vcm_error.find("does not support participating media"), std::string::npos) << vcm_error;
    EXPECT_NE(vcm_error.find("--integrator bdpt or path"), std::string::npos) << vcm_error;
    const Scene height_fog = test::load_exact_scene(
        R"({"media": {"f": {"type": "height_fog", "sigma_a": 0, "sigma_s": 1, "scale_height": 0.5}}, "medium": "f",
            "shapes": [{"type": "sphere", "center": [0, 0, -3], "radius": 1, "emission": 1}]})",
        "height fog");
    const std::string bdpt_error = message(bdpt, height_fog);
    EXPECT_NE(bdpt_error.find("does not support heterogeneous media"), std::string::npos) << bdpt_error;
    EXPECT_NE(bdpt_error.find("expected --integrator path"), std::string::npos) << bdpt_error;
}

}  // namespace
}  // namespace spt

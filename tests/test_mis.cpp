// Next-event estimation with multiple importance sampling in the path tracer: the three
// estimators (light sampling and BSDF sampling combined by MIS, either alone) are unbiased,
// so they agree with each other and with the analytic radiance of a floor under a small
// emitting sphere; and scenes whose lights are only point lights or (by default) emitting
// planes take exactly the code path of before (bit-identical films whatever the mode).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "render/mis.h"
#include "scene/scene_loader.h"
#include "test_scenes.h"

namespace {

using namespace spt;
using spt::test::compare;
using spt::test::constant_spectrum;
using spt::test::describe;
using spt::test::max_pixel_z;
using spt::test::render_film;
using spt::test::small_settings;

constexpr float kRadius = 0.1f;
constexpr double kLe = 30.0, kAlbedo = 0.8;
const Vec3 kCenter(0, 0.5f, 0);

/// A diffuse floor y = 0 under a small emitting sphere (black, radius 0.1 at (0, 0.5, 0)),
/// and a plastic ball beside it (a diffuse and a specular lobe: MIS at a mixed vertex). The
/// camera looks down at (x, 0, z) from `camera_height` with field of view `fov`.
Scene floor_under_sphere(float x, float z, float fov, bool with_ball, Vec3 offset = {}) {
    Scene scene;
    Material floor;
    floor.name = "floor";
    floor.bsdf = DiffuseBsdf{constant_spectrum(kAlbedo)};
    const int m_floor = scene.add_material(floor);
    Material black;
    black.name = "black";
    black.bsdf = DiffuseBsdf{};
    const int m_black = scene.add_material(black);
    scene.planes.push_back({{0, 1, 0}, offset.y, m_floor});
    Sphere light{kCenter + offset, kRadius, m_black};
    light.light = scene.add_emitter(ShapeKind::sphere, constant_spectrum(kLe));
    scene.spheres.push_back(light);
    if (with_ball) {
        Material plastic;
        plastic.name = "plastic";
        plastic.bsdf = LobeMixBsdf{constant_spectrum(0.6), constant_spectrum(0.2), {}, {}};
        scene.spheres.push_back({{0.35f, 0.15f, -0.1f}, 0.15f, scene.add_material(plastic)});
    }
    scene.camera = {Vec3(x, 1.2f, z + 1e-3f) + offset, Vec3(x, 0.f, z) + offset, {0, 0, -1}, fov};
    scene.finalize();
    return scene;
}

RenderSettings with_mode(RenderSettings s, LightSampling mode) {
    s.integrator.light_sampling = mode;
    return s;
}

TEST(Mis, PowerHeuristicStaysFiniteForExtremeDensities) {
    EXPECT_FLOAT_EQ(power_heuristic(1.f, 1.f), 0.5f);
    EXPECT_FLOAT_EQ(power_heuristic(3.f, 1.f), 0.9f);
    EXPECT_FLOAT_EQ(power_heuristic(1.f, 3.f) + power_heuristic(3.f, 1.f), 1.f);
    EXPECT_EQ(power_heuristic(0.f, 1.f), 0.f);
    EXPECT_EQ(power_heuristic(1.f, 0.f), 1.f);
    // Squares of these overflow a float: the weights must still be 1 and 0, never NaN.
    EXPECT_EQ(power_heuristic(1e25f, 0.3f), 1.f);
    EXPECT_EQ(power_heuristic(0.3f, 1e25f), 0.f);
    EXPECT_FLOAT_EQ(power_heuristic(2e30f, 2e30f), 0.5f);
    EXPECT_EQ(power_heuristic(INFINITY, 1.f), 1.f);
    EXPECT_EQ(power_heuristic(1.f, INFINITY), 0.f);
}

TEST(Mis, QuadricsUnderADiskLightHaveNoRejectedSamples) {
    // A disk light over a floor with a cylinder, a cone and a plastic ball: next-event
    // estimation sees the disk nearly edge-on from points near its plane (densities beyond
    // 1e19 in solid angle), where the power heuristic's squares overflowed.
    const std::string text = R"({"camera": {"position": [0, 0.3, 3.5], "look_at": [0, -0.2, 0]},
      "materials": {"white": {"type": "diffuse", "kd": 0.75}, "plastic": {"kd": 0.5, "ks": 0.2}},
      "shapes": [{"type": "plane", "normal": [0, 1, 0], "point": [0, -1, 0], "material": "white"},
        {"type": "cylinder", "base": [-0.8, -1, -0.3], "axis": [0, 1, 0], "radius": 0.3, "height": 0.9, "material": "white"},
        {"type": "cone", "base": [0.1, -1, -0.5], "axis": [0, 1, 0], "radius": 0.35, "height": 1.0, "material": "plastic"},
        {"type": "disk", "center": [0, 1.2, 0], "normal": [0, -1, 0], "radius": 0.4, "emission": 10},
        {"type": "disk", "center": [0.5, -0.2, 0.5], "normal": [0, 1, 0], "radius": 0.2, "emission": 5}]})";
    const Scene scene = load_scene_text(text, "quadrics.json", "quadrics", {}, {});
    RenderStats stats;
    const auto film = render_film(scene, small_settings(48, 48, 64), &stats);
    EXPECT_EQ(film->rejected_nonfinite(), 0u);
    EXPECT_EQ(film->rejected_negative(), 0u);
}

TEST(Mis, FloorRadianceUnderSmallSphereIsAnalyticForEveryEstimator) {
    // Only direct light reaches the floor (the emitter is black, nothing else reflects):
    // L = (ρ/π)·E with E = π·Le·(r/d)²·cos β for a sphere wholly above the horizon.
    const float x = 0.3f, z = -0.2f;
    const Scene scene = floor_under_sphere(x, z, 1e-4f, false);
    const Vec3 p(x, 0, z), to_center = kCenter - p;
    const double d = length(to_center), cos_beta = to_center.y / d;
    const double expected = kAlbedo * kLe * (kRadius / d) * (kRadius / d) * cos_beta;
    for (LightSampling mode : {LightSampling::mis, LightSampling::light, LightSampling::bsdf}) {
        if (mode == LightSampling::mis) {
            // The same far from the origin (floats 1e-3 apart there): the shadow rays to the
            // sphere, which skip the light's own sphere, must neither leak nor self-occlude.
            const Scene far = floor_under_sphere(x, z, 1e-4f, false, {3e4f, -2e3f, -1e4f});
            const auto film = render_film(far, small_settings(8, 8, 256));
            const auto r = max_pixel_z(*film, expected);
            EXPECT_LT(r.max_z, 4.5) << "far from the origin: " << describe(r);
        }
        const int spp = mode == LightSampling::bsdf ? 4096 : 256;  // BSDF sampling rarely finds it
        const auto film = render_film(scene, with_mode(small_settings(8, 8, spp), mode));
        const auto r = max_pixel_z(*film, expected);
        // 64 pixels: |z| < 4.5 fails by chance with probability 64·7e-6.
        EXPECT_LT(r.max_z, 4.5) << "mode " << int(mode) << " expected " << expected << ": " << describe(r);
    }
}

TEST(Mis, EstimatorsAgreeOnTheWholeImage) {
    // The camera sees the floor, the emitter and the plastic ball (its specular lobe reflects
    // the emitter: emission after a delta bounce keeps weight 1).
    Scene scene = floor_under_sphere(0.f, 0.f, 70.f, true);
    const RenderSettings base = small_settings(24, 24, 512);
    const auto mis = render_film(scene, with_mode(base, LightSampling::mis));
    const auto light = render_film(scene, with_mode(base, LightSampling::light));
    const auto bsdf = render_film(scene, with_mode(small_settings(24, 24, 4096, 2), LightSampling::bsdf));
    const auto all = [](int, int) { return true; };
    for (const auto& [name, other] : {std::pair{"light", light.get()}, std::pair{"bsdf", bsdf.get()}}) {
        const spt::test::Comparison c = compare(*mis, *other, all);
        EXPECT_NEAR(c.mean_a, c.mean_b, 4 * c.se) << "mis against " << name;
    }
}

TEST(Mis, PlaneLightSamplingAgreesWithFindingThePlane) {
    // cornell's ceiling is not sampled by default (measured not to pay); sampled, it must
    // give the same image in expectation.
    std::optional<Scene> scene = load_builtin_scene("cornell", {});
    ASSERT_TRUE(scene.has_value());
    RenderSettings s = small_settings(16, 16, 256);
    const auto plain = render_film(*scene, s);
    s.integrator.sample_planes = true;
    s.seed = 7;
    const auto sampled = render_film(*scene, s);
    const spt::test::Comparison c = compare(*plain, *sampled, [](int, int) { return true; });
    EXPECT_NEAR(c.mean_a, c.mean_b, 4 * c.se);
    EXPECT_LT(c.max_z, 5.0);
}

TEST(Mis, EveryBuiltInSceneMatchesTheEstimatorOfBefore) {
    // LightSampling::bsdf draws the same random numbers and does the same arithmetic as the
    // path tracer before light sampling (bit-identical images on every built-in scene, checked
    // against that build when it was replaced). The default must agree with it in expectation.
    for (const std::string& name : builtin_scene_names()) {
        std::optional<Scene> scene = load_builtin_scene(name, {});
        ASSERT_TRUE(scene.has_value()) << name;
        const auto mis = render_film(*scene, small_settings(32, 32, 64));
        const auto bsdf = render_film(*scene, with_mode(small_settings(32, 32, 512, 2), LightSampling::bsdf));
        const spt::test::Comparison c = compare(*mis, *bsdf, [](int, int) { return true; });
        EXPECT_NEAR(c.mean_a, c.mean_b, 4.5 * c.se) << name;
        EXPECT_EQ(mis->rejected_samples(), 0u) << name;
    }
}

TEST(Mis, ScenesWithoutSampledLightsTakeTheOldPathBitForBit) {
    // Point lights only (cornell-point), or an emitting plane only (cornell) with the plane
    // sampler off (IntegratorSettings::sample_planes, on by default): no light of the
    // next-event choice, so no random number is drawn for one and every mode gives the
    // same bits as BSDF sampling alone, the estimator of before.
    for (const char* name : {"cornell", "cornell-point"}) {
        std::optional<Scene> scene = load_builtin_scene(name, {});
        ASSERT_TRUE(scene.has_value());
        RenderSettings s = small_settings(16, 16, 8);
        s.integrator.sample_planes = false;
        const auto mis = render_film(*scene, with_mode(s, LightSampling::mis));
        const auto bsdf = render_film(*scene, with_mode(s, LightSampling::bsdf));
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x)
                ASSERT_EQ(mis->pixel_xyz(x, y).y, bsdf->pixel_xyz(x, y).y) << name << " pixel " << x << "," << y;
    }
}

}  // namespace

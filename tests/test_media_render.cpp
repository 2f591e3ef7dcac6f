// Participating media through the whole renderer: hero-wavelength spectral MIS against the
// one-wavelength reference, spot lights, and vcm's refusal of media (bdpt: test_bdpt_media.cpp).
#include <gtest/gtest.h>

#include <cmath>

#include "cli/integrator_choice.h"
#include "test_scenes.h"

namespace spt {
namespace {

Scene load(const std::string& json) {
    const RelativeFileReader none = [](const std::string&, std::string&, std::string&, std::string& why) {
        why = "no files in this test";
        return false;
    };
    return load_scene_text(json, "test.json", "test", SpectralResolution{}, none);
}

/// Camera at the centre of an emitting sphere (radiance 1) in a strongly chromatic medium:
/// bluish scattering, reddish absorption, so free-flight distances differ a lot between
/// wavelengths. Every pixel has the same expected colour (the scene is symmetric).
Scene chromatic_furnace() {
    return load(R"({"camera": {"position": [0, 0, 0], "look_at": [0, 0, -1]},
        "media": {"m": {"type": "homogeneous", "g": 0.5,
            "sigma_s": {"type": "table", "points": [[380, 2.5], [780, 0.2]]},
            "sigma_a": {"type": "table", "points": [[380, 0.05], [780, 0.8]]}}},
        "medium": "m",
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1.5, "emission": 1}]})");
}

/// Per-pixel mean and variance over the image (pixels are i.i.d. here) of X, Y, Z and of
/// two opponent colour signals, X − Y (red–green) and Z − Y (blue–yellow): the colour noise.
struct ColourStats {
    static constexpr int kSignals = 5;
    double mean[kSignals] = {}, var[kSignals] = {};
};
ColourStats colour_stats(const Film& film) {
    ColourStats s;
    const int n = film.width() * film.height();
    for (int pass = 0; pass < 2; ++pass)
        for (int y = 0; y < film.height(); ++y)
            for (int x = 0; x < film.width(); ++x) {
                const Xyz c = film.pixel_xyz(x, y);
                const double v[ColourStats::kSignals] = {c.x, c.y, c.z, c.x - c.y, c.z - c.y};
                for (int k = 0; k < ColourStats::kSignals; ++k) {
                    if (pass == 0) s.mean[k] += v[k] / n;
                    else s.var[k] += (v[k] - s.mean[k]) * (v[k] - s.mean[k]) / (n - 1);
                }
            }
    return s;
}

TEST(ChromaticMedium, HeroMisMatchesOneWavelengthReferenceWithLessColourNoise) {
    const Scene scene = chromatic_furnace();
    RenderSettings hero = test::small_settings(64, 64, 4, 5);
    RenderSettings single = hero;
    single.integrator.wavelengths_per_path = 1;
    RenderStats hero_time, single_time;
    const auto a = test::render_film(scene, hero, &hero_time);
    const auto b = test::render_film(scene, single, &single_time);
    const ColourStats h = colour_stats(*a), s = colour_stats(*b);
    const int n = 64 * 64;
    const char* names[ColourStats::kSignals] = {"X", "Y", "Z", "X-Y", "Z-Y"};
    for (int k = 0; k < ColourStats::kSignals; ++k) {
        // Same expectation: the means agree within 4 standard errors of their difference.
        const double se = std::sqrt((h.var[k] + s.var[k]) / n);
        EXPECT_NEAR(h.mean[k], s.mean[k], 4 * se) << names[k];
        std::printf("[ measured ] %s: mean %.4f (hero MIS) %.4f (one wavelength); variance per pixel at 4 spp "
                    "%.4g (hero MIS) %.4g (one wavelength), ratio %.2f\n",
                    names[k], h.mean[k], s.mean[k], h.var[k], s.var[k], s.var[k] / h.var[k]);
    }
    // The colour is far from grey (a strongly chromatic medium), and the four wavelengths of
    // a path cut the colour noise several times at equal paths (a path costs about the same:
    // one free flight per event serves all four).
    EXPECT_GT(h.mean[2] / h.mean[0], 1.2);
    for (int k = 3; k < ColourStats::kSignals; ++k) EXPECT_GT(s.var[k] / h.var[k], 3.0) << names[k];
    std::printf("[ measured ] seconds: hero MIS %.3f, one wavelength %.3f (noisy: other work on the machine)\n",
                hero_time.seconds, single_time.seconds);
}

TEST(ChromaticMedium, DispersionInsideAMediumKeepsTheHeroEstimateUnbiased) {
    // A dispersive glass sphere in the chromatic medium terminates the companions mid-path;
    // the spectral MIS must then fall back to the hero alone (against the one-wavelength mode).
    Scene scene = load(R"({"camera": {"position": [0, 0, 0.9], "look_at": [0, 0, -1]},
        "materials": {"bk7": {"kt": 1, "ior": {"type": "glass", "name": "N-BK7"}}},
        "media": {"m": {"type": "homogeneous", "g": 0.2,
            "sigma_s": {"type": "table", "points": [[380, 1.2], [780, 0.3]]},
            "sigma_a": {"type": "table", "points": [[380, 0.05], [780, 0.4]]}}},
        "medium": "m",
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1.5, "emission": 1},
                   {"type": "sphere", "center": [0, 0, -0.2], "radius": 0.5, "material": "bk7", "exterior": "m"}]})");
    ASSERT_TRUE(scene.effects.dispersion);
    RenderSettings hero = test::small_settings(24, 24, 64, 3);
    RenderSettings single = hero;
    single.integrator.wavelengths_per_path = 1;
    const auto a = test::render_film(scene, hero);
    const auto b = test::render_film(scene, single);
    const test::ImageMean ma = test::image_mean_y(*a), mb = test::image_mean_y(*b);
    EXPECT_NEAR(ma.mean, mb.mean, 4 * std::hypot(ma.standard_error, mb.standard_error));
}

// ---------------------------- Spot light ----------------------------

TEST(SpotLight, LightsItsConeAsAPointLightAndNothingOutside) {
    // A spot light 1 above a diffuse plane (albedo 0.5), pointing down with a 30° cone: the
    // camera looks straight down with a tiny field of view at the foot (inside the cone:
    // (a/π)·I/h²) and at 45° off the axis (outside: black).
    for (const float x : {0.f, 1.f}) {
        Scene scene = test::lit_plane_scene(0.5, 2.0, 1.f, x, 0.f);
        SpotLight spot;
        spot.position = {0.f, 1.f, 0.f};
        spot.direction = {0.f, -1.f, 0.f};
        spot.intensity = test::constant_spectrum(2.0);
        spot.cos_cone = std::cos(30.f * kPi / 180.f);
        spot.cos_falloff = std::cos(20.f * kPi / 180.f);
        scene.lights.clear();
        scene.lights.emplace_back(spot);
        scene.finalize();
        ASSERT_EQ(scene.spot_light_indices.size(), 1u);
        const auto film = test::render_film(scene, test::small_settings(4, 4, 16));
        const double expected = x == 0.f ? test::lit_plane_radiance(0.5, 2.0, 1.0, 0.0) : 0.0;
        EXPECT_NEAR(test::image_mean_y(*film).mean, expected, 2e-3 * expected + 1e-9) << "x = " << x;
    }
}

TEST(SpotLight, FalloffIsASmoothStepBetweenTheAngles) {
    SpotLight s;
    s.direction = {0.f, 0.f, 1.f};
    s.cos_cone = std::cos(30.f * kPi / 180.f);
    s.cos_falloff = std::cos(10.f * kPi / 180.f);
    auto at = [&](float degrees) {
        const float r = degrees * kPi / 180.f;
        return s.falloff({std::sin(r), 0.f, std::cos(r)});
    };
    EXPECT_EQ(at(5.f), 1.f);
    EXPECT_EQ(at(31.f), 0.f);
    EXPECT_GT(at(15.f), at(25.f));
    const float mid = 0.5f * (s.cos_cone + s.cos_falloff);
    EXPECT_NEAR(s.falloff({std::sqrt(1.f - mid * mid), 0.f, mid}), 0.5f, 1e-4f);
}

// ---------------------------- Integrators without media ----------------------------

TEST(MediaIntegrators, VcmRefusesMedia) {
    const Scene fog = chromatic_furnace();
    for (IntegratorKind kind : {IntegratorKind::vcm}) {
        Options options;
        options.integrator = kind;
        try {
            choose_integrator(options, fog);
            ADD_FAILURE() << "no error for " << integrator_name(kind);
        } catch (const UsageError& e) {
            EXPECT_NE(std::string(e.what()).find(std::string(integrator_name(kind)) + " integrator"), std::string::npos);
            EXPECT_NE(std::string(e.what()).find("participating media"), std::string::npos) << e.what();
        }
    }
    Options path;
    path.integrator = IntegratorKind::path;
    EXPECT_NO_THROW(choose_integrator(path, fog));
}

TEST(MediaScenes, ScenesWithoutMediaHaveNoMediumState) {
    const Scene cornell = *load_builtin_scene("cornell", SpectralResolution{});
    EXPECT_FALSE(cornell.effects.media);
    for (const auto& sides : cornell.shape_media) EXPECT_TRUE(sides.empty());
    EXPECT_EQ(cornell.interface_material, -1);
}

}  // namespace
}  // namespace spt

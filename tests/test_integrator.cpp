// Statistical and exact tests of the path tracer on scenes with known answers (ROBUSTNESS.md
// §7): closed furnaces, a point light above a plane, mirrors, glass in uniform environments,
// and the NaN/Inf guard on the canonical Cornell boxes.
//
// Tolerances. Each render has a fixed seed, so every run is deterministic. A pixel passes when
// |Y − expected| ≤ kZ·σ, σ its measured standard error (Film::pixel_y_standard_error). With
// kZ = 5 and at most 1024 pixels per check, a correct renderer fails with probability below
// 1024 · 5.7e-7 ≈ 6e-4 (Gaussian two-sided tail, union bound), while a bias of a few σ is
// caught. "Exact" checks compare with a relative tolerance of 1e-5 (float32 arithmetic).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <future>
#include <numbers>
#include <string>
#include <vector>

#include "core/rng.h"
#include "render/integrator.h"
#include "scene/builtin_scenes.h"
#include "test_scenes.h"

namespace spt {
namespace {

using test::closed_sphere_scene;
using test::constant_spectrum;
using test::describe;
using test::diffuse_material;
using test::image_mean_y;
using test::lit_plane_radiance;
using test::lit_plane_scene;
using test::max_pixel_z;
using test::render_film;
using test::small_settings;

constexpr double kZ = 5.0;        // z-score bound (see the header comment)
constexpr double kExactRel = 1e-5;  // "exact" in float32

constexpr float kPiF = std::numbers::pi_v<float>;

/// Furnace with a point light: diffuse sphere kd = 0.5, I = π at the centre. The first hit
/// receives (0.5/π)·π/1² = 0.5, every further bounce halves it: Y = 0.5 + 0.25 + … = 1.
TEST(IntegratorFurnace, PointLightAtCentreGivesOne) {
    Scene scene = closed_sphere_scene(diffuse_material(0.5));
    scene.add_point_light({0, 0, 0}, constant_spectrum(kPiF));
    scene.finalize();
    const auto film = render_film(scene, small_settings(16, 16, 512, 11));
    EXPECT_EQ(film->rejected_samples(), 0u);
    const auto z = max_pixel_z(*film, 1.0);
    EXPECT_LE(z.max_z, kZ) << describe(z);
    const auto m = image_mean_y(*film);
    EXPECT_NEAR(m.mean, 1.0, kZ * m.standard_error) << "σ = " << m.standard_error;
    // Power: a bias above 5·0.002 = 1 % would be caught.
    EXPECT_LT(m.standard_error, 0.002) << "too few samples for the test to mean anything";
}

/// Four point lights of I = π/4, all at the centre, give the same answer (pbrt's variant),
/// which checks that next-event estimation sums over lights.
TEST(IntegratorFurnace, FourPointLightsOfQuarterIntensityGiveOne) {
    Scene scene = closed_sphere_scene(diffuse_material(0.5));
    for (int i = 0; i < 4; ++i) scene.add_point_light({0, 0, 0}, constant_spectrum(kPiF / 4));
    scene.finalize();
    const auto film = render_film(scene, small_settings(8, 8, 256, 12));
    const auto z = max_pixel_z(*film, 1.0);
    EXPECT_LE(z.max_z, kZ) << describe(z);
}

/// Closed furnace, albedo 0.8, Le = 1, roulette on, unbounded depth: Σ 0.8^k = 5.
TEST(IntegratorFurnace, EmissiveAlbedo08WithRouletteGivesFive) {
    Scene scene = closed_sphere_scene(diffuse_material(0.8), 1.0);
    scene.finalize();
    RenderSettings rs = small_settings(16, 16, 1024, 13);
    ASSERT_TRUE(rs.integrator.roulette);
    ASSERT_EQ(rs.integrator.max_depth, IntegratorSettings::kUnbounded);
    const auto film = render_film(scene, rs);
    EXPECT_EQ(film->rejected_samples(), 0u);
    const auto z = max_pixel_z(*film, 5.0);
    EXPECT_LE(z.max_z, kZ) << describe(z);
    const auto m = image_mean_y(*film);
    EXPECT_NEAR(m.mean, 5.0, kZ * m.standard_error) << "σ = " << m.standard_error;
    EXPECT_LT(m.standard_error, 0.01);  // a bias above 1 % would be caught
}

/// Radiance along rays of the closed furnace, computed by trace_path directly: with roulette
/// off and a depth cap every path is the same, so L(λ) is exact at every wavelength. This is
/// a property of BSDF sampling alone (LightSampling::bsdf, the estimator before next-event
/// estimation for area lights): sampling the emitting wall as a light gives each path its own
/// value (the default MIS estimator is checked statistically by the roulette furnace above).
void expect_exact_furnace_paths(const Scene& scene, int max_depth, double expected) {
    IntegratorSettings is;
    is.roulette = false;
    is.max_depth = max_depth;
    is.light_sampling = LightSampling::bsdf;
    PathStats stats;
    for (int s = 0; s < 200; ++s) {
        Rng rng(5, 0, static_cast<std::uint64_t>(s));
        SampledWavelengths lambda = SampledWavelengths::sample(rng.uniform());
        const Vec3 d = normalize(Vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f));
        const SampledSpectrum L = trace_path(scene, is, {scene.camera.position, d, kInfinity}, 0.f, lambda, rng, stats);
        for (int k = 0; k < kLambdaCount; ++k)
            ASSERT_NEAR(L[k], expected, kExactRel * expected) << "sample " << s << " wavelength " << k;
    }
    // One camera ray plus max_depth bounce rays per path, no shadow rays.
    EXPECT_EQ(stats.rays, 200u * static_cast<std::uint64_t>(max_depth + 1));
}

/// The same furnace rendered twice with the same seed: a scene whose radiance is 1 at every
/// wavelength (the reference) and the furnace. Wavelengths and pixel positions are drawn the
/// same way for both, so a zero-variance furnace gives exactly expected × reference per pixel
/// (zero variance with BSDF sampling alone, as above).
void expect_exact_furnace_image(const Scene& scene, int max_depth, double expected) {
    Scene reference = closed_sphere_scene(diffuse_material(0.0), 1.0);
    reference.finalize();
    RenderSettings rs = small_settings(8, 8, 16, 21);
    rs.integrator.roulette = false;
    rs.integrator.max_depth = max_depth;
    rs.integrator.light_sampling = LightSampling::bsdf;
    const auto film = render_film(scene, rs);
    const auto ref = render_film(reference, rs);
    EXPECT_EQ(film->rejected_samples(), 0u);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const double ratio = film->pixel_xyz(x, y).y / ref->pixel_xyz(x, y).y;
            ASSERT_NEAR(ratio, expected, kExactRel * expected) << "pixel " << x << ", " << y;
        }
}

TEST(IntegratorFurnace, NoRouletteDepth10IsExact) {
    Scene scene = closed_sphere_scene(diffuse_material(0.8), 1.0);
    scene.finalize();
    const double expected = (1 - std::pow(0.8, 11)) / (1 - 0.8);
    ASSERT_NEAR(expected, 4.5705033, 1e-7);
    expect_exact_furnace_paths(scene, 10, expected);
    expect_exact_furnace_image(scene, 10, expected);
}

TEST(IntegratorFurnace, AlbedoOneDepth10GivesEleven) {
    Scene scene = closed_sphere_scene(diffuse_material(1.0), 1.0);
    scene.finalize();
    expect_exact_furnace_paths(scene, 10, 11.0);
    expect_exact_furnace_image(scene, 10, 11.0);
}

TEST(IntegratorFurnace, DepthZeroSeesOnlyEmission) {
    Scene scene = closed_sphere_scene(diffuse_material(0.8), 1.0);
    scene.finalize();
    expect_exact_furnace_paths(scene, 0, 1.0);
}

/// Radiance scales linearly with emission: Le = 1e6 gives 5e6 with the same relative error.
/// Roulette decisions depend on the throughput only, so with one seed the two images are the
/// same up to the factor 1e6 (float rounding aside).
TEST(IntegratorFurnace, HugeEmissionScalesLinearly) {
    Scene unit = closed_sphere_scene(diffuse_material(0.8), 1.0);
    unit.finalize();
    Scene huge = closed_sphere_scene(diffuse_material(0.8), 1e6);
    huge.finalize();
    const RenderSettings rs = small_settings(4, 4, 256, 17);
    const auto a = render_film(unit, rs);
    const auto b = render_film(huge, rs);
    EXPECT_EQ(b->rejected_samples(), 0u);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            ASSERT_NEAR(b->pixel_xyz(x, y).y / a->pixel_xyz(x, y).y, 1e6, 1e6 * kExactRel);
            ASSERT_NEAR(b->pixel_y_standard_error(x, y) / a->pixel_y_standard_error(x, y), 1e6, 1e6 * 1e-4);
        }
    const auto z = max_pixel_z(*b, 5e6);
    EXPECT_LE(z.max_z, kZ) << describe(z);
}

// ---------------------------------------------------------------------------------------
// Point light above a Lambertian plane (ROBUSTNESS cases 3 and 17).

/// trace_path along a vertical ray hitting the plane at (x, height, z): the path has exactly one
/// diffuse vertex lit by the light (the bounce escapes to a black sky), so L(λ) is exact.
SampledSpectrum trace_vertical(const Scene& scene, float x, float z, float from_height) {
    IntegratorSettings is;
    PathStats stats;
    Rng rng(3, 1, 4);
    SampledWavelengths lambda = SampledWavelengths::sample(0.37f);
    const Ray ray{{x, from_height, z}, {0, -1, 0}, kInfinity};
    return trace_path(scene, is, ray, 0.f, lambda, rng, stats);
}

TEST(IntegratorPointLight, PlaneRadianceIsExactAlongRays) {
    const double a = 0.5, intensity = 1.0;
    for (float h : {1.f, 1e-2f, 1e-4f, 1e-6f}) {
        for (float rho_over_h : {0.f, 0.5f, 1.f, 3.f}) {
            const float rho = rho_over_h * h;
            Scene scene = lit_plane_scene(a, intensity, h, rho, 0.f);
            scene.finalize();
            // Expected from the float positions the renderer uses (h and ρ are floats).
            const double expected = lit_plane_radiance(a, intensity, h, rho);
            const SampledSpectrum L = trace_vertical(scene, rho, 0.f, 2.f * h);
            for (int k = 0; k < kLambdaCount; ++k)
                EXPECT_NEAR(L[k], expected, kExactRel * expected)
                    << "h = " << h << ", rho = " << rho << ", wavelength " << k;
        }
        // Case 17: the foot pixel is (a/π)·I/h² = 0.1591549/h².
        EXPECT_NEAR(lit_plane_radiance(a, intensity, h, 0), 0.1591549 / (double(h) * h),
                    1e-6 / (double(h) * h));
    }
}

/// Scale invariance (case 3): plane, light and ray all translated by s. Oblique rays make the
/// hit points land off the float grid; expected values use the hit point the scene reports.
TEST(IntegratorPointLight, PlaneRadianceIsScaleInvariant) {
    const double a = 0.5, intensity = 1.0;
    for (float s : {0.f, 1e-3f, 1.f, 1e3f, 1e5f}) {
        Scene scene = lit_plane_scene(a, intensity, 1.f, 0.f, 0.f, s);
        for (Light& l : scene.lights) std::get<PointLight>(l).position = {s, s + 1.f, s};
        scene.finalize();
        const Vec3 light = std::get<PointLight>(scene.lights[scene.point_light_indices.at(0)]).position;
        int checked = 0;
        for (float rho : {0.f, 0.5f, 1.f, 1.5f}) {
            for (const Vec3 dir : {Vec3(0, -1, 0), normalize(Vec3(0.3f, -1.f, 0.2f)),
                                   normalize(Vec3(-0.7f, -0.4f, 0.1f))}) {
                const Ray ray{{s + rho, s + 3.f, s}, dir, kInfinity};
                const std::optional<Hit> hit = scene.intersect(ray);
                ASSERT_TRUE(hit);
                const double dx = double(light.x) - hit->p.x, dy = double(light.y) - hit->p.y,
                             dz = double(light.z) - hit->p.z;
                const double r2 = dx * dx + dy * dy + dz * dz;
                const double expected = a / std::numbers::pi * intensity * (dy / std::sqrt(r2)) / r2;
                IntegratorSettings is;
                PathStats stats;
                Rng rng(9, 9, 9);
                SampledWavelengths lambda = SampledWavelengths::sample(0.81f);
                const SampledSpectrum L = trace_path(scene, is, ray, 0.f, lambda, rng, stats);
                for (int k = 0; k < kLambdaCount; ++k)
                    EXPECT_NEAR(L[k], expected, kExactRel * expected)
                        << "s = " << s << ", rho = " << rho << ", dir = (" << dir.x << ", " << dir.y
                        << ", " << dir.z << "): shadow acne gives 0";
                ++checked;
            }
        }
        EXPECT_EQ(checked, 12);
    }
}

/// Render-level check: a 1×1 image through a tiny field of view is the radiance at one point;
/// Y must match within kZ·σ (σ from the spectral sampling noise).
TEST(IntegratorPointLight, PlanePixelsMatchAnalyticRadiance) {
    const double a = 0.5, intensity = 1.0;
    struct Case {
        float h, rho;
    };
    for (const Case c : {Case{1.f, 0.f}, Case{1.f, 0.75f}, Case{1.f, 2.f}, Case{1e-2f, 0.f},
                         Case{1e-2f, 1e-2f}, Case{1e-4f, 0.f}, Case{1e-4f, 2e-4f}}) {
        // Footprint 2·H·tan(vfov/2) ≈ 1.7e-8·H for vfov = 1e-6°: far below h.
        Scene scene = lit_plane_scene(a, intensity, c.h, c.rho, 0.f, 0.f, 1.f, 1e-6f);
        scene.finalize();
        const auto film = render_film(scene, small_settings(1, 1, 4096, 31, 1));
        const double expected = lit_plane_radiance(a, intensity, c.h, c.rho);
        const auto z = max_pixel_z(*film, expected);
        EXPECT_LE(z.max_z, kZ) << "h = " << c.h << ", rho = " << c.rho << ": expected " << expected
                               << "; " << describe(z);
        EXPECT_EQ(film->rejected_samples(), 0u);
    }
}

/// A light exactly on the plane: every direction to it is tangent (or undefined at the foot).
/// The image must be finite and non-negative, with no rejected samples.
TEST(IntegratorPointLight, LightOnThePlaneIsFiniteAndNonNegative) {
    Scene scene = lit_plane_scene(0.5, 1.0, 0.f, 0.f, 0.f, 0.f, 1.f, 60.f);
    scene.finalize();
    const auto film = render_film(scene, small_settings(9, 9, 16, 41));
    EXPECT_EQ(film->rejected_samples(), 0u);
    EXPECT_EQ(test::count_bad_pixels(*film), 0);
    // The ray that hits the light's position exactly.
    const SampledSpectrum L = trace_vertical(scene, 0.f, 0.f, 1.f);
    for (int k = 0; k < kLambdaCount; ++k) EXPECT_TRUE(std::isfinite(L[k]) && L[k] >= 0.f) << L[k];
}

// ---------------------------------------------------------------------------------------
// NaN/Inf guard on the canonical scenes.

TEST(IntegratorRobustness, CornellBoxesHaveNoRejectedSamples) {
    for (const std::string name : {"cornell", "cornell-point"}) {
        for (const int bins : {SpectralResolution::kDefaultBins, SpectralResolution::kExact, 1}) {
            const std::optional<Scene> scene = make_builtin_scene(name, SpectralResolution{bins});
            ASSERT_TRUE(scene) << name;
            const int spp = bins == SpectralResolution::kDefaultBins ? 16 : 4;
            const auto film = render_film(*scene, small_settings(32, 32, spp, 3));
            EXPECT_EQ(film->rejected_nonfinite(), 0u) << name << ", bins " << bins;
            EXPECT_EQ(film->rejected_negative(), 0u) << name << ", bins " << bins;
            EXPECT_EQ(test::count_bad_pixels(*film), 0) << name << ", bins " << bins;
            const auto m = image_mean_y(*film);
            EXPECT_GT(m.mean, 0.05) << name << ": the box should not be black";
            for (int y = 0; y < 32; ++y)
                for (int x = 0; x < 32; ++x) ASSERT_EQ(film->sample_count(x, y), std::uint32_t(spp));
        }
    }
}

// ---------------------------------------------------------------------------------------
// Mirrors and specular furnaces (case 14).

/// Runs f on another thread; if it does not finish in time the whole test binary stops (a
/// render that never terminates would otherwise hang the suite).
template <typename F>
void run_with_watchdog(F f, std::chrono::seconds limit, const char* what) {
    auto done = std::async(std::launch::async, f);
    if (done.wait_for(limit) != std::future_status::ready) {
        std::fprintf(stderr, "FATAL: %s did not finish within %lld s\n", what,
                     static_cast<long long>(limit.count()));
        std::_Exit(1);
    }
    done.get();
}

Scene facing_mirrors_scene() {
    Scene scene;
    scene.name = "facing mirrors";
    const int m = scene.add_material(test::mirror_material(1.0));
    scene.planes = {{{0, 1, 0}, -1.f, m}, {{0, -1, 0}, -1.f, m}};  // y = -1 and y = +1
    // Every camera ray goes downwards, so it bounces between the mirrors forever.
    scene.camera = {{0, 0, 0}, {0, -1, 0.3f}, {0, 0, -1}, 30.f};
    scene.finalize();
    return scene;
}

/// Lossless mirrors, no light: roulette caps survival at 0.95, so paths end after
/// roulette_depth + 0.95/0.05 = 22 rays on average; the image is exactly 0.
TEST(IntegratorMirrors, FacingMirrorsTerminateByRouletteAndAreBlack) {
    const Scene scene = facing_mirrors_scene();
    RenderSettings rs = small_settings(16, 16, 16, 51);
    rs.integrator.roulette = true;
    rs.integrator.roulette_depth = 3;
    std::unique_ptr<Film> film;
    RenderStats stats;
    run_with_watchdog([&] { film = render_film(scene, rs, &stats); }, std::chrono::seconds(60),
                      "facing mirrors with roulette");
    ASSERT_TRUE(film);
    EXPECT_EQ(film->rejected_samples(), 0u);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) ASSERT_EQ(film->pixel_xyz(x, y).y, 0.0);
    // Rays per path = 3 + K, K geometric with P(K = k) = 0.95^k·0.05: E[K] = 19, sd(K) = 19.49.
    const double paths = 16.0 * 16 * 16;
    ASSERT_EQ(stats.paths, std::uint64_t(paths));
    const double mean_rays = double(stats.rays) / paths;
    const double sigma = std::sqrt(0.95) / 0.05 / std::sqrt(paths);
    EXPECT_NEAR(mean_rays, 22.0, kZ * sigma);
}

/// Without roulette the depth cap ends the paths: exactly max_depth + 1 rays each.
TEST(IntegratorMirrors, FacingMirrorsTerminateByDepthCap) {
    const Scene scene = facing_mirrors_scene();
    RenderSettings rs = small_settings(8, 8, 4, 52);
    rs.integrator.roulette = false;
    rs.integrator.max_depth = 50;
    std::unique_ptr<Film> film;
    RenderStats stats;
    run_with_watchdog([&] { film = render_film(scene, rs, &stats); }, std::chrono::seconds(60),
                      "facing mirrors with a depth cap");
    ASSERT_TRUE(film);
    EXPECT_EQ(stats.rays, stats.paths * 51u);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) ASSERT_EQ(film->pixel_xyz(x, y).y, 0.0);
}

/// Camera outside a unit sphere in a uniform environment Le = 1.
Scene sphere_in_environment(std::optional<Material> material) {
    Scene scene;
    scene.name = "sphere in environment";
    scene.set_background(constant_spectrum(1.0));
    scene.camera = {{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 40.f};
    if (material) {
        const int m = scene.add_material(*material);
        scene.spheres.push_back({{0, 0, 0}, 1.f, m});
    }
    scene.finalize();
    return scene;
}

/// Mirror sphere in Le = 1: every path carries weight exactly 1, so with the same seed the
/// image equals the empty environment's image pixel for pixel (zero variance in L).
TEST(IntegratorMirrors, MirrorSphereInUniformEnvironmentIsExactlyOne) {
    const Scene sphere = sphere_in_environment(test::mirror_material(1.0));
    const Scene empty = sphere_in_environment(std::nullopt);
    const RenderSettings rs = small_settings(12, 12, 8, 53);
    const auto a = render_film(sphere, rs);
    const auto b = render_film(empty, rs);
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 12; ++x)
            ASSERT_NEAR(a->pixel_xyz(x, y).y / b->pixel_xyz(x, y).y, 1.0, kExactRel) << x << ", " << y;
}

/// Convex Lambertian sphere, albedo a, in Le = 1, no lights: one bounce then escape, exactly a
/// for pixels entirely on the sphere (the centre pixels).
TEST(IntegratorMirrors, ConvexLambertianSphereInUniformEnvironmentIsExactlyAlbedo) {
    const Scene sphere = sphere_in_environment(diffuse_material(0.6));
    const Scene empty = sphere_in_environment(std::nullopt);
    const RenderSettings rs = small_settings(12, 12, 8, 54);
    const auto a = render_film(sphere, rs);
    const auto b = render_film(empty, rs);
    // The sphere covers |pixel − centre| < 12/2 · (1/sqrt(15))/tan(20°) ≈ 4.25 pixels.
    for (int y = 4; y < 8; ++y)
        for (int x = 4; x < 8; ++x)
            ASSERT_NEAR(a->pixel_xyz(x, y).y / b->pixel_xyz(x, y).y, 0.6, 0.6 * kExactRel) << x << ", " << y;
    // Corner pixels miss the sphere.
    EXPECT_NEAR(a->pixel_xyz(0, 0).y / b->pixel_xyz(0, 0).y, 1.0, kExactRel);
}

// ---------------------------------------------------------------------------------------
// Dielectrics.

/// Diffuse wall z = -1 lit from the side by a point light, optionally a glass sphere between
/// camera and wall. The light sits at z = -0.5 off to the side, so no shadow ray from a
/// visible wall point passes the sphere (glass is opaque to shadow rays by design: a point light
/// seen through glass is a caustic that path tracing cannot find).
Scene wall_scene(std::optional<Material> sphere_material) {
    Scene scene;
    scene.name = "wall";
    const int wall = scene.add_material(diffuse_material(0.7));
    scene.planes.push_back({{0, 0, 1}, -1.f, wall});
    scene.add_point_light({5, 0.3f, -0.5f}, constant_spectrum(30.0));
    if (sphere_material) {
        const int m = scene.add_material(*sphere_material);
        scene.spheres.push_back({{0, 0, 0}, 0.5f, m});
    }
    scene.camera = {{0, 0, 3}, {0, 0, -1}, {0, 1, 0}, 35.f};
    scene.finalize();
    return scene;
}

/// Glass of index 1.0 is invisible: the image equals the scene without it, within noise.
/// Different seeds, so the two renders are independent and σ_diff² = σ_a² + σ_b².
TEST(IntegratorGlass, IndexOneSphereIsInvisible) {
    const Scene with = wall_scene(test::glass_material(1.0));
    const Scene without = wall_scene(std::nullopt);
    const auto a = render_film(with, small_settings(16, 16, 256, 61));
    const auto b = render_film(without, small_settings(16, 16, 256, 62));
    EXPECT_EQ(a->rejected_samples(), 0u);
    const auto ma = image_mean_y(*a), mb = image_mean_y(*b);
    const double sigma = std::hypot(ma.standard_error, mb.standard_error);
    EXPECT_NEAR(ma.mean, mb.mean, kZ * sigma) << "σ = " << sigma;
    EXPECT_LT(sigma, 0.01 * mb.mean) << "too noisy to detect a visible sphere";
    double max_z = 0;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            const double s = std::hypot(a->pixel_y_standard_error(x, y), b->pixel_y_standard_error(x, y));
            max_z = std::max(max_z, std::fabs(a->pixel_xyz(x, y).y - b->pixel_xyz(x, y).y) / s);
        }
    EXPECT_LE(max_z, kZ);
}

/// Negative control for the test above: glass of index 1.5 is visible (the image changes by
/// many σ), so the comparison can fail.
TEST(IntegratorGlass, IndexOneAndAHalfSphereIsVisible) {
    const Scene with = wall_scene(test::glass_material(1.5));
    const Scene without = wall_scene(std::nullopt);
    const auto a = render_film(with, small_settings(16, 16, 256, 61));
    const auto b = render_film(without, small_settings(16, 16, 256, 62));
    double max_z = 0;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            const double s = std::hypot(a->pixel_y_standard_error(x, y), b->pixel_y_standard_error(x, y));
            max_z = std::max(max_z, std::fabs(a->pixel_xyz(x, y).y - b->pixel_xyz(x, y).y) / s);
        }
    EXPECT_GT(max_z, 2 * kZ);
}

/// Camera inside a glass sphere (η = 1.5) in Le = 1: radiance is scaled by n² = 2.25 on
/// entering the denser medium (case 12). The camera is 0.374 from the centre, below 1/η, so no
/// ray is trapped by total internal reflection.
TEST(IntegratorGlass, CameraInsideGlassSphereSeesNSquared) {
    Scene scene;
    scene.name = "inside glass";
    scene.set_background(constant_spectrum(1.0));
    const int m = scene.add_material(test::glass_material(1.5));
    scene.spheres.push_back({{0, 0, 0}, 1.f, m});
    scene.camera = {{0.3f, 0.2f, -0.1f}, {0.f, 0.f, -1.f}, {0, 1, 0}, 90.f};
    scene.finalize();
    const auto film = render_film(scene, small_settings(16, 16, 256, 71));
    EXPECT_EQ(film->rejected_samples(), 0u);
    const auto z = max_pixel_z(*film, 2.25);
    EXPECT_LE(z.max_z, kZ) << describe(z);
    const auto mean = image_mean_y(*film);
    EXPECT_NEAR(mean.mean, 2.25, kZ * mean.standard_error);
    EXPECT_LT(mean.standard_error, 0.02);
}

/// Dielectric furnace (case 13): a glass sphere in Le = 1 seen from outside. Every escaping
/// path has weight exactly 1 per wavelength, so Y = 1 everywhere, also for dispersive BK7.
void expect_dielectric_furnace(const Material& glass, std::uint64_t seed) {
    const Scene scene = sphere_in_environment(glass);
    const auto film = render_film(scene, small_settings(16, 16, 256, seed));
    EXPECT_EQ(film->rejected_samples(), 0u);
    const auto z = max_pixel_z(*film, 1.0);
    EXPECT_LE(z.max_z, kZ) << describe(z);
    const auto mean = image_mean_y(*film);
    EXPECT_NEAR(mean.mean, 1.0, kZ * mean.standard_error);
}

TEST(IntegratorGlass, DielectricFurnaceIsOne) {
    expect_dielectric_furnace(test::glass_material(1.5), 81);
}

TEST(IntegratorGlass, DispersiveDielectricFurnaceIsOne) {
    const Material bk7 = test::bk7_material();
    ASSERT_TRUE(bk7.flags.has(BsdfFlags::dispersive));
    expect_dielectric_furnace(bk7, 82);
}

}  // namespace
}  // namespace spt

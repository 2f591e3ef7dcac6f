// The light BVH (render/light_bvh.h) and its importance (model/lights/light_bounds.h):
//   - its probabilities over every light sum to 1 at random shading points;
//   - sample() draws entries with the frequencies pmf() states (chi-square);
//   - the probability sample() returns is pmf() of the same entry, bit for bit, and the
//     whole-light choice next-event estimation uses equals the one emission weights ask for;
//   - no light that can send a point light gets probability 0 (one-sided emitters at grazing
//     angles, points inside a node's box, point and spot lights), while lights that cannot
//     (the back of a one-sided quad, outside a spot's cone) get 0;
//   - images rendered with the BVH and by power agree within noise (unbiasedness), and the
//     wavefront schedule renders the BVH's choices as the tile loop does.
// Planted bug: a pmf() that takes the first child's probability on every level fails the
// bit-for-bit, sum and chi-square tests (checked by hand when the tests were written).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "chi2.h"
#include "model/lights/light_bounds.h"
#include "render/light_bvh.h"
#include "render/nee_light_choice.h"
#include "test_scenes.h"

namespace {

using namespace spt;

/// A room open towards +z (the camera), lit by a one-sided ceiling quad, a two-sided wall quad,
/// a small sphere, a disk, a one-sided emitting mesh of 8 × 8 tiles (128 triangles) of its own
/// radiance, optionally an emitting plane far below (`plane`), and a dim environment.
std::string many_lights_json(bool plane) {
    std::string positions, indices;
    int v = 0;
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j) {
            const double x0 = -0.9 + 0.2 * i, z0 = -0.9 + 0.2 * j, s = 0.12;
            for (const auto& [x, z] : {std::pair{x0, z0}, {x0 + s, z0}, {x0 + s, z0 + s}, {x0, z0 + s}}) {
                if (!positions.empty()) positions += ", ";
                positions += std::to_string(x) + ", -0.99, " + std::to_string(z);
            }
            if (!indices.empty()) indices += ", ";
            // Counter-clockwise seen from above: the front faces up, into the room.
            indices += std::to_string(v) + ", " + std::to_string(v + 2) + ", " + std::to_string(v + 1) + ", " +
                       std::to_string(v) + ", " + std::to_string(v + 3) + ", " + std::to_string(v + 2);
            v += 4;
        }
    std::string s = R"({
  "camera": {"position": [0, 0, 3.5], "look_at": [0, 0, 0], "up": [0, 1, 0], "vfov_degrees": 40},
  "background": 0.05,
  "materials": {"gray": {"kd": 0.6}, "glossy": {"kd": 0.3, "ks": 0.3}},
  "shapes": [
    {"type": "quad", "origin": [-1, -1, -1], "edge1": [2, 0, 0], "edge2": [0, 2, 0], "material": "gray"},
    {"type": "quad", "origin": [-1, -1, -1], "edge1": [0, 2, 0], "edge2": [0, 0, 2], "material": "gray"},
    {"type": "sphere", "center": [0.3, -0.6, 0.1], "radius": 0.35, "material": "glossy"},
    {"type": "quad", "origin": [-0.2, 0.98, -0.2], "edge1": [0.4, 0, 0], "edge2": [0, 0, 0.4], "two_sided": false,
     "emission": 20},
    {"type": "quad", "origin": [0.99, -0.5, -0.5], "edge1": [0, 0.3, 0], "edge2": [0, 0, 0.3], "emission": 4},
    {"type": "sphere", "center": [-0.6, 0.5, 0.4], "radius": 0.05, "emission": 60},
    {"type": "disk", "center": [0.6, 0.7, -0.6], "normal": [0, -1, 0], "radius": 0.1, "emission": 8},
    {"type": "mesh", "positions": [)" +
                    positions + R"(], "indices": [)" + indices + R"(], "two_sided": false, "emission": 0.5})";
    if (plane) s += R"(,
    {"type": "plane", "normal": [0, 1, 0], "point": [0, -30, 0], "emission": 0.01})";
    s += "\n  ]\n}\n";
    return s;
}

Scene many_lights_scene(bool plane) { return test::load_exact_scene(many_lights_json(plane), "many-lights"); }

/// A random shading point in the room's box with a random unit normal.
LightSampleContext random_context(std::mt19937_64& rng) {
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    LightSampleContext ctx;
    ctx.p = {u(rng), u(rng), u(rng)};
    Vec3 n;
    do n = {u(rng), u(rng), u(rng)};
    while (length_squared(n) > 1.f || length_squared(n) < 1e-4f);
    ctx.n = ctx.ns = normalize(n);
    return ctx;
}

/// Sum of the probabilities of everything the BVH can choose at ctx.
double total_probability(const LightBvh& bvh, const LightSampleContext& ctx, bool with_planes) {
    double sum = static_cast<double>(bvh.infinite_count(with_planes)) * bvh.infinite_pmf(with_planes);
    for (std::size_t e = 0; e < bvh.entries().size(); ++e) sum += bvh.entry_pmf(ctx, static_cast<int>(e), with_planes);
    return sum;
}

TEST(LightBvh, HoldsEveryEmittingTriangleAsAnEntry) {
    const Scene scene = many_lights_scene(true);
    const LightBvh& bvh = scene.light_bvh;
    // Two quads, a sphere, a disk and the mesh's 128 triangles; the environment and the plane
    // in the infinite share.
    EXPECT_EQ(bvh.entries().size(), 4u + 128u);
    EXPECT_EQ(bvh.infinite_count(true), 2u);
    EXPECT_EQ(bvh.infinite_count(false), 1u);
}

TEST(LightBvh, ProbabilitiesSumToOneAtRandomPoints) {
    const Scene scene = many_lights_scene(true);
    std::mt19937_64 rng(7);
    for (int i = 0; i < 500; ++i) {
        const LightSampleContext ctx = random_context(rng);
        for (bool planes : {false, true}) EXPECT_NEAR(total_probability(scene.light_bvh, ctx, planes), 1.0, 2e-5);
    }
}

TEST(LightBvh, SampleReturnsThePmfOfItsChoiceBitForBit) {
    const Scene scene = many_lights_scene(true);
    const LightBvh& bvh = scene.light_bvh;
    IntegratorSettings settings;
    settings.light_selection = LightSelection::bvh;
    const NeeLightChoice choices(scene, settings);
    ASSERT_NE(choices.bvh, nullptr);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<float> uniform(0.f, 1.f);
    int entries = 0, triangles = 0;
    for (int i = 0; i < 20000; ++i) {
        const LightSampleContext ctx = random_context(rng);
        const float u = std::min(uniform(rng), 0x1.fffffep-1f);
        float prob = 0.f;
        const int pick = bvh.sample(ctx, u, true, prob);
        if (pick >= 0) {
            ++entries;
            ASSERT_EQ(prob, bvh.entry_pmf(ctx, pick, true)) << "entry " << pick;
        } else if (pick <= -2) {
            ASSERT_EQ(prob, bvh.infinite_pmf(true));
        }
        // Next-event estimation's whole-light choice against the emission weight's.
        float choice = 0.f;
        int triangle = -1;
        const int light = choices.sample(ctx, u, choice, triangle);
        if (light < 0) continue;
        Hit hit;
        if (triangle >= 0) {
            // The scene triangle of the light's triangle `triangle`.
            int k = 0;
            for (std::size_t t = 0; t < scene.triangles.size(); ++t)
                if (scene.triangles[t].light == light && k++ == triangle) hit.prim = PrimId(ShapeKind::triangle, t);
            ++triangles;
        }
        ASSERT_EQ(choice, choices.probability(ctx, light, &hit)) << "light " << light << " triangle " << triangle;
    }
    EXPECT_GT(entries, 5000);  // two thirds go to the infinite share (the environment, the plane)
    EXPECT_GT(triangles, 100);
}

TEST(LightBvh, SampledFrequenciesMatchThePmf) {
    const Scene scene = many_lights_scene(true);
    const LightBvh& bvh = scene.light_bvh;
    const std::size_t n = bvh.entries().size(), n_inf = bvh.infinite_count(true);
    const LightSampleContext points[] = {
        {{0, 0, 0}, {}, {0, 1, 0}, {0, 1, 0}, false},
        {{0.5f, -0.9f, -0.5f}, {}, {0, 1, 0}, {0, 1, 0}, false},
        {{-0.9f, 0.9f, 0.9f}, {}, {1, 0, 0}, {1, 0, 0}, false},
    };
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<float> uniform(0.f, 1.f);
    constexpr int kSamples = 400000;
    for (const LightSampleContext& ctx : points) {
        std::vector<double> observed(n + n_inf + 1, 0.0), expected(n + n_inf + 1, 0.0);
        for (int i = 0; i < kSamples; ++i) {
            float prob;
            const int pick = bvh.sample(ctx, std::min(uniform(rng), 0x1.fffffep-1f), true, prob);
            observed[pick >= 0 ? static_cast<std::size_t>(pick) : pick == -1 ? n + n_inf : n + static_cast<std::size_t>(-2 - pick)] += 1;
        }
        double total = 0;
        for (std::size_t e = 0; e < n; ++e) total += expected[e] = kSamples * double(bvh.entry_pmf(ctx, int(e), true));
        for (std::size_t k = 0; k < n_inf; ++k) total += expected[n + k] = kSamples * double(bvh.infinite_pmf(true));
        expected[n + n_inf] = std::max(0.0, kSamples - total);  // no sample (nothing lights the point)
        const spt_test::Chi2Result r = spt_test::chi2_test(observed, expected);
        EXPECT_EQ(r.observed_in_empty, 0.0);
        EXPECT_GT(r.p_value, 1e-3) << "chi2 " << r.statistic << " dof " << r.dof;
    }
}

TEST(LightBvh, NoLightThatCanContributeGetsImportanceZero) {
    // A one-sided unit quad at the origin facing +y.
    LightBounds quad = flat_light_bounds({{-0.5f, 0, -0.5f}, {0.5f, 0, 0.5f}}, 1.f, {0, 1, 0}, false);
    // Far away, barely above its plane (it sends light there at a grazing angle), seen by a
    // surface facing it, and by one whose normal lies almost along the plane.
    EXPECT_GT(light_importance(quad, {10, 1e-3f, 0}, {-1, 0, 0}), 0.f);
    EXPECT_GT(light_importance(quad, {10, 1e-3f, 0}, {0, 1, 0}), 0.f);
    EXPECT_GT(light_importance(quad, {0.4f, 1e-6f, 0.4f}, {0, -1, 0}), 0.f);  // just above its surface
    // Behind it nothing arrives; a two-sided quad lights that side too.
    EXPECT_EQ(light_importance(quad, {0, -1, 0}, {0, 1, 0}), 0.f);
    quad.two_sided = true;
    EXPECT_GT(light_importance(quad, {0, -1, 0}, {0, 1, 0}), 0.f);
    // A point inside a node's box (two quads facing each other) and without a normal (a medium).
    const LightBounds up = flat_light_bounds({{-1, -1, -1}, {1, -1, 1}}, 1.f, {0, 1, 0}, false);
    const LightBounds down = flat_light_bounds({{-1, 1, -1}, {1, 1, 1}}, 1.f, {0, -1, 0}, false);
    const LightBounds node = light_bounds_union(up, down);
    EXPECT_GT(light_importance(node, {0, 0, 0}, {1, 0, 0}), 0.f);
    EXPECT_GT(light_importance(node, {0.9f, 0.99f, 0.9f}, {}), 0.f);
    // A point light lights everything around it.
    PointLight point;
    point.position = {0, 2, 0};
    point.intensity = test::constant_spectrum(1.0);
    const LightBounds pb = *light_bounds(Light{point}, light_power(Light{point}));
    EXPECT_GT(light_importance(pb, {5, 0, 0}, {0, 1, 0}), 0.f);
    EXPECT_GT(light_importance(pb, {0, 2.0001f, 0}, {0, -1, 0}), 0.f);
    // A spot light: inside its full cone (also in the fade beyond the falloff angle), not outside.
    SpotLight spot;
    spot.position = {0, 2, 0};
    spot.direction = {0, -1, 0};
    spot.cos_cone = std::cos(0.5f);
    spot.cos_falloff = std::cos(0.3f);
    spot.intensity = test::constant_spectrum(1.0);
    const LightBounds sb = *light_bounds(Light{spot}, light_power(Light{spot}));
    for (float angle : {0.f, 0.29f, 0.31f, 0.45f, 0.499f}) {
        const Vec3 p{2.f * std::tan(angle), 0.f, 0.f};
        EXPECT_GT(light_importance(sb, p, {0, 1, 0}), 0.f) << "angle " << angle;
        EXPECT_GT(spot.falloff(normalize(p - spot.position)), 0.f) << "angle " << angle;  // it does light p
    }
    EXPECT_EQ(light_importance(sb, {2.f * std::tan(0.6f), 0, 0}, {0, 1, 0}), 0.f);
}

TEST(LightBvh, EveryLightThatSendsAPointLightHasProbabilityAboveZeroThere) {
    // Brute force over the scene's emitters: where a point on the light emits towards the
    // shading point, and the shading normal does not stand exactly perpendicular, the BVH
    // must be able to choose that light (its triangle).
    const Scene scene = many_lights_scene(false);
    const LightBvh& bvh = scene.light_bvh;
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<float> uniform(0.f, 1.f);
    const SampledWavelengths lambda = SampledWavelengths::sample(0.5f);
    int checked = 0;
    for (int i = 0; i < 300; ++i) {
        const LightSampleContext ctx = random_context(rng);
        for (std::size_t e = 0; e < bvh.entries().size(); ++e) {
            const LightBvh::Entry& entry = bvh.entries()[e];
            const Light& light = scene.lights[static_cast<std::size_t>(entry.light)];
            bool reaches = false;
            for (int s = 0; s < 16 && !reaches; ++s) {
                LightSample ls;
                if (!light_sample_li_on(light, entry.triangle, ctx, lambda, uniform(rng), uniform(rng), ls)) continue;
                reaches = !ls.L.is_zero() && ls.pdf > 0.f && std::fabs(dot(ls.wi, ctx.ns)) > 1e-3f;
            }
            if (!reaches) continue;
            ++checked;
            EXPECT_GT(bvh.entry_pmf(ctx, static_cast<int>(e), false), 0.f) << "entry " << e << " at point " << i;
        }
    }
    EXPECT_GT(checked, 10000);
}

TEST(LightBvh, ImageAgreesWithPowerSelection) {
    const Scene scene = many_lights_scene(true);
    RenderSettings rs = test::small_settings(24, 24, 512, 21);
    const auto power = test::render_film(scene, rs);
    rs.integrator.light_selection = LightSelection::bvh;
    rs.seed = 22;
    const auto bvh = test::render_film(scene, rs);
    const test::Comparison c = test::compare(*power, *bvh, [](int, int) { return true; });
    EXPECT_LT(c.max_z, 5.0) << test::describe(c);
    EXPECT_LT(std::fabs(c.mean_a - c.mean_b), 4.0 * c.se) << test::describe(c);
    EXPECT_EQ(test::count_bad_pixels(*bvh), 0);
}

TEST(LightBvh, LightSamplingAloneAgreesWithPowerSelection) {
    // Without MIS each light is found by its light samples only: a light the BVH gave
    // probability 0 where it shines would leave its light missing from the image.
    const Scene scene = many_lights_scene(false);
    RenderSettings rs = test::small_settings(24, 24, 512, 31);
    rs.integrator.light_sampling = LightSampling::light;
    const auto power = test::render_film(scene, rs);
    rs.integrator.light_selection = LightSelection::bvh;
    rs.seed = 32;
    const auto bvh = test::render_film(scene, rs);
    const test::Comparison c = test::compare(*power, *bvh, [](int, int) { return true; });
    EXPECT_LT(c.max_z, 5.0) << test::describe(c);
    EXPECT_LT(std::fabs(c.mean_a - c.mean_b), 4.0 * c.se) << test::describe(c);
}

TEST(LightBvh, WavefrontRendersTheSameChoices) {
    const Scene scene = many_lights_scene(true);
    RenderSettings rs = test::small_settings(16, 16, 8, 41);
    rs.integrator.light_selection = LightSelection::bvh;
    rs.integrator.caustic_nee = false;
    const auto tiles = test::render_film(scene, rs);
    rs.schedule = Schedule::wavefront;
    EXPECT_EQ(test::count_differences(*tiles, *test::render_film(scene, rs)), 0u);
}

TEST(LightBvh, OneLightRendersAsByPower) {
    // One light to choose: the BVH is not consulted, the film is the same bit for bit.
    const Scene scene = test::load_exact_scene(R"({
  "camera": {"position": [0, 0, 3.5], "look_at": [0, 0, 0], "up": [0, 1, 0], "vfov_degrees": 40},
  "materials": {"gray": {"kd": 0.6}},
  "shapes": [
    {"type": "quad", "origin": [-1, -1, -1], "edge1": [2, 0, 0], "edge2": [0, 2, 0], "material": "gray"},
    {"type": "mesh", "positions": [-0.2, 0.9, -0.2, 0.2, 0.9, -0.2, 0.2, 0.9, 0.2, -0.2, 0.9, 0.2],
     "indices": [0, 1, 2, 0, 2, 3], "emission": 5}
  ]
})",
                                               "one-light");
    RenderSettings rs = test::small_settings(16, 16, 16, 51);
    const auto power = test::render_film(scene, rs);
    rs.integrator.light_selection = LightSelection::bvh;
    EXPECT_EQ(test::count_differences(*power, *test::render_film(scene, rs)), 0u);
}

}  // namespace

// Emission textures on triangles and meshes: a light point sampled for next-event estimation
// or a light subpath reads the texture at its triangle's (u, v) (the PLY's u, v / s, t, or
// the barycentrics (b1, b2)), exactly as a path that hits that point does.
//   - A mesh and a triangle emitting a texture of one value render bit for bit as the same
//     emitters given that value as a constant, with every integrator.
//   - A light sample's point and the hit of a ray towards it read the same texel.
//   - A triangle emitting a checkerboard (cells of radiance 1 and 4 over its barycentric
//     square) lights a point of a white floor: the irradiance is that of the even region
//     (a quadrilateral) plus that of the odd one (the triangle minus it), each from Lambert's
//     polygon formula. Light sampling alone, BSDF sampling alone, MIS and bdpt must each
//     find it. Planted bug: the light's mean radiance (Le, the selection power) read at
//     light samples instead of the texture: light sampling (and MIS) miss it by far more
//     than the tolerance (the point lies under the dim region).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "test_scenes.h"

namespace spt {
namespace {

/// The triangle (−1, 1, −1), (1, 1, −1), (−1, 1, 1) (facing down onto the floor y = 0) as an
/// ASCII PLY with s, t per vertex: (0, 0), (2, 0), (0, 2), twice the barycentrics, so a
/// texture at uv_scale 1 sees what the triangle shape's barycentric (u, v) gives at scale 2.
const char* kTrianglePly =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "property float s\nproperty float t\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
    "-1 1 -1 0 0\n1 1 -1 2 0\n-1 1 1 0 2\n3 0 1 2\n";

/// The scene `text` whose meshes read `ply`, at `resolution` (exact spectra by default).
Scene load_with_ply(const std::string& text, const std::string& ply,
                    SpectralResolution resolution = SpectralResolution{SpectralResolution::kExact}) {
    const RelativeFileReader reader = [&](const std::string&, std::string& contents, std::string& display,
                                          std::string&) {
        contents = ply;
        display = "t.ply";
        return true;
    };
    return load_scene_text(text, "m.json", "m", resolution, reader);
}

/// Irradiance at x (floor normal +y) from a polygon of unit radiance (Lambert: E = ½ Σ θ_i
/// n·ĉ_i over its edges, θ_i the angle the edge subtends and ĉ_i the unit normal of the
/// plane through x and the edge).
double polygon_irradiance(const std::vector<std::array<double, 3>>& poly, const std::array<double, 3>& x) {
    double sum = 0;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const auto& a = poly[i];
        const auto& b = poly[(i + 1) % poly.size()];
        double ra[3], rb[3];
        for (int k = 0; k < 3; ++k) ra[k] = a[k] - x[k], rb[k] = b[k] - x[k];
        const double la = std::sqrt(ra[0] * ra[0] + ra[1] * ra[1] + ra[2] * ra[2]);
        const double lb = std::sqrt(rb[0] * rb[0] + rb[1] * rb[1] + rb[2] * rb[2]);
        const double c[3] = {ra[1] * rb[2] - ra[2] * rb[1], ra[2] * rb[0] - ra[0] * rb[2], ra[0] * rb[1] - ra[1] * rb[0]};
        const double lc = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        const double theta = std::acos(std::clamp((ra[0] * rb[0] + ra[1] * rb[1] + ra[2] * rb[2]) / (la * lb), -1.0, 1.0));
        sum += 0.5 * theta * c[1] / lc;  // n = +y
    }
    return std::fabs(sum);
}

/// A white-ish floor (kd 0.5) under the emitter `emitter` (a shape's JSON), seen over a
/// footprint of a few thousandths around (−0.5, 0, −0.5) by a camera between them.
std::string irradiance_scene(const std::string& emitter) {
    return R"({"camera": {"position": [-0.5, 0.5, -0.5], "look_at": [-0.5, 0, -0.5], "up": [0, 0, -1], "vfov_degrees": 0.5},
      "textures": {"c": {"type": "checkerboard", "even": 1, "odd": 4, "uv_scale": [2, 2]},
                   "c1": {"type": "checkerboard", "even": 1, "odd": 4}},
      "materials": {"floor": {"kd": 0.5}},
      "shapes": [{"type": "quad", "origin": [-3, 0, 3], "edge1": [6, 0, 0], "edge2": [0, 0, -6], "material": "floor"},
        )" + emitter + "]}";
}

TEST(MeshEmissionTexture, CheckerboardTriangleLightsTheFloorWithItsTwoRegions) {
    // Barycentric square u = b1 < ½, v = b2 < ½ (even, radiance 1): the quadrilateral
    // p0, (p0 + p1)/2, (p1 + p2)/2, (p0 + p2)/2; the rest of the triangle is odd (4).
    const std::array<double, 3> x{-0.5, 0.0, -0.5};
    const double e_even = polygon_irradiance({{-1, 1, -1}, {0, 1, -1}, {0, 1, 0}, {-1, 1, 0}}, x);
    const double e_all = polygon_irradiance({{-1, 1, -1}, {1, 1, -1}, {-1, 1, 1}}, x);
    const double expected = 0.5 / std::numbers::pi * (1.0 * e_even + 4.0 * (e_all - e_even));
    const double with_mean = 0.5 / std::numbers::pi * 2.5 * e_all;  // the planted bug's answer
    std::printf("[mesh emission] E even %.5f, E triangle %.5f: floor radiance %.5f (mean radiance would give %.5f)\n",
                e_even, e_all, expected, with_mean);
    ASSERT_GT(std::fabs(with_mean - expected), 0.1 * expected);

    const std::string shapes[] = {
        R"({"type": "triangle", "vertices": [[-1, 1, -1], [1, 1, -1], [-1, 1, 1]], "emission": {"texture": "c"}})",
        R"({"type": "mesh", "file": "t.ply", "emission": {"texture": "c1"}})",
    };
    for (const std::string& shape : shapes) {
        const Scene scene = load_with_ply(irradiance_scene(shape), kTrianglePly);
        ASSERT_TRUE(scene.effects.textures);
        struct Mode {
            const char* name;
            IntegratorKind kind;
            LightSampling sampling;
        };
        for (const Mode& m : {Mode{"path mis", IntegratorKind::path, LightSampling::mis},
                              Mode{"path light", IntegratorKind::path, LightSampling::light},
                              Mode{"path bsdf", IntegratorKind::path, LightSampling::bsdf},
                              Mode{"bdpt", IntegratorKind::bdpt, LightSampling::mis}}) {
            RenderSettings rs = test::small_settings(8, 8, 256, 5);
            rs.integrator.kind = m.kind;
            rs.integrator.light_sampling = m.sampling;
            const test::ImageMean got = test::image_mean_y(*test::render_film(scene, rs));
            std::printf("[mesh emission] %s, %s: %.5f ± %.5f\n", shape.substr(9, 8).c_str(), m.name, got.mean,
                        got.standard_error);
            // 5σ, plus 0.1 % for the footprint (E varies by far less over 0.004 units).
            EXPECT_NEAR(got.mean, expected, 5 * got.standard_error + 1e-3 * expected) << shape << ", " << m.name;
        }
    }
}

TEST(MeshEmissionTexture, LightSamplesAndHitsReadTheSameTexel) {
    // Light points sampled from a floor point; a ray from there towards each finds the light
    // at (nearly) that point: both read the texture at the triangle's (u, v) of their point.
    for (const char* name : {"c", "c1"}) {
        const bool mesh = std::string(name) == "c1";
        const std::string shape =
            mesh ? R"({"type": "mesh", "file": "t.ply", "emission": {"texture": "c1"}})"
                 : R"({"type": "triangle", "vertices": [[-1, 1, -1], [1, 1, -1], [-1, 1, 1]], "emission": {"texture": "c"}})";
        const Scene scene = load_with_ply(irradiance_scene(shape), kTrianglePly);
        int light = -1;
        for (std::size_t i = 0; i < scene.lights.size(); ++i)
            if (std::holds_alternative<TriangleMeshLight>(scene.lights[i])) light = static_cast<int>(i);
        ASSERT_GE(light, 0);
        ASSERT_TRUE(scene.light_textured(light));
        const SampledWavelengths lambda = SampledWavelengths::sample(0.4f);
        const LightSampleContext ctx{{0.3f, 0.01f, 0.2f}, {}, {0, 1, 0}, {0, 1, 0}, false};
        int same = 0, bright = 0, total = 0;
        for (int i = 0; i < 64; ++i)
            for (int j = 0; j < 64; ++j) {
                const auto ls = light_sample_li(scene.lights[light], ctx, lambda, (i + 0.5f) / 64, (j + 0.5f) / 64);
                ASSERT_TRUE(ls.has_value());
                const SampledSpectrum at_sample = scene.light_point_emission(light, ls->p, ls->triangle, lambda);
                const std::optional<Hit> hit = scene.intersect(Ray{ctx.p, ls->wi, kInfinity});
                ASSERT_TRUE(hit.has_value());
                ASSERT_EQ(hit->light, light);
                const SampledSpectrum at_hit = scene.emitted<true>(*hit, -ls->wi, lambda);
                ++total;
                same += at_sample[0] == at_hit[0];
                bright += at_sample[0] > 2.f;
            }
        // Only points within rounding of a cell edge may read the neighbour cell.
        EXPECT_GE(same, total - total / 100) << name;
        // Both cells are sampled in proportion to their area (half of the triangle each).
        EXPECT_NEAR(bright, total / 2, total / 20) << name;
    }
}

TEST(MeshEmissionTexture, AConstantTextureOnAMeshRendersAsTheConstant) {
    // A floor lit by an emitting mesh (with s, t) and an emitting triangle (barycentric
    // (u, v)): textures of one spectrum render bit for bit as that spectrum, with every
    // integrator (same bins, weight exactly 1, same light choice: the texture's mean is the
    // constant).
    const std::string value = R"({"type": "blackbody", "temperature_k": 4000, "scale": 3})";
    auto scene = [&](const std::string& emission) {
        return R"({"camera": {"position": [0, 2.5, 3], "look_at": [0, 0, 0]},
          "textures": {"c": {"type": "checkerboard", "even": )" + value + R"(, "odd": )" + value + R"(, "uv_scale": [3, 3]}},
          "materials": {"floor": {"kd": 0.6}},
          "shapes": [{"type": "quad", "origin": [-3, 0, 3], "edge1": [6, 0, 0], "edge2": [0, 0, -6], "material": "floor"},
            {"type": "mesh", "file": "t.ply", "emission": )" + emission + R"(},
            {"type": "triangle", "vertices": [[1, 0.5, 0], [2, 0.5, 0], [1, 1.2, -0.5]], "emission": )" + emission +
               R"(},
            {"type": "sphere", "center": [0.5, 0.3, 0.5], "radius": 0.3, "material": "floor"}]})";
    };
    // Binned spectra (the default): texture values are kept as those bins (in exact mode the
    // constant would be evaluated exactly and the texture at 1 nm bins).
    const Scene textured = load_with_ply(scene(R"({"texture": "c"})"), kTrianglePly, SpectralResolution{});
    const Scene constant = load_with_ply(scene(value), kTrianglePly, SpectralResolution{});
    ASSERT_TRUE(textured.effects.textures);
    ASSERT_FALSE(constant.effects.textures);
    for (const IntegratorKind kind : {IntegratorKind::path, IntegratorKind::bdpt, IntegratorKind::vcm}) {
        RenderSettings rs = test::small_settings(24, 16, 8);
        rs.integrator.kind = kind;
        const auto a = test::render_film(textured, rs), b = test::render_film(constant, rs);
        EXPECT_EQ(test::count_differences(*a, *b), 0u) << integrator_name(kind);
        EXPECT_GT(test::image_mean_y(*b).mean, 0.01) << integrator_name(kind);  // not two black images
    }
}

}  // namespace
}  // namespace spt

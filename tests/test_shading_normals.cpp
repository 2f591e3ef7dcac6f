// Smooth shading: PLY vertex normals are read, follow the mesh's transform as normals do,
// are interpolated at each hit (Hit::ns, on the geometric normal's side), and give a coarse
// mesh sphere the shading of the true sphere; bidirectional transport (importance, with
// Veach's shading-normal correction) agrees with path tracing on such a mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <utility>
#include <sstream>
#include <string>

#include "io/ply_reader.h"
#include "scene/scene_loader.h"
#include "test_scenes.h"

namespace {

using namespace spt;
using spt::test::compare;
using spt::test::render_film;
using spt::test::small_settings;

/// An ASCII PLY of a UV sphere of radius 1 at the origin (n_theta bands of quads), with radial
/// vertex normals when `normals` is set.
std::string uv_sphere_ply(int n_phi, int n_theta, bool normals) {
    std::ostringstream v, f;
    int vertices = 0, faces = 0;
    for (int j = 0; j <= n_theta; ++j)
        for (int i = 0; i < n_phi; ++i, ++vertices) {
            const double th = std::numbers::pi * j / n_theta, ph = 2 * std::numbers::pi * i / n_phi;
            const double x = std::sin(th) * std::cos(ph), y = std::cos(th), z = std::sin(th) * std::sin(ph);
            v << x << ' ' << y << ' ' << z;
            if (normals) v << ' ' << x << ' ' << y << ' ' << z;
            v << '\n';
        }
    for (int j = 0; j < n_theta; ++j)
        for (int i = 0; i < n_phi; ++i, ++faces) {
            const int a = j * n_phi + i, b = j * n_phi + (i + 1) % n_phi;
            f << "4 " << a << ' ' << a + n_phi << ' ' << b + n_phi << ' ' << b << '\n';
        }
    std::ostringstream ply;
    ply << "ply\nformat ascii 1.0\nelement vertex " << vertices
        << "\nproperty float x\nproperty float y\nproperty float z\n";
    if (normals) ply << "property float nx\nproperty float ny\nproperty float nz\n";
    ply << "element face " << faces << "\nproperty list uchar int vertex_indices\nend_header\n" << v.str() << f.str();
    return ply.str();
}

/// The mesh sphere (optionally scaled) lit by a point light, in a scene file read from text.
Scene mesh_sphere_scene(bool normals, const std::string& transform = "", const std::string& extra_shapes = "") {
    const std::string ply = uv_sphere_ply(16, 8, normals);
    const std::string text = R"({"camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "vfov_degrees": 1e-3},
      "materials": {"white": {"kd": 0.8}},
      "shapes": [{"type": "mesh", "file": "sphere.ply", "material": "white")" + transform + "}" + extra_shapes + R"(],
      "lights": [{"type": "point", "position": [3, 2, 4], "intensity": 10}]})";
    const RelativeFileReader reader = [&](const std::string&, std::string& contents, std::string& display, std::string&) {
        contents = ply;
        display = "sphere.ply";
        return true;
    };
    return load_scene_text(text, "smooth.json", "smooth", {}, reader);
}

TEST(ShadingNormals, PlyNormalsAndUvAreRead) {
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\nproperty float s\nproperty float t\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0 0 0 1 0 0\n1 0 0 0.6 0 0.8 1 0\n0 1 0 0 0.6 0.8 0 1\n3 0 1 2\n";
    const PlyMesh mesh = parse_ply(ply, "t.ply");
    ASSERT_EQ(mesh.normals.size(), 3u);
    ASSERT_EQ(mesh.uvs.size(), 3u);
    EXPECT_EQ(mesh.normals[1], Vec3(0.6f, 0.f, 0.8f));
    EXPECT_EQ(mesh.uvs[2][1], 1.f);
}

TEST(SurfaceUv, EveryShapeReportsItsCoordinatesAtAHit) {
    // Scene::surface_uv from the hit's primitive and point: a sphere's (φ/2π, θ/π) about +y,
    // a disk's (φ/2π, ρ/r), a plane's tangent coordinates, a mesh's interpolated vertex uv.
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "property float u\nproperty float v\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "10 0 0 0.2 0.4\n12 0 0 0.6 0.4\n10 2 0 0.2 0.8\n3 0 1 2\n";
    const std::string text = R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
      "materials": {"m": {"kd": 0.5}},
      "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"},
        {"type": "disk", "center": [5, 0, 0], "normal": [0, 0, 1], "radius": 2, "material": "m"},
        {"type": "plane", "normal": [0, 0, 1], "point": [0, 0, -50], "material": "m"},
        {"type": "mesh", "file": "t.ply", "material": "m"}]})";
    const RelativeFileReader reader = [&](const std::string&, std::string& contents, std::string& display, std::string&) {
        contents = ply;
        display = "t.ply";
        return true;
    };
    const Scene scene = load_scene_text(text, "uv.json", "uv", {}, reader);
    auto uv_at = [&](const Vec3& o, const Vec3& d, ShapeKind kind) {
        const std::optional<Hit> hit = scene.intersect({o, normalize(d), kInfinity});
        EXPECT_TRUE(hit && hit->prim.kind() == kind);
        float u = -1, v = -1;
        if (hit) scene.surface_uv(*hit, u, v);
        return std::pair{u, v};
    };
    // Sphere, hit at (0, 0, 1) from +z: θ = 90° from +y (v = 1/2); φ = atan2(z, x) = 90°.
    const auto [su, sv] = uv_at({0, 0, 5}, {0, 0, -1}, ShapeKind::sphere);
    EXPECT_NEAR(sv, 0.5f, 1e-6f);
    EXPECT_NEAR(std::fabs(su - 0.5f), 0.25f, 1e-6f);  // a quarter turn from φ = 0 (u = 1/2 ± 1/4)
    // Disk of radius 2 at (5, 0, 0), hit 1 from its centre: ρ/r = 1/2.
    EXPECT_NEAR(uv_at({6, 0, 5}, {0, 0, -1}, ShapeKind::disk).second, 0.5f, 1e-5f);
    // The mesh triangle, hit at its vertex-weighted point (b = 1/4, 1/4, 1/2): uv interpolated.
    const auto [mu, mv] = uv_at({10.5f, 1.f, 5}, {0, 0, -1}, ShapeKind::triangle);
    EXPECT_NEAR(mu, 0.25f * 0.2f + 0.25f * 0.6f + 0.5f * 0.2f, 1e-5f);
    EXPECT_NEAR(mv, 0.25f * 0.4f + 0.25f * 0.4f + 0.5f * 0.8f, 1e-5f);
    // The plane: coordinates along its tangents, so two hits 3 apart are 3 apart in (u, v).
    const auto [pu0, pv0] = uv_at({-20, 20, 0}, {0, 0, -1}, ShapeKind::plane);
    const auto [pu1, pv1] = uv_at({-17, 20, 0}, {0, 0, -1}, ShapeKind::plane);
    EXPECT_NEAR(std::hypot(pu1 - pu0, pv1 - pv0), 3.f, 1e-4f);
}

TEST(ShadingNormals, HitCarriesTheInterpolatedNormalOnTheGeometricSide) {
    const Scene scene = mesh_sphere_scene(true);
    EXPECT_TRUE(scene.effects.shading_normals);
    // A ray towards the origin from many directions: on a sphere with radial vertex normals
    // the shading normal is close to the radial direction, closer than the facet's normal.
    int closer = 0, strictly_closer = 0, rays = 0;
    for (int k = 0; k < 200; ++k) {
        const double z = 1 - 2 * (k + 0.5) / 200, phi = 2.399963 * k, r = std::sqrt(1 - z * z);
        const Vec3 o(float(3 * r * std::cos(phi)), float(3 * z), float(3 * r * std::sin(phi)));
        const std::optional<Hit> hit = scene.intersect({o, normalize(-o), kInfinity});
        ASSERT_TRUE(hit.has_value());
        ++rays;
        const Vec3 radial = face_forward(normalize(hit->p), hit->n);  // on the side of n, as ns is
        EXPECT_NEAR(length(hit->ns), 1.f, 1e-5f);
        EXPECT_GT(dot(hit->ns, hit->n), 0.f);
        closer += dot(hit->ns, radial) >= dot(hit->n, radial) - 1e-6f;
        strictly_closer += dot(hit->ns, radial) > dot(hit->n, radial) + 1e-4f;
    }
    EXPECT_EQ(closer, rays);
    EXPECT_GT(strictly_closer, rays / 2);  // the facets' normals are off by up to 11°
    EXPECT_FALSE(mesh_sphere_scene(false).effects.shading_normals);
}

TEST(ShadingNormals, NormalsFollowTheTransformsInverseTranspose) {
    // Squashed to the ellipsoid x²/4 + y² + z² = 1. The vertex at θ = 45°, φ = 0 of the unit
    // sphere, (sin 45°, cos 45°, 0), moves to (2 sin 45°, cos 45°, 0), where the ellipsoid's
    // normal is ∝ (x/4, y, 0) = (sin 45°/2, cos 45°, 0): the inverse transpose of the scale.
    // Transforming the normal like a point would give (2 sin 45°, cos 45°, 0).
    const Scene scene = mesh_sphere_scene(true, R"(, "transform": {"scale": [2, 1, 1]})");
    const float s45 = std::sin(0.7853982f), c45 = std::cos(0.7853982f);
    auto has_normal = [&](const Vec3& expected) {
        for (const TriangleAttributes& a : scene.triangle_attributes)
            for (const Vec3& n : a.n)
                if (length(n - expected) < 1e-4f) return true;
        return false;
    };
    EXPECT_TRUE(has_normal(normalize(Vec3(s45 / 2.f, c45, 0.f))));
    EXPECT_FALSE(has_normal(normalize(Vec3(2.f * s45, c45, 0.f))));
}

/// Radiance of the pixel at the image centre, looking at the point of the unit sphere facing
/// the camera at (0, 0, 4): the true sphere's value is (ρ/π)·I·cos θ/r².
double centre_radiance(const Scene& scene) {
    const auto film = render_film(scene, small_settings(4, 4, 256));
    return film->pixel_xyz(2, 2).y;
}

TEST(ShadingNormals, CoarseMeshShadesLikeTheTrueSphere) {
    // The camera sees the sphere's point (0, 0, 1), a vertex-free spot inside a facet whose
    // normal is off by several degrees; the light is at (3, 2, 4).
    const Vec3 p(0, 0, 1), light(3, 2, 4);
    const Vec3 to_light = light - p;
    const double r2 = length_squared(to_light), cos_t = dot(normalize(to_light), Vec3(0, 0, 1));
    const double exact = 0.8 / std::numbers::pi * 10 * cos_t / r2;
    const double smooth = centre_radiance(mesh_sphere_scene(true));
    const double flat = centre_radiance(mesh_sphere_scene(false));
    // The facets of a 16 × 8 sphere are ~11° wide: flat shading misses the cosine by ~10 %,
    // the interpolated normal by ~1 %.
    EXPECT_NEAR(smooth, exact, 0.02 * exact) << "flat: " << flat;
    EXPECT_GT(std::fabs(flat - exact), 3 * std::fabs(smooth - exact));
}

TEST(ShadingNormals, BidirectionalTransportAgreesWithPathTracing) {
    // A floor made of a mesh whose vertex normals all lean 40° towards +x (far from its true
    // normal, as bump-like shading does), under a small emitting sphere, next to a white wall:
    // light subpaths carry importance across the shading normals (with the adjoint's
    // correction |wo·ns||wi·ng| / (|wo·ng||wi·ns|)), camera paths carry radiance, and both
    // must give the same image.
    const float s40 = std::sin(0.6981317f), c40 = std::cos(0.6981317f);
    std::ostringstream ply;
    ply << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
           "property float nx\nproperty float ny\nproperty float nz\nelement face 1\n"
           "property list uchar int vertex_indices\nend_header\n";
    for (const char* corner : {"-2 0 -2", "-2 0 2", "2 0 2", "2 0 -2"}) ply << corner << ' ' << s40 << ' ' << c40 << " 0\n";
    ply << "4 0 1 2 3\n";
    const std::string text = R"({"camera": {"position": [0, 2.5, 3], "look_at": [0, 0, 0], "vfov_degrees": 50},
      "materials": {"white": {"kd": 0.8}},
      "shapes": [{"type": "mesh", "file": "floor.ply", "material": "white"},
        {"type": "plane", "normal": [1, 0, 0], "point": [-1.5, 0, 0], "material": "white"},
        {"type": "sphere", "center": [0.3, 1, 0], "radius": 0.15, "emission": 20}]})";
    const RelativeFileReader reader = [&](const std::string&, std::string& contents, std::string& display, std::string&) {
        contents = ply.str();
        display = "floor.ply";
        return true;
    };
    const Scene scene = load_scene_text(text, "tilted.json", "tilted", {}, reader);
    ASSERT_TRUE(scene.effects.shading_normals);
    const auto path = render_film(scene, small_settings(24, 24, 512));
    RenderSettings s = small_settings(24, 24, 512, 3);
    s.integrator.kind = IntegratorKind::bdpt;
    const auto bdpt = render_film(scene, s);
    const spt::test::Comparison c = compare(*path, *bdpt, [](int, int) { return true; });
    EXPECT_NEAR(c.mean_a, c.mean_b, 4 * c.se) << "path " << c.mean_a << " bdpt " << c.mean_b << " se " << c.se;
    EXPECT_LT(c.max_z, 5.0) << "worst pixel " << c.worst_x << ", " << c.worst_y;
}

}  // namespace

// Instanced meshes (scene key "instances", a two-level BVH): an instance is hit exactly where
// the same mesh transformed into the scene is (same rays hit, same t, point, normal and
// material, within float rounding); memory does not grow with the number of placements;
// rays leaving an instance do not hit it again at any scale (ROBUSTNESS.md §7 case 2 with
// transforms); and the loader's errors for the new key.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "core/frame.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "scene/scene_loader.h"

namespace spt {
namespace {

/// An ASCII PLY of a closed bumpy θφ sphere (radii jittered, so triangle sizes vary).
std::string bumpy_sphere_ply(int n_theta, int n_phi) {
    Rng rng(5, 0, 0);
    std::ostringstream v, f;
    int vertices = 0, faces = 0;
    auto vertex = [&](float x, float y, float z) { v << x << ' ' << y << ' ' << z << '\n', ++vertices; };
    vertex(0, 0, 1);
    for (int i = 1; i < n_theta; ++i)
        for (int j = 0; j < n_phi; ++j) {
            const float th = kPi * i / n_theta, ph = 2 * kPi * j / n_phi, r = 0.8f + 0.4f * rng.uniform();
            vertex(r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph), r * std::cos(th));
        }
    vertex(0, 0, -1);
    const int south = vertices - 1;
    auto ring = [n_phi](int i, int j) { return 1 + (i - 1) * n_phi + (j % n_phi); };
    auto face = [&](int a, int b, int c) { f << "3 " << a << ' ' << b << ' ' << c << '\n', ++faces; };
    for (int j = 0; j < n_phi; ++j) {
        face(0, ring(1, j), ring(1, j + 1));
        face(south, ring(n_theta - 1, j + 1), ring(n_theta - 1, j));
        for (int i = 1; i + 1 < n_theta; ++i) {
            face(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1));
            face(ring(i, j), ring(i + 1, j + 1), ring(i, j + 1));
        }
    }
    std::ostringstream ply;
    ply << "ply\nformat ascii 1.0\nelement vertex " << vertices << "\nproperty float x\nproperty float y\n"
        << "property float z\nelement face " << faces << "\nproperty list uchar int vertex_indices\nend_header\n"
        << v.str() << f.str();
    return ply.str();
}

/// Height of the tilted plane of flat_grid_ply (tilted so that its points' coordinates all
/// carry rounding error, as an axis-aligned plane's would not).
double grid_z(double x, double y) { return 0.37 * x + 0.61 * y + 0.2; }

/// A flat 8×8 grid of triangles over [−1, 1]² in the plane z = grid_z(x, y): any second hit
/// on it by a ray leaving it is a self-intersection.
std::string flat_grid_ply() {
    std::ostringstream ply;
    ply << "ply\nformat ascii 1.0\nelement vertex 81\nproperty float x\nproperty float y\nproperty float z\n"
        << "element face 128\nproperty list uchar int vertex_indices\nend_header\n";
    for (int i = 0; i <= 8; ++i)
        for (int j = 0; j <= 8; ++j) ply << (j / 4.0 - 1.0) << ' ' << (i / 4.0 - 1.0) << ' ' << grid_z(j / 4.0 - 1.0, i / 4.0 - 1.0) << '\n';
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j) {
            const int a = i * 9 + j;
            ply << "3 " << a << ' ' << a + 1 << ' ' << a + 10 << "\n3 " << a << ' ' << a + 10 << ' ' << a + 9 << '\n';
        }
    return ply.str();
}

/// Loads a scene whose shapes are `shapes` (JSON), with "m.ply" served from `ply`.
Scene load_with_mesh(const std::string& shapes, const std::string& ply) {
    const RelativeFileReader reader = [ply](const std::string& path, std::string& contents, std::string& display,
                                            std::string& why) {
        if (path != "m.ply") return why = "no such file", false;
        contents = ply, display = path;
        return true;
    };
    const std::string text = "{\"camera\": {\"position\": [0, 0, 50], \"look_at\": [0, 0, 0]},\n"
                             "\"materials\": {\"m\": {\"kd\": 0.5}, \"n\": {\"kd\": 0.3}},\n\"shapes\": [" +
                             shapes + "]}";
    return load_scene_text(text, "s.json", "s", SpectralResolution{SpectralResolution::kExact}, reader);
}

std::string load_error(const std::string& shapes) {
    try {
        load_with_mesh(shapes, flat_grid_ply());
    } catch (const std::exception& e) {
        return e.what();
    }
    return "(no error)";
}

const char* const kTransforms[] = {
    R"({"scale": [2, 0.5, 1.5], "rotate": {"axis": [1, 2, 3], "degrees": 37}, "translate": [0.3, -0.2, 0.1]})",
    R"({"scale": -1.25, "rotate": {"axis": [0, 1, 0], "degrees": 90}, "translate": [-3, 1, 2]})",  // mirroring
    R"({"scale": 1000, "rotate": {"axis": [1, 0, 0], "degrees": -20}, "translate": [4000, 0, -1000]})",
};

TEST(Instancing, InstanceIsHitExactlyWhereTheTransformedMeshIs) {
    const std::string ply = bumpy_sphere_ply(12, 16);
    for (const char* transform : kTransforms) {
        SCOPED_TRACE(transform);
        const Scene flat = load_with_mesh(
            std::string(R"({"type": "mesh", "file": "m.ply", "material": "n", "transform": )") + transform + "}", ply);
        const Scene inst = load_with_mesh(
            std::string(R"({"type": "mesh", "file": "m.ply", "material": "n", "instances": [)") + transform + "]}", ply);
        ASSERT_TRUE(inst.triangles.empty());
        ASSERT_EQ(inst.instances.size(), 1u);
        ASSERT_EQ(inst.instanced_meshes.size(), 1u);
        ASSERT_EQ(inst.instanced_meshes[0].triangles.size(), flat.triangles.size());
        // Rays from a sphere around the object towards random points of its box.
        Aabb box;
        for (const Triangle& t : flat.triangles) box.expand(bounds(t));
        const Vec3 centre = box.centroid();
        const float radius = length(box.hi - box.lo);
        Rng rng(9, 0, 0);
        // The ray mapped into object space is rounded there: a ray perturbed by an ulp. Where
        // the ray grazes the surface or passes within an ulp of an edge or the silhouette, that
        // moves the hit a long way, to a neighbour, or off the mesh: such rays may differ (a
        // handful in 20,000); every other must agree within the points' error bounds.
        int hits = 0, differing = 0;
        for (int k = 0; k < 20000; ++k) {
            const Vec3 o = centre + sample_uniform_sphere(rng.uniform(), rng.uniform()) * radius;
            const Vec3 e = box.hi - box.lo;
            const Vec3 target = box.lo + Vec3(rng.uniform() * e.x, rng.uniform() * e.y, rng.uniform() * e.z);
            const Ray ray{o, normalize(target - o), kInfinity};
            const auto a = flat.intersect(ray), b = inst.intersect(ray);
            if (a.has_value() != b.has_value() || flat.occluded(ray) != inst.occluded(ray)) {
                ++differing;
                continue;
            }
            if (!a) continue;
            ++hits;
            EXPECT_EQ(a->material, b->material);
            EXPECT_EQ(b->light, -1);
            // Besides the points' error bounds: the flattened mesh's vertices are rounded after
            // the transform, and the instance's ray is rounded in object space; either moves the
            // hit by an ulp or two of the coordinates, divided by the cosine along the surface.
            const float cos = std::max(std::fabs(dot(ray.d, a->n)), 0.05f);
            const float slack = 8.f * 0x1p-24f * (std::max({std::fabs(a->p.x), std::fabs(a->p.y), std::fabs(a->p.z)}) + a->t) / cos;
            bool same = std::fabs(a->t - b->t) <= 1e-5f * a->t && dot(a->n, b->n) > 1.f - 1e-5f;
            for (int i = 0; i < 3; ++i)
                same &= std::fabs(a->p[i] - b->p[i]) <= a->p_err[i] + b->p_err[i] + slack && b->p_err[i] >= 0.f;
            if (!same) ++differing;
        }
        EXPECT_LE(differing, 10);
        EXPECT_GT(hits, 5000);
    }
}

TEST(Instancing, MemoryDoesNotGrowWithTheInstanceCount) {
    const std::string ply = bumpy_sphere_ply(24, 48);  // about 2,300 triangles
    auto scene_with = [&](int count) {
        std::string list;
        for (int i = 0; i < count; ++i)
            list += std::string(i ? ", " : "") + "{\"translate\": [" + std::to_string(3 * (i % 40)) + ", " +
                    std::to_string(3 * (i / 40)) + ", 0]}";
        return load_with_mesh(R"({"type": "mesh", "file": "m.ply", "material": "m", "instances": [)" + list + "]}", ply);
    };
    const Scene one = scene_with(1), many = scene_with(1000);
    ASSERT_EQ(many.instances.size(), 1000u);
    EXPECT_EQ(many.instanced_meshes.size(), 1u);
    EXPECT_EQ(many.instanced_meshes[0].triangles.size(), one.instanced_meshes[0].triangles.size());
    EXPECT_TRUE(many.triangles.empty());
    // One copy of the mesh (triangles and tree) against what each further instance costs.
    const std::size_t mesh_bytes = one.instanced_meshes[0].triangles.size() * sizeof(Triangle) +
                                   one.instanced_meshes[0].bvh.memory_bytes();
    const double per_instance = double(many.geometry_bytes() - one.geometry_bytes()) / 999.0;
    EXPECT_GT(mesh_bytes, 100'000u);
    EXPECT_LT(per_instance, 1000.0) << "a mesh copy is " << mesh_bytes << " bytes";
    // Every instance is really there: a ray down onto each one's centre hits it.
    for (int i = 0; i < 1000; i += 37) {
        const Vec3 c(3.f * (i % 40), 3.f * (i / 40), 0.f);
        const auto hit = many.intersect({c + Vec3(0, 0, 10), {0, 0, -1}, kInfinity});
        ASSERT_TRUE(hit.has_value()) << "instance " << i;
        EXPECT_NEAR(hit->p.x, c.x, 1e-4f);
    }
}

TEST(Instancing, RaysLeavingAnInstanceNeverHitItAgain) {
    const std::string ply = flat_grid_ply();
    // Placements at extreme scales and offsets; the last maps the grid point (0.5, 0.5, 0.69) to
    // the world origin, so points there are far smaller in world space than in object space (the
    // object-space error must be carried over, the world point's own rounding is too small).
    struct Placement {
        const char* transform;
        double centre, spread;  ///< the local points aimed at: centre ± spread in x and y
    };
    const Placement placements[] = {
        {R"({"scale": 1e-3, "rotate": {"axis": [1, 1, 0], "degrees": 33}, "translate": [1e-3, 2e-3, 0]})", 0.0, 0.9},
        {R"({"scale": [1e4, 3e3, 1], "rotate": {"axis": [0, 1, 1], "degrees": 71}, "translate": [1e5, -2e5, 3e4]})", 0.0, 0.9},
        {R"({"scale": [0.7, 1.9, 5], "rotate": {"axis": [3, -1, 2], "degrees": 123}, "translate": [12345, 0.5, -777]})", 0.0, 0.9},
        {R"({"scale": 1e4, "translate": [-5000, -5000, -6900]})", 0.5, 1e-4},
    };
    for (const Placement& placement : placements) {
        SCOPED_TRACE(placement.transform);
        const Scene s = load_with_mesh(
            std::string(R"({"type": "mesh", "file": "m.ply", "material": "m", "instances": [)") + placement.transform + "]}", ply);
        const MeshInstance& inst = s.instances[0];
        Rng rng(21, 0, 0);
        int self_hits = 0, tries = 0;
        for (int k = 0; k < 4000; ++k) {
            // A point of the grid, reached by a ray from above or below it.
            auto coordinate = [&] { return placement.centre + placement.spread * (2.0 * rng.uniform() - 1.0); };
            const double x = coordinate(), y = coordinate();
            const DVec3 local(x, y, grid_z(x, y) + (k % 2 ? 1.0 : -1.0));
            const Vec3 target = inst.to_world.point(DVec3(x, y, grid_z(x, y))).to_float();
            const Vec3 from = inst.to_world.point(local).to_float();
            const auto hit = s.intersect({from, normalize(target - from), kInfinity});
            if (!hit) continue;
            ++tries;
            // Leave to either side, in random directions, and towards a far point.
            const Vec3 n = dot(hit->n, target - from) < 0.f ? hit->n : -hit->n;
            const Vec3 w = Frame(k % 4 < 2 ? n : -n).to_world(sample_cosine_hemisphere(rng.uniform(), rng.uniform()));
            if (s.intersect(spawn_ray(*hit, w))) ++self_hits;
            if (s.occluded(spawn_ray(*hit, w))) ++self_hits;
            if (s.occluded(spawn_ray_to(*hit, from))) ++self_hits;
        }
        EXPECT_GT(tries, 3800);
        EXPECT_EQ(self_hits, 0);
    }
}

TEST(Instancing, LoaderErrorsNameTheMeshAndWhatIsExpected) {
    EXPECT_NE(load_error(R"({"type": "mesh", "file": "m.ply", "material": "m", "transform": {"scale": 2}, "instances": [{}]})")
                  .find("mesh (shape 0) has both \"transform\" and \"instances\"; expected one of them"),
              std::string::npos);
    EXPECT_NE(load_error(R"({"type": "mesh", "file": "m.ply", "material": "m", "instances": []})")
                  .find("mesh (shape 0) instances is not a non-empty array"),
              std::string::npos);
    EXPECT_NE(load_error(R"({"type": "mesh", "file": "m.ply", "material": "m", "instances": {"scale": 2}})")
                  .find("instances is not a non-empty array"),
              std::string::npos);
    EXPECT_NE(load_error(R"({"type": "mesh", "file": "m.ply", "emission": 1, "instances": [{}]})")
                  .find("emits light and has instances"),
              std::string::npos);
    EXPECT_NE(load_error(R"({"type": "mesh", "file": "m.ply", "material": "m", "instances": [{"scael": 2}]})")
                  .find("unknown key \"scael\""),
              std::string::npos);
}

}  // namespace
}  // namespace spt

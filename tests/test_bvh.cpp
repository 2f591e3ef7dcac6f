// The BVH returns exactly what a brute-force loop returns (same t, same primitive) for sphere
// and triangle soups, rays starting inside boxes and axis-parallel rays; occluded() agrees
// with intersect(); a closed mesh shot from inside has no cracks through the BVH
// (ROBUSTNESS.md §7 case 7); Scene uses the BVH above its threshold and gives the same hits.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/rng.h"
#include "core/sampling.h"
#include "geometry/bvh.h"
#include "geometry/instanced_mesh.h"
#include "scene/scene.h"
#include "nearest_by_loop.h"

namespace spt {
namespace {

struct Soup {
    std::vector<Sphere> spheres;
    std::vector<Triangle> triangles;
};

/// Random spheres and triangles of widely varying sizes in [−5, 5]³ (overlapping freely).
Soup random_soup(Rng& rng, int n_spheres, int n_triangles) {
    auto point = [&] { return Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 10.f - Vec3(5, 5, 5); };
    Soup s;
    for (int i = 0; i < n_spheres; ++i) s.spheres.push_back({point(), 0.01f + 0.5f * rng.uniform() * rng.uniform(), 0});
    while (static_cast<int>(s.triangles.size()) < n_triangles) {
        const Vec3 a = point();
        const float size = 0.05f + 2.f * rng.uniform() * rng.uniform();
        auto near = [&] { return a + sample_uniform_sphere(rng.uniform(), rng.uniform()) * size; };
        const Triangle t{a, near(), near(), 0};
        if (!t.is_degenerate()) s.triangles.push_back(t);
    }
    return s;
}

/// Nearest hit by testing every primitive (the reference): each primitive's distance below
/// the ray's t_max, the smallest kept, and of equal ones the smallest PrimId (spheres before
/// triangles, then by index), which is what the BVH promises whatever its tree.
bool brute_force(const Soup& s, const Ray& ray, BvhHit& hit) {
    bool found = false;
    auto consider = [&](double t, PrimId prim) {
        if (!(t < ray.t_max)) return false;
        if (found && (t > hit.t || (t == hit.t && prim.bits > hit.prim.bits))) return false;
        hit.t = t, hit.prim = prim, found = true;
        return true;
    };
    for (std::size_t i = 0; i < s.spheres.size(); ++i)
        consider(s.spheres[i].intersect_t(ray), PrimId(ShapeKind::sphere, static_cast<std::uint32_t>(i)));
    for (std::size_t i = 0; i < s.triangles.size(); ++i)
        if (const auto ti = s.triangles[i].intersect(ray, ray.t_max))
            if (consider(ti->t, PrimId(ShapeKind::triangle, static_cast<std::uint32_t>(i)))) hit.tri = *ti;
    return found;
}

/// The BVH over the soup against brute_force on one ray: the same answer, the same
/// distance and the same primitive; occluded() agrees. Returns whether the ray hits.
bool expect_bvh_equals_brute_force(const Bvh& bvh, const Soup& s, const Ray& ray, int k) {
    const BvhShapes shapes = BvhShapes::of_arrays(s.spheres, s.triangles);
    BvhHit expected, got;
    const bool want = brute_force(s, ray, expected);
    double t_best = ray.t_max;
    const bool have = bvh.intersect(ray, shapes, t_best, got);
    EXPECT_EQ(have, want) << "ray " << k;
    EXPECT_EQ(bvh.occluded(ray, shapes), want) << "ray " << k;
    if (!want || !have) return false;
    EXPECT_EQ(got.t, expected.t) << "ray " << k;
    EXPECT_EQ(t_best, expected.t);
    EXPECT_EQ(got.prim, expected.prim) << "ray " << k;
    if (got.prim.kind() == ShapeKind::triangle) {
        EXPECT_EQ(got.tri.b0, expected.tri.b0) << "ray " << k;
    }
    return true;
}

/// A random direction; every fourth is axis-parallel and every fourth has one zero component.
Vec3 random_direction(Rng& rng, int k) {
    Vec3 d = sample_uniform_sphere(rng.uniform(), rng.uniform());
    const int axis = static_cast<int>(rng.uniform() * 3) % 3;
    if (k % 4 == 1) {
        float c[3] = {0, 0, 0};
        c[axis] = rng.uniform() < 0.5f ? -1.f : 1.f;
        d = {c[0], c[1], c[2]};
    } else if (k % 4 == 2) {
        float c[3] = {d.x, d.y, d.z};
        c[axis] = 0.f;
        d = normalize(Vec3(c[0], c[1], c[2]));
    }
    return d;
}

TEST(Bvh, NearestHitEqualsBruteForce) {
    Rng rng(11, 0, 0);
    for (const auto& [n_spheres, n_triangles] : {std::pair{0, 1}, std::pair{3, 0}, std::pair{40, 60}, std::pair{300, 1500}}) {
        const Soup s = random_soup(rng, n_spheres, n_triangles);
        Bvh bvh;
        const BvhBuildStats stats = bvh.build(BvhShapes::of_arrays(s.spheres, s.triangles));
        EXPECT_LT(stats.max_depth, Bvh::kStackSize);
        int hits = 0;
        for (int k = 0; k < 4000; ++k) {
            // Origins inside the soup (so inside many boxes) and outside it.
            const Vec3 o = Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 14.f - Vec3(7, 7, 7);
            Ray ray{o, random_direction(rng, k), k % 3 == 0 ? 2.f + 10.f * rng.uniform() : kInfinity};
            if (k % 5 == 0 && !s.triangles.empty()) {
                // Aimed exactly at a vertex: the boxes' faces are touched, not crossed.
                const Triangle& t = s.triangles[k % s.triangles.size()];
                ray.d = normalize(t.p1 - o);
            }
            hits += expect_bvh_equals_brute_force(bvh, s, ray, k);
        }
        if (n_spheres + n_triangles > 100) {
            EXPECT_GT(hits, 1000);
        }
    }
}

/// Adversarial layouts, where many primitives are equally near: a grid of triangles sharing
/// edges and vertices, laid twice (every hit on it ties with its copy), a fan around one
/// vertex, huge and tiny triangles, collinear ones, coincident spheres, all in shuffled order.
/// Rays go through the shared vertices and edge midpoints, graze the grid's plane and run
/// along axes. The BVH must give brute_force's answer: the nearest, and of equally near ones
/// the smallest PrimId, whatever leaf or node the walk meets them in.
TEST(Bvh, TiesGoToTheSmallestPrimitiveWhateverTheTree) {
    Rng rng(23, 0, 0);
    Soup s;
    constexpr int kGrid = 24;
    auto grid_point = [](int i, int j) { return Vec3(-3.f + 0.25f * i, -3.f + 0.25f * j, 0.5f); };
    for (int copy = 0; copy < 2; ++copy)
        for (int i = 0; i < kGrid; ++i)
            for (int j = 0; j < kGrid; ++j) {
                s.triangles.push_back({grid_point(i, j), grid_point(i + 1, j), grid_point(i + 1, j + 1), 0});
                s.triangles.push_back({grid_point(i, j), grid_point(i + 1, j + 1), grid_point(i, j + 1), 0});
            }
    const Vec3 hub(1.f, -2.f, -1.f);
    for (int k = 0; k < 32; ++k) {
        const float a0 = 2.f * kPi * k / 32, a1 = 2.f * kPi * (k + 1) / 32;
        s.triangles.push_back({hub, hub + Vec3(std::cos(a0), std::sin(a0), -0.3f), hub + Vec3(std::cos(a1), std::sin(a1), -0.3f), 0});
    }
    s.triangles.push_back({{-4e3f, -4e3f, -2.f}, {4e3f, -4e3f, -2.f}, {0.f, 4e3f, -2.f}, 0});  // huge, below all
    for (int k = 0; k < 200; ++k) {
        const Vec3 a(-3.f + 6.f * rng.uniform(), -3.f + 6.f * rng.uniform(), -1.5f + rng.uniform());
        s.triangles.push_back({a, a + Vec3(1e-4f, 0, 0), a + Vec3(0, 1e-4f, 1e-5f), 0});  // tiny
    }
    s.triangles.push_back({{0, 0, 0.7f}, {1, 1, 0.7f}, {2, 2, 0.7f}, 0});  // collinear: never hit
    for (int k = 0; k < 6; ++k) s.spheres.push_back({{-2.f, 2.f, -0.5f}, 0.4f, 0});  // coincident
    // Shuffled, so that copies and neighbours sit in unrelated leaves.
    for (std::size_t i = s.triangles.size() - 1; i > 0; --i)
        std::swap(s.triangles[i], s.triangles[static_cast<std::size_t>(rng.uniform() * float(i + 1)) % (i + 1)]);
    Bvh bvh;
    bvh.build(BvhShapes::of_arrays(s.spheres, s.triangles));
    int hits = 0, ties = 0;
    for (int k = 0; k < 20000; ++k) {
        Vec3 o = Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 8.f - Vec3(4, 4, 4);
        Vec3 target;
        switch (k % 5) {
            case 0: target = grid_point(int(rng.uniform() * kGrid), int(rng.uniform() * kGrid)); break;  // a vertex
            case 1: target = 0.5f * (grid_point(k % kGrid, 3) + grid_point(k % kGrid + 1, 4)); break;  // a diagonal
            case 2: target = hub; break;
            case 3: target = s.spheres[0].center + Vec3(0.4f, 0, 0); break;  // the spheres' rim
            default: target = o + random_direction(rng, k); break;
        }
        if (k % 7 == 0) o.z = 0.5f;  // in the grid's plane: grazing
        const Vec3 d = target - o;
        if (!(length(d) > 0.f)) continue;
        const Ray ray{o, normalize(d), k % 3 == 0 ? 1.f + 6.f * rng.uniform() : kInfinity};
        hits += expect_bvh_equals_brute_force(bvh, s, ray, k);
        BvhHit first;
        if (brute_force(s, ray, first)) {
            // A tie: some other primitive at the same distance (the brute force keeps the first).
            Soup rest = s;
            if (first.prim.kind() == ShapeKind::triangle) rest.triangles[first.prim.index()] = s.triangles.back();
            else rest.spheres[first.prim.index()] = s.spheres.back();
            BvhHit second;
            if (brute_force(rest, ray, second) && second.t == first.t) ++ties;
        }
        if (::testing::Test::HasFailure()) break;
    }
    EXPECT_GT(hits, 10000);
    EXPECT_GT(ties, 2000) << "the layout must make ties, or the test tests nothing";
}

/// Instances: of equally near instanced triangles the smallest instance wins, and instanced
/// triangles win over the arrays' own triangle at the same distance.
TEST(Bvh, TiesBetweenInstancesGoToTheSmallestInstance) {
    InstancedMesh mesh;
    mesh.triangles = {{{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}, 0}};
    mesh.bounds = bounds(mesh.triangles[0]);
    mesh.bvh.build(mesh.shapes());
    AffineMap shifted;
    shifted.a[0][3] = 5.0;
    std::vector<MeshInstance> instances = {MeshInstance(0, shifted), MeshInstance(0, AffineMap{}),
                                           MeshInstance(0, shifted), MeshInstance(0, AffineMap{})};
    for (MeshInstance& i : instances) i.world_bounds = instance_bounds(i.to_world, mesh.bounds);
    const std::vector<Triangle> own = {mesh.triangles[0]};
    BvhShapes shapes = BvhShapes::of_arrays(own);
    shapes.instances = instances;
    shapes.meshes = &mesh;
    Bvh bvh;
    bvh.build(shapes);
    for (const float x : {0.f, 5.f}) {
        BvhHit hit;
        double t_best = kInfinity;
        ASSERT_TRUE(bvh.intersect({{x, 0.f, 3.f}, {0, 0, -1}, kInfinity}, shapes, t_best, hit));
        EXPECT_EQ(t_best, 3.0);
        EXPECT_EQ(hit.instance, x == 0.f ? 1u : 0u) << "at x = " << x;
    }
}

/// Case 7 through the BVH: the 16×16 θφ sphere mesh with jittered radii, rays from inside in
/// random directions and exactly at vertices: no misses.
TEST(Bvh, ClosedMeshHasNoCracksThroughTheBvh) {
    Rng rng(7, 0, 0);
    constexpr int kTheta = 16, kPhi = 16;
    std::vector<Vec3> v;
    v.push_back({0, 0, 1.f + 5.f * rng.uniform()});
    for (int i = 1; i < kTheta; ++i)
        for (int j = 0; j < kPhi; ++j) {
            const float th = kPi * i / kTheta, ph = 2 * kPi * j / kPhi, r = 1.f + 5.f * rng.uniform();
            v.push_back({r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph), r * std::cos(th)});
        }
    v.push_back({0, 0, -(1.f + 5.f * rng.uniform())});
    const int south = static_cast<int>(v.size()) - 1;
    auto ring = [](int i, int j) { return 1 + (i - 1) * kPhi + (j % kPhi); };
    std::vector<Triangle> mesh;
    for (int j = 0; j < kPhi; ++j) {
        mesh.push_back({v[0], v[ring(1, j)], v[ring(1, j + 1)], 0});
        mesh.push_back({v[south], v[ring(kTheta - 1, j + 1)], v[ring(kTheta - 1, j)], 0});
        for (int i = 1; i + 1 < kTheta; ++i) {
            mesh.push_back({v[ring(i, j)], v[ring(i + 1, j)], v[ring(i + 1, j + 1)], 0});
            mesh.push_back({v[ring(i, j)], v[ring(i + 1, j + 1)], v[ring(i, j + 1)], 0});
        }
    }
    Bvh bvh;
    bvh.build(BvhShapes::of_arrays(mesh));
    int misses = 0, unoccluded = 0;
    for (int k = 0; k < 100000; ++k) {
        const Vec3 o = sample_uniform_sphere(rng.uniform(), rng.uniform()) * (0.5f * rng.uniform());
        Vec3 d = sample_uniform_sphere(rng.uniform(), rng.uniform());
        if (k % 2) d = normalize(v[k / 2 % v.size()] - o);  // exactly at a vertex
        if (k % 8 == 3) d = Vec3(0, 0, k % 16 < 8 ? 1.f : -1.f);  // axis-parallel, at the poles
        double t_best = kInfinity;
        BvhHit hit;
        if (!bvh.intersect({o, d, kInfinity}, BvhShapes::of_arrays(mesh), t_best, hit)) ++misses;
        if (!bvh.occluded({o, d, kInfinity}, BvhShapes::of_arrays(mesh))) ++unoccluded;
    }
    EXPECT_EQ(misses, 0);
    EXPECT_EQ(unoccluded, 0);
}

/// Degenerate layouts: all primitives at one point, and a line of spheres (deep trees).
TEST(Bvh, CoincidentAndCollinearPrimitives) {
    std::vector<Sphere> same(50, Sphere{{1, 2, 3}, 0.5f, 0});
    Bvh bvh;
    bvh.build(BvhShapes::of_arrays(same));
    double t = kInfinity;
    BvhHit hit;
    ASSERT_TRUE(bvh.intersect({{1, 2, 10}, {0, 0, -1}, kInfinity}, BvhShapes::of_arrays(same), t, hit));
    EXPECT_NEAR(t, 6.5, 1e-6);
    std::vector<Sphere> line;
    for (int i = 0; i < 2000; ++i) line.push_back({{std::ldexp(1.f, i % 60 - 30), 0, 0}, 1e-3f, 0});
    const BvhBuildStats stats = bvh.build(BvhShapes::of_arrays(line));
    EXPECT_LT(stats.max_depth, Bvh::kStackSize);
    t = kInfinity;
    EXPECT_TRUE(bvh.intersect({{1, 0, 5}, {0, 0, -1}, kInfinity}, BvhShapes::of_arrays(line), t, hit));
}

/// Scene: the BVH is used above the threshold only, and its hits equal the linear loop's.
TEST(Bvh, SceneUsesTheBvhAboveTheThresholdWithIdenticalHits) {
    Rng rng(3, 0, 0);
    const Soup s = random_soup(rng, 30, 50);
    Scene tree;
    tree.add_material(Material{});
    tree.spheres = s.spheres;
    tree.triangles = s.triangles;
    tree.finalize();
    ASSERT_TRUE(tree.uses_bvh());
    // The reference: every shape tested in a loop, the nearest kept.
    auto nearest_by_loop = [&](const Ray& ray) { return test::nearest_t_by_loop(s.spheres, s.triangles, ray); };
    for (int k = 0; k < 2000; ++k) {
        const Vec3 o = Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 14.f - Vec3(7, 7, 7);
        const Ray ray{o, random_direction(rng, k), kInfinity};
        const double t_ref = nearest_by_loop(ray);
        const auto b = tree.intersect(ray);
        ASSERT_EQ(t_ref < kInfinity, b.has_value());
        EXPECT_EQ(t_ref < kInfinity, tree.occluded(ray));
        if (b) {
            EXPECT_EQ(static_cast<float>(t_ref), b->t);
        }
    }
    Scene small;
    small.add_material(Material{});
    small.spheres = {s.spheres[0], s.spheres[1]};
    small.finalize();
    EXPECT_FALSE(small.uses_bvh());
}

}  // namespace
}  // namespace spt

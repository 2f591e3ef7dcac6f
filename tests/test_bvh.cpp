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

/// Nearest hit by testing every primitive (the reference).
bool brute_force(const Soup& s, const Ray& ray, BvhHit& hit) {
    double t_best = ray.t_max;
    bool found = false;
    for (std::size_t i = 0; i < s.spheres.size(); ++i)
        if (const double t = s.spheres[i].intersect_t(ray); t < t_best)
            t_best = t, hit.prim = PrimId(ShapeKind::sphere, static_cast<std::uint32_t>(i)), found = true;
    for (std::size_t i = 0; i < s.triangles.size(); ++i)
        if (const auto ti = s.triangles[i].intersect(ray, t_best))
            t_best = ti->t, hit.prim = PrimId(ShapeKind::triangle, static_cast<std::uint32_t>(i)), hit.tri = *ti, found = true;
    hit.t = t_best;
    return found;
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
            BvhHit expected, got;
            const bool want = brute_force(s, ray, expected);
            double t_best = ray.t_max;
            const bool have = bvh.intersect(ray, BvhShapes::of_arrays(s.spheres, s.triangles), t_best, got);
            ASSERT_EQ(have, want) << "ray " << k;
            EXPECT_EQ(bvh.occluded(ray, BvhShapes::of_arrays(s.spheres, s.triangles)), want) << "ray " << k;
            if (!want) continue;
            ++hits;
            EXPECT_EQ(got.t, expected.t) << "ray " << k;
            EXPECT_EQ(t_best, expected.t);
            EXPECT_EQ(got.prim, expected.prim) << "ray " << k;
        }
        if (n_spheres + n_triangles > 100) {
            EXPECT_GT(hits, 1000);
        }
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

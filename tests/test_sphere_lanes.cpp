// SphereLanes (the float rejection made on four spheres at once) must never reject a sphere
// that Sphere::intersect_t would hit: a small scene (no BVH) agrees with a loop over
// Sphere::intersect_t for every ray, with 1 to 8 spheres (one and two groups of four); the
// same for triangles, which use the test on their bounding spheres. Scene::disable_bvh (the
// --no-bvh measurement) puts any number of them through the same loop.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/rng.h"
#include "core/sampling.h"
#include "scene/scene.h"
#include "nearest_by_loop.h"

namespace spt {
namespace {

/// Checks scene.intersect and scene.occluded against the reference nearest distance t_ref
/// (what a loop over the shapes gives) for one ray; returns whether the ray hit.
bool expect_same_hit(const Scene& scene, const Ray& ray, double t_ref, const std::string& what) {
    const auto hit = scene.intersect(ray);
    EXPECT_EQ(hit.has_value(), t_ref < ray.t_max) << what;
    EXPECT_EQ(scene.occluded(ray), t_ref < ray.t_max) << what;
    if (hit) {
        EXPECT_EQ(hit->t, static_cast<float>(t_ref)) << what;
    }
    return hit.has_value();
}

/// Finalizes a small scene (no BVH), then casts 4000 rays from make_ray(k) and checks each
/// against reference(ray), the nearest distance a plain loop over the shapes gives. Returns
/// how many rays hit (−1 after the first failure, to keep the output short).
template <class MakeRay, class Reference>
int hits_equal_a_loop(Scene& scene, MakeRay make_ray, Reference reference, const std::string& what) {
    scene.finalize();
    EXPECT_FALSE(scene.uses_bvh());
    int hits = 0;
    for (int k = 0; k < 4000; ++k) {
        const Ray ray = make_ray(k);
        hits += expect_same_hit(scene, ray, reference(ray), what + ", ray " + std::to_string(k));
        if (::testing::Test::HasFailure()) return -1;
    }
    return hits;
}

TEST(SphereLanes, SmallSceneHitsEqualALoopOverTheSpheres) {
    Rng rng(11, 0, 0);
    for (int count = 1; count <= static_cast<int>(Scene::kBvhThreshold); ++count) {
        Scene scene;
        scene.add_material(Material{});
        for (int i = 0; i < count; ++i) {
            Sphere s;
            s.center = {4 * rng.uniform() - 2, 4 * rng.uniform() - 2, 4 * rng.uniform() - 2};
            s.radius = 0.05f + rng.uniform();
            s.material = 0;
            scene.spheres.push_back(s);
        }
        auto make_ray = [&](int k) {
            Ray ray;
            ray.o = {6 * rng.uniform() - 3, 6 * rng.uniform() - 3, 6 * rng.uniform() - 3};
            ray.d = sample_uniform_sphere(rng.uniform(), rng.uniform());
            if (k % 3 != 0) {  // aim near a sphere's rim, where the float test is closest to wrong
                const Sphere& s = scene.spheres[static_cast<std::size_t>(rng.uniform() * count)];
                const Vec3 target = s.center + sample_uniform_sphere(rng.uniform(), rng.uniform()) *
                                                   (s.radius * (0.9f + 0.2f * rng.uniform()));
                ray.d = normalize(target - ray.o);
            }
            ray.t_max = k % 2 ? kInfinity : 2.f;
            return ray;
        };
        auto loop = [&](const Ray& ray) {
            double t_ref = ray.t_max;
            for (const Sphere& s : scene.spheres) t_ref = std::min(t_ref, s.intersect_t(ray));
            return t_ref;
        };
        const int hits = hits_equal_a_loop(scene, make_ray, loop, std::to_string(count) + " spheres");
        if (hits < 0) return;
        EXPECT_GT(hits, 100) << "the rays must actually meet the spheres";
    }
}

/// Triangles of small scenes go through the float test of their bounding spheres first: the
/// hits must equal a loop over Triangle::intersect, slivers and huge triangles included.
TEST(SphereLanes, SmallSceneTriangleHitsEqualALoop) {
    Rng rng(13, 0, 0);
    for (int count = 1; count <= static_cast<int>(Scene::kBvhThreshold); ++count) {
        Scene scene;
        scene.add_material(Material{});
        for (int i = 0; i < count; ++i) {
            const float scale = std::pow(10.f, 4 * rng.uniform() - 2);  // 0.01 … 100
            const Vec3 c = {4 * rng.uniform() - 2, 4 * rng.uniform() - 2, 4 * rng.uniform() - 2};
            Triangle t;
            t.p0 = c + sample_uniform_sphere(rng.uniform(), rng.uniform()) * scale;
            t.p1 = c + sample_uniform_sphere(rng.uniform(), rng.uniform()) * scale;
            // Every third one a sliver: p2 almost on the edge p0p1.
            t.p2 = i % 3 == 0 ? t.p0 + (t.p1 - t.p0) * 0.5f + Vec3(1e-4f, 0, 0) * scale
                              : c + sample_uniform_sphere(rng.uniform(), rng.uniform()) * scale;
            t.material = 0;
            if (t.is_degenerate()) continue;
            scene.triangles.push_back(t);
        }
        auto make_ray = [&](int) {
            Ray ray;
            ray.o = {6 * rng.uniform() - 3, 6 * rng.uniform() - 3, 6 * rng.uniform() - 3};
            const Triangle& t = scene.triangles[static_cast<std::size_t>(rng.uniform() * scene.triangles.size())];
            // Aim at a random point of a triangle, slightly outside it at times (edges).
            const float a = rng.uniform() * 1.1f - 0.05f, b = rng.uniform() * (1.1f - a) - 0.05f;
            ray.d = normalize(t.p0 + (t.p1 - t.p0) * a + (t.p2 - t.p0) * b - ray.o);
            ray.t_max = kInfinity;
            return ray;
        };
        auto loop = [&](const Ray& ray) {
            double t_ref = ray.t_max;
            for (const Triangle& tri : scene.triangles)
                if (auto ti = tri.intersect(ray, t_ref)) t_ref = ti->t;
            return t_ref;
        };
        const int hits = hits_equal_a_loop(scene, make_ray, loop, std::to_string(count) + " triangles");
        if (hits < 0) return;
        EXPECT_GT(hits, 1000) << "the rays must actually meet the triangles";
    }
}

/// --no-bvh: a scene far above the threshold, its BVH disabled, still hits exactly what a loop
/// over its spheres and triangles hits.
TEST(SphereLanes, DisabledBvhHitsEqualALoop) {
    Rng rng(17, 0, 0);
    Scene scene;
    scene.add_material(Material{});
    for (int i = 0; i < 24; ++i) {
        const Vec3 c = {4 * rng.uniform() - 2, 4 * rng.uniform() - 2, 4 * rng.uniform() - 2};
        Sphere s;
        s.center = c;
        s.radius = 0.05f + 0.3f * rng.uniform();
        s.material = 0;
        scene.spheres.push_back(s);
        Triangle t;
        t.p0 = c + Vec3(0.5f, 0, 0);
        t.p1 = c + sample_uniform_sphere(rng.uniform(), rng.uniform());
        t.p2 = c + sample_uniform_sphere(rng.uniform(), rng.uniform());
        t.material = 0;
        if (!t.is_degenerate()) scene.triangles.push_back(t);
    }
    scene.finalize();
    ASSERT_TRUE(scene.uses_bvh());
    ASSERT_TRUE(scene.disable_bvh());
    auto make_ray = [&](int) {
        Ray ray;
        ray.o = {6 * rng.uniform() - 3, 6 * rng.uniform() - 3, 6 * rng.uniform() - 3};
        const Sphere& s = scene.spheres[static_cast<std::size_t>(rng.uniform() * scene.spheres.size())];
        ray.d = normalize(s.center + sample_uniform_sphere(rng.uniform(), rng.uniform()) * 0.5f - ray.o);
        ray.t_max = kInfinity;
        return ray;
    };
    auto loop = [&](const Ray& ray) { return test::nearest_t_by_loop(scene.spheres, scene.triangles, ray); };
    EXPECT_GT(hits_equal_a_loop(scene, make_ray, loop, "24 spheres and triangles without a BVH"), 1000);
}

/// The loop knows spheres and triangles only: a scene with another bounded shape keeps its BVH.
TEST(SphereLanes, DisableBvhRefusesShapesOnlyTheBvhIntersects) {
    Scene scene;
    scene.add_material(Material{});
    Disk d;
    d.material = 0;
    scene.disks.push_back(d);
    scene.finalize();
    ASSERT_TRUE(scene.uses_bvh());
    EXPECT_FALSE(scene.disable_bvh());
    EXPECT_TRUE(scene.uses_bvh());
}

}  // namespace
}  // namespace spt

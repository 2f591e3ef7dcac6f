// SphereLanes (the float rejection made on four spheres at once) must never reject a sphere
// that Sphere::intersect_t would hit: a small scene (no BVH) agrees with a loop over
// Sphere::intersect_t for every ray, with 1 to 8 spheres (one and two groups of four).
#include <gtest/gtest.h>

#include "core/rng.h"
#include "core/sampling.h"
#include "scene/scene.h"

namespace spt {
namespace {

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
        scene.finalize();
        ASSERT_FALSE(scene.uses_bvh());
        int hits = 0;
        for (int k = 0; k < 4000; ++k) {
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
            double t_ref = ray.t_max;
            for (const Sphere& s : scene.spheres) t_ref = std::min(t_ref, s.intersect_t(ray));
            const auto hit = scene.intersect(ray);
            ASSERT_EQ(hit.has_value(), t_ref < ray.t_max) << count << " spheres, ray " << k;
            ASSERT_EQ(scene.occluded(ray), t_ref < ray.t_max) << count << " spheres, ray " << k;
            if (hit) {
                EXPECT_EQ(hit->t, static_cast<float>(t_ref));
                ++hits;
            }
        }
        EXPECT_GT(hits, 100) << "the rays must actually meet the spheres";
    }
}

}  // namespace
}  // namespace spt

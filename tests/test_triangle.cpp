// Watertight triangles (ROBUSTNESS.md §7): no self-hits when leaving a triangle (case 2), no
// ray through a closed mesh or a shared edge (case 7), degenerate inputs (case 8).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/rng.h"
#include "core/sampling.h"
#include "geometry/triangle.h"

namespace spt {
namespace {

TEST(Triangle, HitPointNormalAndBarycentrics) {
    const Triangle t{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 3};
    const Ray r{{0.25f, 0.25f, 1}, {0, 0, -1}, kInfinity};
    const auto ti = t.intersect(r, kInfinity);
    ASSERT_TRUE(ti);
    EXPECT_DOUBLE_EQ(ti->t, 1.0);
    const Hit h = t.make_hit(*ti);
    EXPECT_EQ(h.p, Vec3(0.25f, 0.25f, 0));
    EXPECT_EQ(h.n, Vec3(0, 0, 1));
    EXPECT_EQ(h.material, 3);
    EXPECT_FALSE(t.intersect({{0.25f, 0.25f, 1}, {0, 0, 1}, kInfinity}, kInfinity));  // behind
    EXPECT_FALSE(t.intersect(r, 0.5));                                                // beyond t_max
}

/// Case 2: rays spawned from a hit on a triangle (vertices 10^U(−8,8)) never hit it again.
TEST(Triangle, SpawnedRaysNeverHitTheirOwnTriangle) {
    Rng rng(42, 0, 0);
    auto log_uniform = [&] {
        const float v = std::pow(10.f, -8.f + 16.f * rng.uniform());
        return rng.uniform() < 0.5f ? -v : v;
    };
    int tested = 0, self_hits = 0;
    while (tested < 1000) {
        const Triangle t{{log_uniform(), log_uniform(), log_uniform()},
                         {log_uniform(), log_uniform(), log_uniform()},
                         {log_uniform(), log_uniform(), log_uniform()}, 0};
        double c[3];
        t.cross_double(c);
        if (c[0] * c[0] + c[1] * c[1] + c[2] * c[2] < 1e-20) continue;
        // A point on the triangle, reached by a ray from outside.
        const float b1 = rng.uniform(), b2 = rng.uniform() * (1 - b1);
        const Vec3 target = t.p0 * (1 - b1 - b2) + t.p1 * b1 + t.p2 * b2;
        const Vec3 n = normalize(Vec3(float(c[0]), float(c[1]), float(c[2])));
        const Vec3 from = target + n * (1.f + length(target));
        const auto ti = t.intersect({from, normalize(target - from), kInfinity}, kInfinity);
        if (!ti) continue;
        const Hit hit = t.make_hit(*ti);
        ++tested;
        // 1 ray over the full sphere and 1 ray towards a point.
        const Vec3 w = sample_uniform_sphere(rng.uniform(), rng.uniform());
        if (t.intersect(spawn_ray(hit, w), kInfinity)) ++self_hits;
        const Vec3 to = hit.p + sample_uniform_sphere(rng.uniform(), rng.uniform()) * (1.f + length(hit.p));
        const Ray shadow = spawn_ray_to(hit, to);
        if (t.intersect(shadow, shadow.t_max)) ++self_hits;
    }
    EXPECT_EQ(self_hits, 0);
}

/// Case 7a: a 16×16 θφ sphere mesh with shared poles and jittered radii; rays from inside,
/// in random directions and aimed exactly at vertices, always hit it.
TEST(Triangle, ClosedMeshHasNoCracks) {
    Rng rng(7, 0, 0);
    constexpr int kTheta = 16, kPhi = 16;
    std::vector<Vec3> v;  // v[0] north pole, then rings, then south pole
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
    auto hits = [&](const Ray& r) {
        for (const Triangle& t : mesh)
            if (t.intersect(r, kInfinity)) return true;
        return false;
    };
    int misses = 0;
    for (int k = 0; k < 100000; ++k) {
        const Vec3 o = sample_uniform_sphere(rng.uniform(), rng.uniform()) * (0.5f * rng.uniform());
        Vec3 d = sample_uniform_sphere(rng.uniform(), rng.uniform());
        if (k % 2) d = normalize(v[k / 2 % v.size()] - o);  // exactly at a vertex
        if (!hits({o, d, kInfinity})) ++misses;
    }
    EXPECT_EQ(misses, 0);
}

/// Case 7b: a square split along its diagonal, hit exactly at the shared edge's midpoint.
TEST(Triangle, SharedEdgeMidpointIsHit) {
    const Triangle a{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, 0}, b{{0, 0, 0}, {1, 1, 0}, {0, 1, 0}, 0};
    for (const Vec3 o : {Vec3(0.5f, 0.5f, 1), Vec3(0.3f, 0.9f, 2), Vec3(-3, 7, 0.25f)}) {
        const Ray r{o, normalize(Vec3(0.5f, 0.5f, 0) - o), kInfinity};
        const int n = (a.intersect(r, kInfinity) ? 1 : 0) + (b.intersect(r, kInfinity) ? 1 : 0);
        EXPECT_GE(n, 1);
        EXPECT_LE(n, 2);
    }
}

/// Case 8: pbrt's BadCases triangle, and a ray lying in the triangle's plane.
TEST(Triangle, DegenerateInputsDoNotHit) {
    const Triangle bad{{-1113.45459f, -79.049614f, -56.2431908f},
                       {-1113.45459f, -87.0922699f, -56.2431908f},
                       {-1113.45459f, -79.2090149f, -56.2431908f}, 0};
    const Ray r{{-1081.47925f, 99.9999542f, 87.7701111f}, {-32.1072998f, -183.355865f, -144.607635f}, 0.9999f};
    EXPECT_FALSE(bad.intersect(r, r.t_max));
    const Triangle t{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0};
    EXPECT_FALSE(t.intersect({{-1, 0.25f, 0}, {1, 0, 0}, kInfinity}, kInfinity));
    const Triangle collinear{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, 0};
    EXPECT_TRUE(collinear.is_degenerate());
    EXPECT_FALSE(collinear.intersect({{1, 1, 5}, {0, 0, -1}, kInfinity}, kInfinity));
}

}  // namespace
}  // namespace spt

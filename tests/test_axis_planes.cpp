// AxisPlanes (two planes per vector test, NaN padding, an overflow list beyond two planes
// per axis) against a plain loop over the same planes in order, coincident planes included.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/rng.h"
#include "core/sampling.h"
#include "geometry/axis_planes.h"
#include "geometry/plane.h"

namespace {

struct ListedPlane {
    int axis;
    double position;
};

/// The reference: every plane in index order, the first strictly nearer one kept.
void nearest_by_loop(const std::vector<ListedPlane>& planes, const spt::Ray& ray, double& t_best, int& best) {
    const double o[3] = {ray.o.x, ray.o.y, ray.o.z};
    const double inv[3] = {1.0 / ray.d.x, 1.0 / ray.d.y, 1.0 / ray.d.z};
    for (int i = 0; i < static_cast<int>(planes.size()); ++i) {
        const double t = (planes[i].position - o[planes[i].axis]) * inv[planes[i].axis];
        if (t > 0.0 && t < t_best) t_best = t, best = i;
    }
}

TEST(AxisPlanes, NearestEqualsAPlainLoopForAnyPlaneCount) {
    spt::Rng rng(7, 0, 0);
    for (int scene = 0; scene < 300; ++scene) {
        // 0–5 planes per axis at positions from a small set, so some coincide.
        std::vector<ListedPlane> listed;
        spt::AxisPlanes planes;
        const int count = static_cast<int>(rng.uniform() * 12);
        for (int i = 0; i < count; ++i) {
            const int axis = static_cast<int>(rng.uniform() * 3);
            const double position = static_cast<int>(rng.uniform() * 5) - 2;
            listed.push_back({axis, position});
            planes.add(axis, position, i);
        }
        for (int r = 0; r < 200; ++r) {
            spt::Ray ray;
            ray.o = {4 * rng.uniform() - 2, 4 * rng.uniform() - 2, 4 * rng.uniform() - 2};
            ray.d = spt::sample_uniform_sphere(rng.uniform(), rng.uniform());
            if (r % 10 == 0) ray.d = {0, 0, 1};  // zero components: ±inf and NaN distances
            ray.t_max = r % 3 == 0 ? 1.5f : spt::kInfinity;
            double t_ref = ray.t_max, t_got = ray.t_max;
            int i_ref = -1, i_got = -1;
            nearest_by_loop(listed, ray, t_ref, i_ref);
            planes.nearest(ray, t_got, i_got);
            ASSERT_EQ(i_got, i_ref) << "scene " << scene << " ray " << r;
            ASSERT_EQ(t_got, t_ref) << "scene " << scene << " ray " << r;
            ASSERT_EQ(planes.any_hit(ray), i_ref >= 0);
        }
    }
}

TEST(AxisPlanes, CoincidentPlanesResolveToTheLowerIndex) {
    spt::AxisPlanes planes;
    planes.add(1, 0.5, 0);
    planes.add(1, 0.5, 1);
    planes.add(1, 0.5, 2);  // overflow pair
    planes.add(0, 0.5, 3);
    spt::Ray ray{{0, 0, 0}, {0, 1, 0}, spt::kInfinity};
    double t = ray.t_max;
    int best = -1;
    planes.nearest(ray, t, best);
    EXPECT_EQ(best, 0);
    EXPECT_EQ(t, 0.5);
    // Nothing ahead: unchanged.
    ray.d = {0, -1, 0};
    t = ray.t_max, best = -1;
    planes.nearest(ray, t, best);
    EXPECT_EQ(best, -1);
    EXPECT_EQ(t, double(spt::kInfinity));
}

}  // namespace

namespace {

/// The shortcut for axis-aligned planes gives the same hit record as the general projection.
TEST(AxisPlanes, AxisHitEqualsTheGeneralProjection) {
    spt::Rng rng(5, 0, 0);
    for (int k = 0; k < 20000; ++k) {
        const int axis = static_cast<int>(rng.uniform() * 3);
        spt::Plane plane;
        plane.normal = {0, 0, 0};
        plane.normal[axis] = rng.uniform() < 0.5f ? 1.f : -1.f;
        plane.offset = (rng.uniform() - 0.5f) * std::pow(10.f, 8 * rng.uniform() - 4);
        plane.material = 0;
        spt::Ray ray;
        ray.o = {rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f};
        ray.o = ray.o * std::pow(10.f, 8 * rng.uniform() - 4);
        ray.d = spt::sample_uniform_sphere(rng.uniform(), rng.uniform());
        const double t = plane.intersect_t(ray);
        if (!(t < spt::kInfinity)) continue;
        const spt::Hit a = plane.make_axis_hit(ray, t, axis), b = plane.make_hit(ray, t);
        ASSERT_EQ(a.p, b.p) << k;
        ASSERT_EQ(a.p_err, b.p_err) << k;
        ASSERT_EQ(a.n, b.n) << k;
        ASSERT_EQ(a.t, b.t) << k;
    }
}

}  // namespace

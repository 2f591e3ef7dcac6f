// Axis-aligned bounding boxes and the robust ray-slab test used by the BVH (pbrt-v4's
// Bounds3::IntersectP: the far distance is enlarged by 1 + 2γ3 so that rounding in the slab
// computation can never cull a box that the watertight triangle test would hit).
#pragma once
#include <algorithm>

#include "geometry/ray.h"

namespace spt {

struct Aabb {
    Vec3 lo{kInfinity, kInfinity, kInfinity};
    Vec3 hi{-kInfinity, -kInfinity, -kInfinity};

    bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    void expand(const Vec3& p) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    void expand(const Aabb& b) {
        lo = {std::min(lo.x, b.lo.x), std::min(lo.y, b.lo.y), std::min(lo.z, b.lo.z)};
        hi = {std::max(hi.x, b.hi.x), std::max(hi.y, b.hi.y), std::max(hi.z, b.hi.z)};
    }
    Vec3 centroid() const { return (lo + hi) * 0.5f; }
    /// Surface area in double (SAH costs sum many of them); 0 for an empty box.
    double surface_area() const {
        if (empty()) return 0.0;
        const double dx = double(hi.x) - lo.x, dy = double(hi.y) - lo.y, dz = double(hi.z) - lo.z;
        return 2.0 * (dx * dy + dy * dz + dz * dx);
    }
    int largest_axis() const {
        const Vec3 d = hi - lo;
        return d.x > d.y ? (d.x > d.z ? 0 : 2) : (d.y > d.z ? 1 : 2);
    }
};

/// Per-ray constants of the slab test: reciprocal direction (±inf for zero components).
struct RaySlabs {
    Vec3 o;
    float inv_d[3];
    explicit RaySlabs(const Ray& ray) : o(ray.o) {
        inv_d[0] = 1.f / ray.d.x, inv_d[1] = 1.f / ray.d.y, inv_d[2] = 1.f / ray.d.z;
    }
};

/// True if the ray meets the box [lo, hi] within (0, t_max). A zero direction component
/// gives ±inf slab distances (or NaN when the origin lies on the slab): comparisons written so
/// that a NaN never shrinks the interval, as in pbrt.
inline bool slab_hit(const float lo[3], const float hi[3], const RaySlabs& r, float t_max) {
    constexpr float kGrow = 1.f + 2.f * gamma_bound(3);
    float t0 = 0.f, t1 = t_max;
    for (int a = 0; a < 3; ++a) {
        const float o = (&r.o.x)[a];
        float t_near = (lo[a] - o) * r.inv_d[a];
        float t_far = (hi[a] - o) * r.inv_d[a];
        if (t_near > t_far) std::swap(t_near, t_far);
        t_far *= kGrow;
        t0 = t_near > t0 ? t_near : t0;
        t1 = t_far < t1 ? t_far : t1;
        if (t0 > t1) return false;
    }
    return true;
}

}  // namespace spt

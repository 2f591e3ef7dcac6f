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

/// Per-ray constants of the slab test: reciprocal direction (±inf for zero components) and
/// which of a box's two bounds is met first on each axis.
struct RaySlabs {
    float o[3];
    float inv_d[3];
    int near[3];  ///< 0: lo first, 1: hi first (negative direction)
    explicit RaySlabs(const Ray& ray) {
        const float d[3] = {ray.d.x, ray.d.y, ray.d.z};
        for (int a = 0; a < 3; ++a) {
            o[a] = (&ray.o.x)[a];
            inv_d[a] = 1.f / d[a];
            near[a] = inv_d[a] < 0.f ? 1 : 0;
        }
    }
};

/// True if the ray meets the box whose bounds are b[0] = lo and b[1] = hi within
/// (0, t_max). A zero direction component gives ±inf slab distances (NaN when the origin lies
/// on the slab): the comparisons are written so that a NaN never shrinks the interval (pbrt).
inline bool slab_hit(const float* const b[2], const RaySlabs& r, float t_max) {
    constexpr float kGrow = 1.f + 2.f * gamma_bound(3);
    float t0 = 0.f, t1 = t_max;
    for (int a = 0; a < 3; ++a) {
        const float t_near = (b[r.near[a]][a] - r.o[a]) * r.inv_d[a];
        const float t_far = (b[1 - r.near[a]][a] - r.o[a]) * r.inv_d[a] * kGrow;
        t0 = t_near > t0 ? t_near : t0;
        t1 = t_far < t1 ? t_far : t1;
    }
    return t0 <= t1;
}

}  // namespace spt

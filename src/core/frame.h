// Orthonormal frame around a unit normal (Duff et al. 2017, "Building an orthonormal basis,
// revisited"): branchless and finite for every unit normal, including the poles.
#pragma once
#include "core/vec3.h"

namespace spt {

struct Frame {
    Vec3 s, t, n;

    explicit Frame(const Vec3& normal) : n(normal) {
        const float sign = std::copysign(1.f, n.z);
        const float a = -1.f / (sign + n.z);
        const float b = n.x * n.y * a;
        s = {1.f + sign * n.x * n.x * a, sign * b, -sign * n.x};
        t = {b, sign + n.y * n.y * a, -n.y};
    }
    Vec3 to_world(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
    Vec3 to_local(const Vec3& v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
};

}  // namespace spt

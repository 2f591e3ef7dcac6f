// Infinite plane dot(n, p) = offset. Intersected in double and snapped back onto the plane, so
// the hit point's only error is its final rounding to float.
#pragma once
#include <cmath>
#include <optional>

#include "geometry/ray.h"

namespace spt {

struct Plane {
    Vec3 normal;        ///< unit normal; the side it points to is the plane's front
    float offset = 0.f;  ///< dot(normal, p) for points p on the plane
    int material = -1;

    std::optional<Hit> intersect(const Ray& ray) const {
        const double nx = normal.x, ny = normal.y, nz = normal.z;
        const double denom = nx * ray.d.x + ny * ray.d.y + nz * ray.d.z;
        if (denom == 0.0) return std::nullopt;  // ray parallel to the plane
        const double no = nx * ray.o.x + ny * ray.o.y + nz * ray.o.z;
        const double t = (offset - no) / denom;
        if (!(t > 0.0) || t >= ray.t_max) return std::nullopt;
        double px = ray.o.x + t * ray.d.x, py = ray.o.y + t * ray.d.y, pz = ray.o.z + t * ray.d.z;
        const double residual = nx * px + ny * py + nz * pz - offset;
        px -= residual * nx, py -= residual * ny, pz -= residual * nz;
        Hit hit;
        hit.t = static_cast<float>(t);
        hit.p = {static_cast<float>(px), static_cast<float>(py), static_cast<float>(pz)};
        hit.p_err = rounded_point_error(hit.p);
        hit.n = normal;
        hit.material = material;
        return hit;
    }
};

}  // namespace spt

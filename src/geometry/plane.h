// Infinite plane dot(n, p) = offset. Intersected in double and the hit point snapped back onto
// the plane, so the hit point's only error is its final rounding to float.
#pragma once
#include <cmath>

#include "geometry/ray.h"

namespace spt {

struct Plane {
    Vec3 normal;         ///< unit normal; the side it points to is the plane's front
    float offset = 0.f;  ///< dot(normal, p) for points p on the plane
    int material = -1;

    Plane() = default;
    Plane(const Vec3& n, float offset_, int material_) : normal(n), offset(offset_), material(material_) {
        for (int a = 0; a < 3; ++a)
            if (std::fabs(n[a]) == 1.f) axis = a, axis_position = n[a] * offset;
    }

    /// Distance along the ray to the plane, or infinity when there is no hit with t > 0.
    double intersect_t(const Ray& ray) const {
        if (axis >= 0) {
            // Axis-aligned: one subtraction and one division in float. The subtraction is exact
            // near the plane (Sterbenz), so a ray spawned off the plane never re-hits it.
            const float t = (axis_position - (&ray.o.x)[axis]) / (&ray.d.x)[axis];
            return t > 0.f ? t : kInfinity;
        }
        const double denom = double(normal.x) * ray.d.x + double(normal.y) * ray.d.y +
                             double(normal.z) * ray.d.z;
        const double no = double(normal.x) * ray.o.x + double(normal.y) * ray.o.y +
                          double(normal.z) * ray.o.z;
        const double t = (offset - no) / denom;  // ±inf or NaN when parallel: rejected below
        return t > 0.0 ? t : kInfinity;
    }

    Hit make_hit(const Ray& ray, double t) const {
        const double nx = normal.x, ny = normal.y, nz = normal.z;
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

private:
    int axis = -1;              ///< 0, 1, 2 when the normal is ±x, ±y, ±z
    float axis_position = 0.f;  ///< the plane's coordinate on that axis
};

}  // namespace spt

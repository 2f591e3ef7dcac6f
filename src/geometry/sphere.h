// Sphere shape. Intersection in double precision with the geometric discriminant (Ray Tracing
// Gems ch. 7), so far-away and tiny spheres stay exact; hits are reprojected onto the surface.
#pragma once
#include <cmath>
#include <optional>

#include "geometry/ray.h"

namespace spt {

struct Sphere {
    Vec3 center;
    float radius = 1.f;
    int material = -1;

    /// Nearest hit with t in (0, ray.t_max).
    std::optional<Hit> intersect(const Ray& ray) const {
        const double ox = ray.o.x - static_cast<double>(center.x);
        const double oy = ray.o.y - static_cast<double>(center.y);
        const double oz = ray.o.z - static_cast<double>(center.z);
        const double dx = ray.d.x, dy = ray.d.y, dz = ray.d.z;
        const double dd = dx * dx + dy * dy + dz * dz;
        const double t_c = -(ox * dx + oy * dy + oz * dz) / dd;  // closest approach
        const double vx = ox + t_c * dx, vy = oy + t_c * dy, vz = oz + t_c * dz;
        const double r = radius;
        const double disc = (r * r - (vx * vx + vy * vy + vz * vz)) / dd;
        if (disc < 0.0) return std::nullopt;
        const double half = std::sqrt(disc);
        double t = t_c - half;
        if (t <= 0.0) t = t_c + half;
        if (t <= 0.0 || t >= ray.t_max) return std::nullopt;
        // Reproject onto the surface: the point is then exact up to its final rounding.
        double px = ox + t * dx, py = oy + t * dy, pz = oz + t * dz;
        const double scale = r / std::sqrt(px * px + py * py + pz * pz);
        px *= scale, py *= scale, pz *= scale;
        Hit hit;
        hit.t = static_cast<float>(t);
        hit.p = {static_cast<float>(px + center.x), static_cast<float>(py + center.y),
                 static_cast<float>(pz + center.z)};
        hit.p_err = rounded_point_error(hit.p);
        hit.n = Vec3(static_cast<float>(px / r), static_cast<float>(py / r),
                     static_cast<float>(pz / r));
        hit.n = normalize(hit.n);
        hit.material = material;
        return hit;
    }
};

}  // namespace spt

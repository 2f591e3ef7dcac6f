// Sphere shape. Intersection in double precision with the geometric discriminant (Ray Tracing
// Gems ch. 7), so far-away and tiny spheres stay exact; hits are reprojected onto the surface.
#pragma once
#include <algorithm>
#include <cmath>

#include "geometry/dvec3.h"
#include "geometry/ray.h"
#include "geometry/shape_array.h"
#include "geometry/surface_sample.h"

namespace spt {

/// Cheap float rejection of clear misses (most rays): the sphere behind the origin, or the
/// line passing outside it by a margin far above float rounding. oc = centre − origin, d the
/// ray direction. T is float (one sphere: a bool) or Float4 (SphereLanes: four at once, a
/// lane mask); the same expressions either way, so both reject exactly the same spheres.
template <typename T>
inline auto sphere_surely_missed(T ocx, T ocy, T ocz, T dx, T dy, T dz, T radius) {
    const T tc = ocx * dx + ocy * dy + ocz * dz;
    const T oc2 = ocx * ocx + ocy * ocy + ocz * ocz;
    const T r2 = radius * radius;
    return ((tc < -radius) & (oc2 > r2 * 1.01f)) | (oc2 - tc * tc > r2 * 1.01f + 1e-5f * oc2);
}

struct Sphere {
    Vec3 center;
    float radius = 1.f;
    int material = -1;
    int light = -1;  ///< emitter attached to the sphere (Scene::lights), −1 if none

    static constexpr const char* kName = "sphere";
    /// What makes the sphere unrenderable, or nullptr.
    const char* defect() const {
        if (!is_finite(center)) return "sphere centre must be finite";
        if (!(std::isfinite(radius) && radius > 0.f)) return "sphere radius must be > 0 and finite";
        return nullptr;
    }

    /// Distance to the nearest hit with t > 0, or infinity when there is none.
    double intersect_t(const Ray& ray) const {
        const Vec3 oc = center - ray.o;
        if (sphere_surely_missed(oc.x, oc.y, oc.z, ray.d.x, ray.d.y, ray.d.z, radius)) return kInfinity;
        return intersect_t_exact(ray);
    }

    /// intersect_t without the float rejection: the exact test in double.
    double intersect_t_exact(const Ray& ray) const {
        const double ox = double(ray.o.x) - center.x, oy = double(ray.o.y) - center.y,
                     oz = double(ray.o.z) - center.z;
        const double dx = ray.d.x, dy = ray.d.y, dz = ray.d.z;
        const double inv_dd = 1.0 / (dx * dx + dy * dy + dz * dz);  // one division for both uses
        const double t_c = -(ox * dx + oy * dy + oz * dz) * inv_dd;  // closest approach
        const double vx = ox + t_c * dx, vy = oy + t_c * dy, vz = oz + t_c * dz;
        const double r = radius;
        const double disc = (r * r - (vx * vx + vy * vy + vz * vz)) * inv_dd;
        if (disc < 0.0) return kInfinity;
        const double half = std::sqrt(disc);
        if (t_c - half > 0.0) return t_c - half;
        return t_c + half > 0.0 ? t_c + half : kInfinity;
    }

    Hit make_hit(const Ray& ray, double t) const {
        // Reproject onto the surface: the point is then exact up to its final rounding. The
        // unit normal comes from the same division (one sqrt and one division in double; the
        // normal, unit to double precision, needs no float normalisation afterwards).
        const double px = double(ray.o.x) - center.x + t * ray.d.x;
        const double py = double(ray.o.y) - center.y + t * ray.d.y;
        const double pz = double(ray.o.z) - center.z + t * ray.d.z;
        const double inv_len = 1.0 / std::sqrt(px * px + py * py + pz * pz);
        const double nx = px * inv_len, ny = py * inv_len, nz = pz * inv_len;
        const double r = radius;
        Hit hit;
        hit.t = static_cast<float>(t);
        hit.p = {static_cast<float>(nx * r + center.x), static_cast<float>(ny * r + center.y),
                 static_cast<float>(nz * r + center.z)};
        hit.p_err = rounded_point_error(hit.p);
        hit.n = {static_cast<float>(nx), static_cast<float>(ny), static_cast<float>(nz)};
        hit.ns = hit.n;
        hit.material = material;
        hit.light = light;
        return hit;
    }

    float area() const { return static_cast<float>(4.0 * kPiDouble * radius * radius); }

    /// Uniform by area (Archimedes: the height along the axis is uniform), computed in double.
    SurfaceSample sample_area(float u1, float u2) const {
        const double z = 1.0 - 2.0 * u1, s = std::sqrt(std::max(0.0, 1.0 - z * z));
        const double phi = 2.0 * kPiDouble * u2;
        const DVec3 n(s * std::cos(phi), s * std::sin(phi), z);
        const Vec3 p = (DVec3(center) + double(radius) * n).to_float();
        return {p, double_point_error(p, max_abs(DVec3(center)) + radius), n.to_float()};
    }

    /// u = φ/2π about +y, φ from +x towards +z; v = θ/π, θ the angle from +y. In [0, 1].
    void uv(const Vec3& p, float& u, float& v) const {
        const DVec3 q = DVec3(p) - DVec3(center);
        const double len = length(q);
        u = turns(q.x, q.z);
        const double theta = len > 0.0 ? std::acos(std::clamp(q.y / len, -1.0, 1.0)) : 0.0;
        v = std::min(static_cast<float>(theta / kPiDouble), 1.f);
    }
    /// dp/du up to scale: the direction of growing φ about +y (u runs from +x towards +z).
    Vec3 dpdu(const Vec3& p) const { return cross(Vec3{0, -1, 0}, p - center); }
};

template <>
struct ShapeArray<Sphere> {
    std::vector<Sphere> spheres;
    std::vector<Sphere>& array() { return spheres; }
    const std::vector<Sphere>& array() const { return spheres; }
};

}  // namespace spt

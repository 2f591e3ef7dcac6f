// Disk: a flat circle, hittable from both sides. Intersected in double with an error-bounded t;
// hits are snapped onto the disk's plane (as for Plane), so their error is their rounding.
#pragma once
#include <algorithm>
#include <cmath>

#include "geometry/dvec3.h"
#include "geometry/ray.h"
#include "geometry/shape_array.h"
#include "geometry/surface_sample.h"

namespace spt {

struct Disk {
    Vec3 center;
    Vec3 normal{0, 1, 0};  ///< unit normal; both sides are hit, hits report this normal
    float radius = 1.f;
    int material = -1;
    int light = -1;  ///< emitter attached to the disk (Scene::lights), −1 if none

    static constexpr const char* kName = "disk";
    /// What makes the disk unrenderable, or nullptr.
    const char* defect() const {
        if (!is_finite(center)) return "disk centre must be finite";
        if (!(is_finite(normal) && std::fabs(length(normal) - 1.f) < 1e-4f)) return "disk normal must be a unit vector";
        if (!(std::isfinite(radius) && radius > 0.f)) return "disk radius must be > 0 and finite";
        return nullptr;
    }

    /// The normal normalised in double: the plane's definition for every computation.
    DVec3 unit_normal() const { return normalize(DVec3(normal)); }

    /// Distance to the hit with t > 0 (beyond the error bound of t), or infinity.
    double intersect_t(const Ray& ray) const {
        constexpr double u = kDoubleEps;
        const DVec3 n = unit_normal(), d(ray.d);
        const DVec3 f = DVec3(center) - DVec3(ray.o);  // one rounding per component
        const double num = dot(n, f), den = dot(n, d);
        const double t = num / den;  // ±inf or NaN when the ray is parallel: rejected below
        // Rounding of f (u·|f|) and of the two dot products (3u each), |nᵢ| ≤ 1; doubled.
        const double err = 2.0 * ((4.0 * u * sum_abs(f) + std::fabs(t) * 3.0 * u * sum_abs(d)) / std::fabs(den) +
                                  u * std::fabs(t));
        if (!(t > err) || t == kInfinity) return kInfinity;
        const DVec3 q = t * d - f;  // hit point relative to the centre
        return dot(q, q) <= double(radius) * radius ? t : kInfinity;
    }

    /// The hit at distance t (from intersect_t), its point snapped onto the plane.
    Hit make_hit(const Ray& ray, double t) const {
        const DVec3 n = unit_normal();
        DVec3 q = DVec3(ray.o) - DVec3(center) + t * DVec3(ray.d);
        q = q - dot(q, n) * n;
        Hit hit;
        hit.t = static_cast<float>(t);
        hit.p = (DVec3(center) + q).to_float();
        hit.p_err = double_point_error(hit.p, magnitude());
        hit.n = normal;
        hit.ns = normal;
        hit.material = material;
        hit.light = light;
        return hit;
    }

    float area() const { return static_cast<float>(kPiDouble * radius * radius); }

    /// Uniform by area: ρ = radius·√u1, angle 2π·u2. The normal is the disk's normal.
    SurfaceSample sample_area(float u1, float u2) const {
        DVec3 s, t;
        tangent_basis(unit_normal(), s, t);
        const double rho = radius * std::sqrt(double(u1)), phi = 2.0 * kPiDouble * u2;
        const Vec3 p = (DVec3(center) + (rho * std::cos(phi)) * s + (rho * std::sin(phi)) * t).to_float();
        return {p, double_point_error(p, magnitude()), normal};
    }

    /// u = φ/2π, the angle about the normal from the tangent s of tangent_basis(normal)
    /// towards t; v = ρ/radius, the distance from the centre. Both clamped to [0, 1].
    void uv(const Vec3& p, float& u, float& v) const {
        DVec3 s, t;
        tangent_basis(unit_normal(), s, t);
        const DVec3 q = DVec3(p) - DVec3(center);
        const double x = dot(q, s), y = dot(q, t);
        u = turns(x, y);
        v = static_cast<float>(std::min(std::sqrt(x * x + y * y) / radius, 1.0));
    }
    /// dp/du up to scale: the direction of growing φ about the normal.
    Vec3 dpdu(const Vec3& p) const { return cross(normal, p - center); }

private:
    /// Largest magnitude in the double arithmetic of points on the surface (for their error).
    double magnitude() const { return max_abs(DVec3(center)) + radius; }
};

template <>
struct ShapeArray<Disk> {
    std::vector<Disk> disks;
    std::vector<Disk>& array() { return disks; }
    const std::vector<Disk>& array() const { return disks; }
};

}  // namespace spt

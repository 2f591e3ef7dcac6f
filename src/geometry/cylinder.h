// Open cylinder (a tube without caps). Intersected in double through the axial-quadric solver
// (geometric discriminant, stable roots, error-bounded t); hits are reprojected onto the tube.
#pragma once
#include <algorithm>
#include <cmath>

#include "geometry/axial_quadric.h"
#include "geometry/ray.h"
#include "geometry/shape_array.h"
#include "geometry/surface_sample.h"

namespace spt {

struct Cylinder {
    Vec3 base;            ///< centre of the bottom rim
    Vec3 axis{0, 1, 0};   ///< unit direction from the bottom rim to the top rim
    float radius = 1.f;
    float height = 1.f;
    int material = -1;
    int light = -1;  ///< emitter attached to the cylinder (Scene::lights), −1 if none

    static constexpr const char* kName = "cylinder";
    /// What makes the cylinder unrenderable, or nullptr.
    const char* defect() const {
        if (!is_finite(base)) return "cylinder base must be finite";
        if (!(is_finite(axis) && std::fabs(length(axis) - 1.f) < 1e-4f)) return "cylinder axis must be a unit vector";
        if (!(std::isfinite(radius) && radius > 0.f)) return "cylinder radius must be > 0 and finite";
        if (!(std::isfinite(height) && height > 0.f)) return "cylinder height must be > 0 and finite";
        return nullptr;
    }

    /// The axis normalised in double: the surface's definition for every computation.
    DVec3 unit_axis() const { return normalize(DVec3(axis)); }

    /// Distance to the nearest hit with t > 0 (beyond the error bound of t), or infinity.
    double intersect_t(const Ray& ray) const {
        const DVec3 a = unit_axis(), d(ray.d);
        const DVec3 g = DVec3(ray.o) - DVec3(base);  // one rounding per component
        const AxialRoots roots = solve_axial_quadric(g, kDoubleEps * max_abs(g), d, a, 0.0, radius);
        double best = kInfinity;
        for (int i = 0; i < roots.count; ++i) {
            const double t = roots.t[i];
            if (!(t > roots.err[i]) || t >= best) continue;
            const double z = dot(g, a) + t * dot(d, a);
            if (z >= 0.0 && z <= height) best = t;
        }
        return best;
    }

    /// The hit at distance t (from intersect_t): the point is reprojected onto the tube at
    /// its axial position, so its error is its rounding plus that of the reprojection; the
    /// normal points away from the axis (outward), whichever side the ray came from.
    Hit make_hit(const Ray& ray, double t) const {
        const DVec3 a = unit_axis();
        const DVec3 q = DVec3(ray.o) - DVec3(base) + t * DVec3(ray.d);
        const double z = dot(q, a);
        const DVec3 n = radial_direction(q - z * a, a);
        const Vec3 p = (DVec3(base) + z * a + double(radius) * n).to_float();
        Hit hit;
        hit.t = static_cast<float>(t);
        hit.p = p;
        hit.p_err = double_point_error(p, magnitude());
        hit.n = n.to_float();
        hit.ns = hit.n;
        hit.material = material;
        hit.light = light;
        return hit;
    }

    float area() const { return static_cast<float>(2.0 * kPiDouble * radius * height); }

    /// Uniform by area: height uniform along the axis, angle uniform about it.
    SurfaceSample sample_area(float u1, float u2) const {
        const DVec3 a = unit_axis();
        const DVec3 n = direction_about_axis(a, 2.0 * kPiDouble * u2);
        const Vec3 p = (DVec3(base) + (double(height) * u1) * a + double(radius) * n).to_float();
        return {p, double_point_error(p, magnitude()), n.to_float()};
    }

    /// (u, v) as axial_uv: u = φ/2π about the axis, v the height fraction (base 0, top 1).
    void uv(const Vec3& p, float& u, float& v) const { axial_uv(p, base, unit_axis(), height, u, v); }
    /// dp/du up to scale: the direction of growing φ about the axis.
    Vec3 dpdu(const Vec3& p) const { return cross(axis, p - base); }

private:
    /// Largest magnitude in the double arithmetic of points on the surface (for their error).
    double magnitude() const { return max_abs(DVec3(base)) + radius + height; }
};

template <>
struct ShapeArray<Cylinder> {
    std::vector<Cylinder> cylinders;
    std::vector<Cylinder>& array() { return cylinders; }
    const std::vector<Cylinder>& array() const { return cylinders; }
};

}  // namespace spt

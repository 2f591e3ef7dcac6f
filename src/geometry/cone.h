// Open cone (the lateral surface, no base cap). Intersected in double through the axial-quadric
// solver (geometric discriminant, stable roots, error-bounded t) with the apex as origin; hits
// are reprojected onto the cone's generator line through them.
#pragma once
#include <algorithm>
#include <cmath>

#include "geometry/axial_quadric.h"
#include "geometry/ray.h"
#include "geometry/shape_array.h"
#include "geometry/surface_sample.h"

namespace spt {

struct Cone {
    Vec3 base;            ///< centre of the base rim
    Vec3 axis{0, 1, 0};   ///< unit direction from the base towards the apex
    float radius = 1.f;   ///< base radius (> 0)
    float height = 1.f;   ///< apex = base + axis·height (> 0)
    int material = -1;
    int light = -1;  ///< emitter attached to the cone (Scene::lights), −1 if none

    static constexpr const char* kName = "cone";
    /// What makes the cone unrenderable, or nullptr.
    const char* defect() const {
        if (!is_finite(base)) return "cone base must be finite";
        if (!(is_finite(axis) && std::fabs(length(axis) - 1.f) < 1e-4f)) return "cone axis must be a unit vector";
        if (!(std::isfinite(radius) && radius > 0.f)) return "cone radius must be > 0 and finite";
        if (!(std::isfinite(height) && height > 0.f)) return "cone height must be > 0 and finite";
        return nullptr;
    }

    /// The axis normalised in double: the surface's definition for every computation.
    DVec3 unit_axis() const { return normalize(DVec3(axis)); }
    /// Length of a generator (base rim to apex).
    double slant() const { return std::sqrt(double(radius) * radius + double(height) * height); }

    /// Distance to the nearest hit with t > 0 (beyond the error bound of t), or infinity.
    double intersect_t(const Ray& ray) const {
        const DVec3 a = unit_axis(), d(ray.d);
        const DVec3 f = DVec3(ray.o) - DVec3(base);
        const DVec3 g = f - double(height) * a;  // from the apex
        const double g_err = 2.0 * kDoubleEps * (max_abs(f) + height + max_abs(g));
        const double k = double(radius) / height;
        const AxialRoots roots = solve_axial_quadric(g, g_err, d, a, k, 0.0);
        double best = kInfinity;
        for (int i = 0; i < roots.count; ++i) {
            const double t = roots.t[i];
            if (!(t > roots.err[i]) || t >= best) continue;
            const double z = dot(g, a) + t * dot(d, a);  // ≤ 0 below the apex
            if (z >= -double(height) && z <= 0.0) best = t;  // this nappe, between base and apex
        }
        return best;
    }

    /// The hit at distance t (from intersect_t): the point is projected onto the generator
    /// (the line from the base rim to the apex in the half-plane through the axis and the
    /// point), so its error is its rounding plus that of the projection. The outward normal
    /// is constant along a generator: (height·radial + radius·axis)/slant.
    Hit make_hit(const Ray& ray, double t) const {
        const DVec3 q = DVec3(ray.o) - DVec3(base) + t * DVec3(ray.d);
        Hit hit;
        hit.t = static_cast<float>(t);
        surface_point(q, hit.p, hit.n);
        hit.p_err = double_point_error(hit.p, magnitude());
        hit.ns = hit.n;
        hit.material = material;
        hit.light = light;
        return hit;
    }

    float area() const { return static_cast<float>(kPiDouble * radius * slant()); }

    /// Uniform by area: the density grows linearly with the distance w from the apex, so
    /// w = √u1 (as a fraction of the slant); angle uniform about the axis.
    SurfaceSample sample_area(float u1, float u2) const {
        const DVec3 a = unit_axis();
        const double w = std::sqrt(double(u1));
        const DVec3 e = direction_about_axis(a, 2.0 * kPiDouble * u2);
        SurfaceSample out;
        out.p = (DVec3(base) + (double(height) * (1.0 - w)) * a + (double(radius) * w) * e).to_float();
        out.p_err = double_point_error(out.p, magnitude());
        out.n = normal(e, a).to_float();
        return out;
    }

    /// (u, v) as axial_uv: u = φ/2π about the axis, v the height fraction (base 0, top 1).
    void uv(const Vec3& p, float& u, float& v) const { axial_uv(p, base, unit_axis(), height, u, v); }
    /// dp/du up to scale: the direction of growing φ about the axis.
    Vec3 dpdu(const Vec3& p) const { return cross(axis, p - base); }

private:
    /// Largest magnitude in the double arithmetic of points on the surface (for their error).
    double magnitude() const { return max_abs(DVec3(base)) + radius + height; }
    DVec3 normal(const DVec3& radial, const DVec3& a) const {
        return (double(height) * radial + double(radius) * a) * (1.0 / slant());
    }
    /// The point of the cone nearest q (relative to the base) in q's half-plane, and the
    /// normal there. On the axis itself any half-plane will do.
    void surface_point(const DVec3& q, Vec3& p, Vec3& n) const {
        const DVec3 a = unit_axis();
        const double z = dot(q, a);
        const DVec3 r = q - z * a;
        const double len = length(r);
        const DVec3 e = radial_direction(r, a);
        // Generator: (radius·(1 − s), height·s) for s in [0, 1]; project (len, z) onto it.
        const double rr = radius, h = height;
        const double s = std::clamp(((rr - len) * rr + z * h) / (rr * rr + h * h), 0.0, 1.0);
        p = (DVec3(base) + (h * s) * a + (rr * (1.0 - s)) * e).to_float();
        n = normal(e, a).to_float();
    }
};

template <>
struct ShapeArray<Cone> {
    std::vector<Cone> cones;
    std::vector<Cone>& array() { return cones; }
    const std::vector<Cone>& array() const { return cones; }
};

}  // namespace spt

// Infinite plane dot(n, p) = offset. Intersected in double and the hit point snapped back onto
// the plane, so the hit point's only error is its final rounding to float.
#pragma once
#include <cmath>
#include <cstdint>

#include "core/frame.h"
#include "core/simd.h"
#include "geometry/ray.h"
#include "geometry/shape_array.h"

namespace spt {

struct Plane {
    Vec3 normal;         ///< unit normal; the side it points to is the plane's front
    float offset = 0.f;  ///< dot(normal, p) for points p on the plane
    int material = -1;
    int light = -1;  ///< emitter attached to the plane (Scene::lights), −1 if none
    /// Tangents of the plane (u, v directions of its surface coordinates), set by set_frame().
    Vec3 tangent_u{1, 0, 0}, tangent_v{0, 0, 1};

    static constexpr const char* kName = "plane";
    /// What makes the plane unrenderable, or nullptr.
    const char* defect() const {
        if (!(is_finite(normal) && std::isfinite(offset))) return "plane must be finite";
        if (!(std::fabs(length(normal) - 1.f) < 1e-4f)) return "plane normal must be unit length";
        return nullptr;
    }

    /// Sets the tangents from the normal (Frame's orthonormal basis).
    void set_frame();

    /// Distance along the ray to the plane, or infinity when there is no hit with t > 0.
    double intersect_t(const Ray& ray) const {
        const double denom = double(normal.x) * ray.d.x + double(normal.y) * ray.d.y +
                             double(normal.z) * ray.d.z;
        const double no = double(normal.x) * ray.o.x + double(normal.y) * ray.o.y +
                          double(normal.z) * ray.o.z;
        const double t = (offset - no) / denom;  // ±inf or NaN when parallel: rejected below
        return t > 0.0 ? t : kInfinity;
    }

    /// make_hit for a plane whose normal is ±axis: the point's coordinate on that axis is the
    /// plane's exactly (what the projection below gives), the other two are o + t·d. The axis
    /// lane is chosen with a mask: writing a stored point at index `axis` and reading it back
    /// stalls the path on the reload.
    Hit make_axis_hit(const Ray& ray, double t, int axis) const {
        const Double4 o = {ray.o.x, ray.o.y, ray.o.z, 0.0}, d = {ray.d.x, ray.d.y, ray.d.z, 0.0};
        // normal[axis] is ±1 and the other two components are 0, so their sum is normal[axis].
        const double on_plane = double(offset) * (normal.x + normal.y + normal.z);
        const Long4 is_axis = Long4{0, 1, 2, 3} == axis;
        const Double4 p = is_axis ? Double4{} + on_plane : o + t * d;
        Hit hit;
        hit.t = static_cast<float>(t);
        hit.p = {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])};
        hit.p_err = rounded_point_error(hit.p);
        hit.n = normal;
        fill_surface(hit);
        return hit;
    }

    /// The parts of a hit that do not depend on the ray: shading normal, material, light.
    void fill_surface(Hit& hit) const {
        hit.ns = normal;
        hit.material = material;
        hit.light = light;
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
        fill_surface(hit);
        return hit;
    }

    /// (u, v) = (dot(p, tangent_u), dot(p, tangent_v)): coordinates in scene units, unbounded.
    void uv(const Vec3& p, float& u, float& v) const {
        u = dot(p, tangent_u);
        v = dot(p, tangent_v);
    }
    Vec3 dpdu(const Vec3&) const { return tangent_u; }
};

inline void Plane::set_frame() {
    const Frame f(normal);
    tangent_u = f.s;
    tangent_v = f.t;
}

template <>
struct ShapeArray<Plane> {
    std::vector<Plane> planes;
    std::vector<Plane>& array() { return planes; }
    const std::vector<Plane>& array() const { return planes; }
};

}  // namespace spt

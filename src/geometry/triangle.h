// Triangle shape with the watertight ray-triangle test of Woop, Benthin and Wald (JCGT 2013),
// as refined in pbrt-v4: the edge functions are evaluated in double, where products of floats
// are exact, so their signs are exact for the sheared vertices; neighbours share an edge
// through identical operations and no ray slips between them. The hit point comes from the
// barycentrics (never o + t·d) with pbrt's error bound, and t must exceed a conservative bound
// on its own rounding error so that rays leaving a triangle do not hit it again.
#pragma once
#include <cmath>
#include <optional>

#include "geometry/dvec3.h"
#include "geometry/ray.h"
#include "geometry/shape_array.h"
#include "geometry/surface_sample.h"

namespace spt {

struct TriangleIntersection {
    double t;
    double b0, b1, b2;  ///< barycentric weights of p0, p1, p2
};

/// What a mesh's vertices add to its triangles: normals for smooth shading, and (u, v).
struct TriangleAttributes {
    Vec3 n[3];                ///< unit vertex normals (Vec3{} each when the mesh has none)
    float uv[3][2] = {};      ///< vertex (u, v)
    bool has_normals = false, has_uv = false;

    /// The interpolated unit normal at barycentrics b, turned to the side of the geometric
    /// normal ng (shading normals stay on the geometric side: Hit::ns).
    Vec3 shading_normal(double b0, double b1, double b2, const Vec3& ng) const {
        const Vec3 n_i = n[0] * static_cast<float>(b0) + n[1] * static_cast<float>(b1) + n[2] * static_cast<float>(b2);
        const float len = length(n_i);
        if (!(len > 0.f) || !std::isfinite(len)) return ng;  // opposite normals cancel: no shading normal
        return face_forward(n_i / len, ng);
    }
};

/// The ray's part of the watertight test, computed once per ray (a BVH tests many triangles
/// with it): translate to the ray origin, permute so that z is the largest direction
/// component and shear so that the ray becomes the +z axis.
struct ShearedRay {
    Vec3 o;
    int kx = 0, ky = 1, kz = 2;
    float sx = 0.f, sy = 0.f, sz = 0.f;
    bool valid = false;  ///< false for d = 0 (not a ray): nothing is hit

    explicit ShearedRay(const Ray& ray) : o(ray.o) {
        const Vec3 ad = abs(ray.d);
        kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
        kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
        const float dx = ray.d[kx], dy = ray.d[ky], dz = ray.d[kz];
        valid = dz != 0.f;
        if (valid) sx = -dx / dz, sy = -dy / dz, sz = 1.f / dz;
    }
};

/// pbrt's zero-area check, in float: such a triangle is never hit (rounding could otherwise
/// make it hittable). A BVH drops these when it is built.
inline bool has_zero_float_area(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
    return length_squared(cross(p2 - p0, p1 - p0)) == 0.f;
}

/// The watertight test of the triangle (p0, p1, p2) without the zero-area check: an
/// intersection with t in (0, t_max), or nullopt.
inline std::optional<TriangleIntersection> intersect_triangle(const Vec3& p0, const Vec3& p1, const Vec3& p2,
                                                              const ShearedRay& r, double t_max) {
    if (!r.valid) return std::nullopt;
    auto shear = [&](const Vec3& p, float& x, float& y, float& z) {
        const Vec3 q = p - r.o;
        z = q[r.kz];
        x = q[r.kx] + r.sx * z;
        y = q[r.ky] + r.sy * z;
    };
    float x0, y0, z0, x1, y1, z1, x2, y2, z2;
    shear(p0, x0, y0, z0);
    shear(p1, x1, y1, z1);
    shear(p2, x2, y2, z2);
    const float sz = r.sz;

    // Edge functions: exact products, one rounding each, so the signs are exact.
    const double e0 = double(x1) * y2 - double(y1) * x2;
    const double e1 = double(x2) * y0 - double(y2) * x0;
    const double e2 = double(x0) * y1 - double(y0) * x1;
    if ((e0 < 0 || e1 < 0 || e2 < 0) && (e0 > 0 || e1 > 0 || e2 > 0)) return std::nullopt;
    const double det = e0 + e1 + e2;
    if (det == 0.0) return std::nullopt;

    // Scaled distance, compared with t_max before dividing.
    const double zs0 = double(sz) * z0, zs1 = double(sz) * z1, zs2 = double(sz) * z2;
    const double t_scaled = e0 * zs0 + e1 * zs1 + e2 * zs2;
    if (det < 0 && (t_scaled >= 0 || t_scaled < t_max * det)) return std::nullopt;
    if (det > 0 && (t_scaled <= 0 || t_scaled > t_max * det)) return std::nullopt;
    const double inv_det = 1.0 / det;
    const double t = t_scaled * inv_det;

    // t must be positive beyond its rounding error (pbrt-v4, after Woop et al.): the
    // deltas bound the float error of the sheared coordinates and of the edge functions.
    const double max_z = std::max({std::fabs(zs0), std::fabs(zs1), std::fabs(zs2)});
    const double max_x = std::max({std::fabs(double(x0)), std::fabs(double(x1)), std::fabs(double(x2))});
    const double max_y = std::max({std::fabs(double(y0)), std::fabs(double(y1)), std::fabs(double(y2))});
    const double delta_z = gamma_bound(3) * max_z;
    const double delta_x = gamma_bound(5) * (max_x + max_z);
    const double delta_y = gamma_bound(5) * (max_y + max_z);
    const double delta_e = 2 * (gamma_bound(2) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    const double max_e = std::max({std::fabs(e0), std::fabs(e1), std::fabs(e2)});
    const double delta_t =
        3 * (gamma_bound(3) * max_e * max_z + delta_e * max_z + delta_z * max_e) * std::fabs(inv_det);
    if (t <= delta_t) return std::nullopt;
    return TriangleIntersection{t, e0 * inv_det, e1 * inv_det, e2 * inv_det};
}

struct Triangle {
    Vec3 p0, p1, p2;  ///< counter-clockwise seen from the front (the side n points to)
    int material = -1;
    int light = -1;       ///< emitter attached to the triangle's shape (Scene::lights), −1 if none
    /// Per-vertex normals and (u, v) (Scene::triangle_attributes), −1 if none: then (u, v)
    /// are the barycentrics (b1, b2) and the shading normal is the geometric one.
    int attributes = -1;

    static constexpr const char* kName = "triangle";
    /// What makes the triangle unrenderable, or nullptr (its attributes index is the scene's
    /// to check).
    const char* defect() const {
        if (!(is_finite(p0) && is_finite(p1) && is_finite(p2))) return "triangle vertices must be finite";
        if (is_degenerate()) return "triangle has zero area (collinear or repeated vertices)";
        return nullptr;
    }

    /// Unnormalised geometric normal cross(p1 − p0, p2 − p0), in double.
    void cross_double(double out[3]) const {
        const double ax = double(p1.x) - p0.x, ay = double(p1.y) - p0.y, az = double(p1.z) - p0.z;
        const double bx = double(p2.x) - p0.x, by = double(p2.y) - p0.y, bz = double(p2.z) - p0.z;
        out[0] = ay * bz - az * by, out[1] = az * bx - ax * bz, out[2] = ax * by - ay * bx;
    }
    /// Zero area (collinear or repeated vertices): such a triangle cannot be rendered.
    bool is_degenerate() const {
        double c[3];
        cross_double(c);
        const double len2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
        return !(len2 > 0.0) || !std::isfinite(len2);
    }

    /// Intersection with t in (0, t_max), or nullopt.
    std::optional<TriangleIntersection> intersect(const Ray& ray, double t_max) const {
        // Zero-area triangles (pbrt's check): rounding could otherwise make them hittable.
        if (has_zero_float_area(p0, p1, p2)) return std::nullopt;
        return intersect_triangle(p0, p1, p2, ShearedRay(ray), t_max);
    }

    /// Distance to the hit, or infinity (the cheap part of intersect(), for nearest-hit search).
    double intersect_t(const Ray& ray, double t_max) const {
        const auto hit = intersect(ray, t_max);
        return hit ? hit->t : kInfinity;
    }

    Hit make_hit(const TriangleIntersection& ti) const {
        // The point from the barycentrics, whose error pbrt bounds by γ7·Σ|bᵢpᵢ|.
        Hit hit;
        hit.t = static_cast<float>(ti.t);
        const double p[3] = {ti.b0 * p0.x + ti.b1 * p1.x + ti.b2 * p2.x,
                             ti.b0 * p0.y + ti.b1 * p1.y + ti.b2 * p2.y,
                             ti.b0 * p0.z + ti.b1 * p1.z + ti.b2 * p2.z};
        hit.p = {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])};
        const Vec3 abs_sum = abs(p0) * static_cast<float>(std::fabs(ti.b0)) +
                             abs(p1) * static_cast<float>(std::fabs(ti.b1)) +
                             abs(p2) * static_cast<float>(std::fabs(ti.b2));
        hit.p_err = abs_sum * gamma_bound(7) + rounded_point_error(hit.p);
        double c[3];
        cross_double(c);
        const double inv_len = 1.0 / std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        hit.n = {static_cast<float>(c[0] * inv_len), static_cast<float>(c[1] * inv_len),
                 static_cast<float>(c[2] * inv_len)};
        hit.ns = hit.n;
        hit.material = material;
        hit.light = light;
        return hit;
    }

    float area() const {
        double c[3];
        cross_double(c);
        return static_cast<float>(0.5 * std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]));
    }

    /// Uniform by area: barycentrics (1 − √u1, u2·√u1, ·) (the square-root warp), the point
    /// from them in double with make_hit's error bound; n as in make_hit.
    SurfaceSample sample_area(float u1, float u2) const {
        const double su = std::sqrt(double(u1)), b0 = 1.0 - su, b1 = u2 * su, b2 = 1.0 - b0 - b1;
        const Vec3 p = (b0 * DVec3(p0) + b1 * DVec3(p1) + b2 * DVec3(p2)).to_float();
        const Vec3 abs_sum = abs(p0) * static_cast<float>(b0) + abs(p1) * static_cast<float>(b1) +
                             abs(p2) * static_cast<float>(b2);
        double c[3];
        cross_double(c);
        return {p, abs_sum * gamma_bound(7) + rounded_point_error(p), normalize(DVec3(c[0], c[1], c[2])).to_float()};
    }

    /// (u, v) = (b1, b2), the barycentrics of p1 and p2, recomputed from p (its projection
    /// onto the plane, by least squares in double) and clamped to [0, 1].
    void uv(const Vec3& p, float& u, float& v) const {
        const DVec3 e1 = DVec3(p1) - DVec3(p0), e2 = DVec3(p2) - DVec3(p0), w = DVec3(p) - DVec3(p0);
        const double d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2);
        const double w1 = dot(w, e1), w2 = dot(w, e2), det = d11 * d22 - d12 * d12;
        u = static_cast<float>(std::clamp((d22 * w1 - d12 * w2) / det, 0.0, 1.0));
        v = static_cast<float>(std::clamp((d11 * w2 - d12 * w1) / det, 0.0, 1.0));
    }
};

template <>
struct ShapeArray<Triangle> {
    /// Triangles of meshes, quads and single triangles, in one flat array.
    std::vector<Triangle> triangles;
    std::vector<Triangle>& array() { return triangles; }
    const std::vector<Triangle>& array() const { return triangles; }
};

}  // namespace spt

// Rays, hit records, and error-bounded spawning of rays from surfaces.
#pragma once
#include <bit>
#include <cstdint>

#include "core/vec3.h"

namespace spt {

/// o + t·d for t in (0, t_max); d is unit length throughout the renderer.
struct Ray {
    Vec3 o, d;
    float t_max = kInfinity;
};

/// Which shape array a primitive index refers to: the shape types of the set in the order of
/// ShapeTypes (shape.h), then `moving`: Scene::moving_shapes; `instance`: a MeshInstance (a
/// placed InstancedMesh), in the top level of the BVH only.
enum class ShapeKind : unsigned char { sphere, plane, triangle, disk, cylinder, cone, moving, instance };

/// A primitive of the scene: its shape kind and its index in that kind's array, in 32 bits
/// (the BVH's primitive lists hold these too); the kind takes as few bits as ShapeKind needs.
struct PrimId {
    static constexpr int kKindBits = std::bit_width(static_cast<unsigned>(ShapeKind::instance));
    static constexpr int kIndexBits = 32 - kKindBits;
    std::uint32_t bits = ~0u;

    PrimId() = default;
    PrimId(ShapeKind kind, std::uint32_t index) : bits(std::uint32_t(kind) << kIndexBits | index) {}
    ShapeKind kind() const { return static_cast<ShapeKind>(bits >> kIndexBits); }
    std::uint32_t index() const { return bits & ((1u << kIndexBits) - 1u); }
    bool valid() const { return bits != ~0u; }
    bool operator==(const PrimId&) const = default;
};

/// A ray-surface intersection. p_err bounds |p − true surface point| per axis, so rays can
/// leave the surface by exactly as much as the rounding error requires (pbrt's approach)
/// instead of a fixed epsilon that breaks at large or small scene scales.
///
/// Kept at 64 bytes: GCC scalarises an optional<Hit> of that size into registers in the path
/// loop, and a larger record (with (u, v) inside) goes through memory, which costs a third of
/// the time per path in small scenes. Surface coordinates are therefore computed on request
/// (Scene::surface_uv), from the primitive and the point.
struct Hit {
    float t = kInfinity;
    Vec3 p;
    Vec3 p_err;
    Vec3 n;            ///< unit geometric normal of the shape (outward for closed shapes)
    /// Unit shading normal, on the side of n (dot(ns, n) > 0): n itself except on meshes
    /// with vertex normals (smooth shading). BSDFs work around ns; rays leave along n.
    Vec3 ns;
    int material = -1;
    int light = -1;    ///< the emitter attached to the shape (index into Scene::lights), or −1
    PrimId prim;       ///< the primitive hit (set by the scene's intersect)
};
static_assert(sizeof(Hit) == 64, "see the comment on Hit");

/// Origin for a ray leaving p towards w: p pushed along ±n past its error box, then one
/// more ulp away per axis so that rounding cannot bring it back (pbrt-v4 OffsetRayOrigin).
inline Vec3 offset_ray_origin(const Vec3& p, const Vec3& p_err, const Vec3& n, const Vec3& w) {
    const float dist = dot(abs(n), p_err);
    Vec3 offset = n * dist;
    if (dot(w, n) < 0.f) offset = -offset;
    Vec3 po = p + offset;
    for (int i = 0; i < 3; ++i) {
        if (offset[i] > 0.f) po[i] = next_float_up(po[i]);
        else if (offset[i] < 0.f) po[i] = next_float_down(po[i]);
    }
    return po;
}

inline Ray spawn_ray(const Hit& hit, const Vec3& w) {
    return {offset_ray_origin(hit.p, hit.p_err, hit.n, w), w, kInfinity};
}

/// Shadow ray from the hit towards a point (a point light): stops just short of it.
inline Ray spawn_ray_to(const Hit& hit, const Vec3& target) {
    const Vec3 o = offset_ray_origin(hit.p, hit.p_err, hit.n, target - hit.p);
    const Vec3 to = target - o;
    const float dist = length(to);
    return {o, to / dist, dist * (1.f - 1e-4f)};
}

/// Ray between two points, each pushed off its surface past its error bound towards the other
/// (a point with a zero normal, a point light or the camera, stays where it is); it stops
/// just short of the second point, so neither end occludes it (shadow rays, connections).
inline Ray spawn_ray_between(const Vec3& p0, const Vec3& err0, const Vec3& n0, const Vec3& p1, const Vec3& err1,
                             const Vec3& n1) {
    const Vec3 o = offset_ray_origin(p0, err0, n0, p1 - p0);
    const Vec3 target = offset_ray_origin(p1, err1, n1, o - p1);
    const Vec3 d = target - o;
    const float dist = length(d);
    return {o, d / dist, dist * (1.f - 1e-4f)};  // t_max 0 (no ray) when the points coincide
}

/// Error bound of a point computed in double precision and rounded to float: half an ulp
/// per axis from the rounding, padded to a few ulps for the double-precision arithmetic.
inline Vec3 rounded_point_error(const Vec3& p) { return abs(p) * gamma_bound(5); }

}  // namespace spt

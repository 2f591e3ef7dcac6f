// Rays, hit records, and error-bounded spawning of rays from surfaces.
#pragma once
#include "core/vec3.h"

namespace spt {

/// o + t·d for t in (0, t_max); d is unit length throughout the renderer.
struct Ray {
    Vec3 o, d;
    float t_max = kInfinity;
};

/// A ray-surface intersection. p_err bounds |p − true surface point| per axis, so rays can
/// leave the surface by exactly as much as the rounding error requires (pbrt's approach)
/// instead of a fixed epsilon that breaks at large or small scene scales.
struct Hit {
    float t = kInfinity;
    Vec3 p;
    Vec3 p_err;
    Vec3 n;            ///< unit geometric normal of the shape (outward for spheres)
    int material = -1;
};

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

/// Error bound of a point computed in double precision and rounded to float: half an ulp
/// per axis from the rounding, padded to a few ulps for the double-precision arithmetic.
inline Vec3 rounded_point_error(const Vec3& p) { return abs(p) * gamma_bound(5); }

}  // namespace spt

// Rigid motion over the shutter interval: keyframed translations and rotations about a pivot,
// for shapes and point lights that move while the shutter is open (motion blur).
//
// World position of a point x given at rest (as written in the scene file) at time t:
//     M(t)·x = R(t)·(x − c) + c + T(t)
// with c the pivot, T(t) linear between keyframes and R(t) the spherical linear
// interpolation (slerp, Shoemake 1985) of the keyframes' rotations, which takes the shorter
// arc: a turn of 180° or more between two keyframes needs keyframes in between. Before the
// first keyframe and after the last the motion holds still. R is a rotation, so lengths and
// angles are kept: a unit direction stays unit and a ray's t is the same in both spaces.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/math.h"
#include "core/vec3.h"
#include "geometry/aabb.h"

namespace spt {

/// A unit quaternion w + (x, y, z): the rotation by angle θ about unit axis a is
/// (cos θ/2, a·sin θ/2).
struct Quaternion {
    float w = 1.f;
    Vec3 v{0, 0, 0};

    static Quaternion axis_angle(const Vec3& unit_axis, float radians) {
        return {std::cos(0.5f * radians), unit_axis * std::sin(0.5f * radians)};
    }
    /// The rotated vector (Rodrigues, through the quaternion: u + 2w(v×u) + 2v×(v×u)).
    Vec3 rotate(const Vec3& u) const {
        const Vec3 t = cross(v, u) * 2.f;
        return u + t * w + cross(v, t);
    }
    /// The inverse rotation (the conjugate, for a unit quaternion).
    Quaternion inverse() const { return {w, -v}; }
};

inline float dot(const Quaternion& a, const Quaternion& b) { return a.w * b.w + dot(a.v, b.v); }

/// Spherical linear interpolation along the shorter arc; s in [0, 1]. Nearly equal
/// rotations fall back to a normalised linear blend (slerp's sin θ → 0 limit).
inline Quaternion slerp(const Quaternion& a, Quaternion b, float s) {
    float c = dot(a, b);
    if (c < 0.f) c = -c, b = {-b.w, -b.v};  // q and −q are the same rotation: take the nearer
    float wa = 1.f - s, wb = s;
    if (c < 0.9995f) {
        const float theta = std::acos(c), inv_sin = 1.f / std::sin(theta);
        wa = std::sin((1.f - s) * theta) * inv_sin;
        wb = std::sin(s * theta) * inv_sin;
    }
    Quaternion q{wa * a.w + wb * b.w, a.v * wa + b.v * wb};
    const float inv_len = 1.f / std::sqrt(dot(q, q));
    return {q.w * inv_len, q.v * inv_len};
}

/// One keyframe: where the motion stands at `time`.
struct Keyframe {
    float time = 0.f;
    Vec3 translation{0, 0, 0};
    Quaternion rotation;
};

/// The motion's transform at one time: x ↦ R·(x − c) + c + T, and back.
struct RigidTransform {
    Quaternion rotation;
    Vec3 pivot, translation;

    Vec3 point(const Vec3& x) const { return rotation.rotate(x - pivot) + pivot + translation; }
    Vec3 vector(const Vec3& d) const { return rotation.rotate(d); }
    Vec3 inverse_point(const Vec3& y) const { return rotation.inverse().rotate(y - translation - pivot) + pivot; }
    Vec3 inverse_vector(const Vec3& d) const { return rotation.inverse().rotate(d); }
};

/// Keyframes in increasing time (the loader checks it); none or one: the thing stands still.
struct RigidMotion {
    std::vector<Keyframe> keys;
    Vec3 pivot{0, 0, 0};

    bool is_static() const { return keys.size() < 2; }

    /// The transform at time t (clamped to the first and last keyframes). Out of line: the
    /// slerp inlined into a static scene's light loop makes GCC stop inlining the shadow ray's
    /// offset there.
    [[gnu::noinline]] RigidTransform at(float t) const {
        if (keys.empty()) return {Quaternion{}, pivot, Vec3(0, 0, 0)};
        if (t <= keys.front().time) return {keys.front().rotation, pivot, keys.front().translation};
        if (t >= keys.back().time) return {keys.back().rotation, pivot, keys.back().translation};
        // The interval [k0, k1] holding t (few keyframes: a linear search).
        std::size_t i = 1;
        while (keys[i].time < t) ++i;
        const Keyframe& k0 = keys[i - 1];
        const Keyframe& k1 = keys[i];
        const float s = (t - k0.time) / (k1.time - k0.time);
        return {slerp(k0.rotation, k1.rotation, s), pivot, k0.translation * (1.f - s) + k1.translation * s};
    }

    /// A box holding `rest` (the bounds at rest) at every time. Translations are linear
    /// between keyframes, so the hull of the keyframes' boxes holds the translated boxes in
    /// between; with any rotation, the box is replaced by the ball around the pivot that
    /// holds it (a rotation about the pivot keeps the ball). Padded by a relative 1e-5 so
    /// that rounding in the transforms cannot step outside it.
    Aabb swept_bounds(const Aabb& rest) const {
        bool rotates = false;
        for (const Keyframe& k : keys) rotates |= k.rotation.w < 1.f;
        Aabb local = rest;
        if (rotates) {
            float r2 = 0.f;
            for (int corner = 0; corner < 8; ++corner) {
                const Vec3 p((corner & 1) ? rest.hi.x : rest.lo.x, (corner & 2) ? rest.hi.y : rest.lo.y,
                             (corner & 4) ? rest.hi.z : rest.lo.z);
                r2 = std::max(r2, length_squared(p - pivot));
            }
            const float r = std::sqrt(r2);
            local = Aabb{pivot - Vec3(r, r, r), pivot + Vec3(r, r, r)};
        }
        Aabb swept;
        if (keys.empty()) swept = local;
        for (const Keyframe& k : keys) swept.expand(Aabb{local.lo + k.translation, local.hi + k.translation});
        const Vec3 extent = swept.hi - swept.lo;
        const float pad = 1e-5f * (std::max({extent.x, extent.y, extent.z}) +
                                   std::max({std::fabs(swept.lo.x), std::fabs(swept.lo.y), std::fabs(swept.lo.z),
                                             std::fabs(swept.hi.x), std::fabs(swept.hi.y), std::fabs(swept.hi.z)}));
        return Aabb{swept.lo - Vec3(pad, pad, pad), swept.hi + Vec3(pad, pad, pad)};
    }
};

}  // namespace spt

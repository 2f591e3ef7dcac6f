// Bounds of what a light (or a set of lights) can send towards a point: where it is, how much
// it emits, and in which directions. The light BVH (render/light_bvh.h) keeps one per node
// and chooses among its children by the importance below.
//
// A LightBounds holds a box, the total power phi, and a normal cone (Conty Estévez & Kulla
// 2018, "Importance Sampling of Many Lights with Adaptive Tree Splitting", §4; the form of
// pbrt-v4's LightBounds, Pharr, Jakob & Humphreys, "Physically Based Rendering", 4th ed.,
// §12.6.3): every emitting normal lies within theta_o of the axis w, and every emitting
// normal emits within theta_e of itself (pi/2 for a surface, 0 beyond a spot's cone); a
// two-sided emitter also emits around −w.
//
// Importance of the bounds for a shading point p (normal n, or none in a medium), with
// d the distance from the box's centre, theta_w the angle between w and the direction from
// the centre to p, theta_b the half angle the box's bounding sphere subtends at p (pi when p
// is inside it), and theta_i the angle between n and that direction:
//     theta' = max(0, theta_w − theta_o − theta_b)   (the emitting normal closest to p)
//     I = 0                                 if theta' ≥ theta_e (nothing emits towards p)
//     I = phi · cos theta' / max(d², (diagonal/2)²) · cos(max(0, theta_i − theta_b))
// Each max(0, ·) keeps the bound conservative: a light that can send p light never gets
// importance 0 (the BVH's density must cover every contributing light for unbiasedness).
// The squared-distance clamp keeps points inside or near a node from getting an unbounded
// share. The cosines of differences are computed without trigonometric functions.
#pragma once
#include <algorithm>
#include <cmath>
#include <optional>

#include "core/math.h"
#include "geometry/aabb.h"
#include "geometry/bvh.h"
#include "model/lights/light.h"

namespace spt {

struct LightBounds {
    Aabb bounds;
    float phi = 0.f;  ///< power (light_power's scale); 0: the bounds of nothing
    Vec3 w{0.f, 0.f, 1.f};     ///< axis of the normal cone (unit)
    float cos_theta_o = 1.f;   ///< the normals' spread around w
    float cos_theta_e = 0.f;   ///< each normal's emission spread
    bool two_sided = false;
};

namespace light_bounds_detail {
/// cos(max(0, a − b)) from the sines and cosines of a and b in [0, pi].
inline float cos_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
    if (cos_a > cos_b) return 1.f;  // a < b
    return cos_a * cos_b + sin_a * sin_b;
}
/// sin(max(0, a − b)) likewise.
inline float sin_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
    if (cos_a > cos_b) return 0.f;
    return sin_a * cos_b - cos_a * sin_b;
}
/// v rotated by `angle` about the unit axis k (Rodrigues).
inline Vec3 rotate(const Vec3& v, const Vec3& k, float angle) {
    const float c = std::cos(angle), s = std::sin(angle);
    return v * c + cross(k, v) * s + k * (dot(k, v) * (1.f - c));
}
}  // namespace light_bounds_detail

/// Importance of `b` for a shading point p with unit normal n (zero vector: no normal, as in
/// a medium). Zero only where no light inside the bounds can reach p.
inline float light_importance(const LightBounds& b, const Vec3& p, const Vec3& n) {
    using namespace light_bounds_detail;
    if (!(b.phi > 0.f)) return 0.f;
    const Vec3 pc = b.bounds.centroid();
    const Vec3 half_diag = (b.bounds.hi - b.bounds.lo) * 0.5f;
    const float r2 = length_squared(half_diag);
    const Vec3 to_p = p - pc;
    const float d2_raw = length_squared(to_p);
    const float d2 = std::max({d2_raw, r2, 1e-30f});
    const Vec3 wi = d2_raw > 0.f ? to_p / std::sqrt(d2_raw) : Vec3{0.f, 0.f, 1.f};

    float cos_w = dot(b.w, wi);
    if (b.two_sided) cos_w = std::fabs(cos_w);
    cos_w = std::clamp(cos_w, -1.f, 1.f);
    const float sin_w = safe_sqrt(1.f - cos_w * cos_w);

    // The box's bounding sphere seen from p: inside it, every direction.
    float sin_b = 0.f, cos_b = -1.f;
    if (d2_raw > r2) {
        const float sin2_b = r2 / d2_raw;
        sin_b = std::sqrt(sin2_b);
        cos_b = safe_sqrt(1.f - sin2_b);
    } else {
        sin_b = 0.f;  // theta_b = pi
    }

    const float cos_o = b.cos_theta_o, sin_o = safe_sqrt(1.f - cos_o * cos_o);
    const float cos_x = cos_sub_clamped(sin_w, cos_w, sin_o, cos_o);
    const float sin_x = sin_sub_clamped(sin_w, cos_w, sin_o, cos_o);
    const float cos_p = cos_sub_clamped(sin_x, cos_x, sin_b, cos_b);
    if (cos_p <= b.cos_theta_e) return 0.f;

    float importance = b.phi * cos_p / d2;
    if (n.x != 0.f || n.y != 0.f || n.z != 0.f) {
        const float cos_i = std::min(std::fabs(dot(wi, n)), 1.f);
        const float sin_i = safe_sqrt(1.f - cos_i * cos_i);
        importance *= cos_sub_clamped(sin_i, cos_i, sin_b, cos_b);
    }
    return std::max(importance, 0.f);
}

/// The bounds of both (the smallest cone around both cones, Conty Estévez & Kulla 2018,
/// Algorithm 1).
inline LightBounds light_bounds_union(const LightBounds& a, const LightBounds& b) {
    using namespace light_bounds_detail;
    if (!(a.phi > 0.f)) return b;
    if (!(b.phi > 0.f)) return a;
    LightBounds u;
    u.bounds = a.bounds;
    u.bounds.expand(b.bounds);
    u.phi = a.phi + b.phi;
    u.two_sided = a.two_sided || b.two_sided;
    u.cos_theta_e = std::min(a.cos_theta_e, b.cos_theta_e);
    const float theta_a = std::acos(std::clamp(a.cos_theta_o, -1.f, 1.f));
    const float theta_b = std::acos(std::clamp(b.cos_theta_o, -1.f, 1.f));
    const float theta_d = std::acos(std::clamp(dot(a.w, b.w), -1.f, 1.f));
    if (std::min(theta_d + theta_b, kPi) <= theta_a) {
        u.w = a.w, u.cos_theta_o = a.cos_theta_o;
        return u;
    }
    if (std::min(theta_d + theta_a, kPi) <= theta_b) {
        u.w = b.w, u.cos_theta_o = b.cos_theta_o;
        return u;
    }
    const float theta_o = 0.5f * (theta_a + theta_d + theta_b);
    const Vec3 axis = cross(a.w, b.w);
    if (theta_o >= kPi || !(length_squared(axis) > 0.f)) {
        u.w = a.w, u.cos_theta_o = -1.f;
        return u;
    }
    u.w = normalize(rotate(a.w, normalize(axis), theta_o - theta_a));
    // Widened by a little so that rounding in the rotation cannot leave a normal outside.
    u.cos_theta_o = std::cos(std::min(theta_o * (1.f + 1e-5f) + 1e-6f, kPi));
    return u;
}

/// A flat emitter's bounds: the box of its points, its power, its unit normal (front).
inline LightBounds flat_light_bounds(const Aabb& box, float phi, const Vec3& normal, bool two_sided) {
    LightBounds b;
    b.bounds = box;
    b.phi = phi;
    b.w = normal;
    b.cos_theta_o = 1.f;
    b.cos_theta_e = 0.f;
    b.two_sided = two_sided;
    return b;
}

/// An emitter that may emit along any direction from anywhere in the box (theta_o = pi).
inline LightBounds omni_light_bounds(const Aabb& box, float phi) {
    LightBounds b;
    b.bounds = box;
    b.phi = phi;
    b.cos_theta_o = -1.f;
    b.cos_theta_e = 0.f;
    return b;
}

/// Triangle k of a mesh light, with its share of the light's power.
inline LightBounds triangle_light_bounds(const TriangleMeshLight& mesh, std::size_t k, float mesh_phi) {
    const Triangle& t = mesh.triangles[k];
    const float area = TriangleMeshLight::triangle_area(t);
    return flat_light_bounds(bounds(t), mesh_phi * (area / mesh.total_area), normalize(cross(t.p1 - t.p0, t.p2 - t.p0)),
                             mesh.two_sided);
}

/// Bounds of a finite light of power `phi` (its light_power, or another measure of it) as
/// one whole; nullopt for the infinite ones (the environment, the infinite plane), which no
/// box holds.
inline std::optional<LightBounds> light_bounds(const Light& light, float phi) {
    if (const auto* q = std::get_if<QuadLight>(&light)) {
        Aabb box;
        for (const Vec3& c : {q->o, q->o + q->e1, q->o + q->e2, q->o + q->e1 + q->e2}) box.expand(c);
        return flat_light_bounds(box, phi, q->n, q->two_sided);
    }
    if (const auto* s = std::get_if<SphereLight>(&light)) return omni_light_bounds(bounds(s->sphere), phi);
    if (const auto* m = std::get_if<TriangleMeshLight>(&light)) {
        LightBounds all;
        for (std::size_t k = 0; k < m->triangles.size(); ++k)
            all = light_bounds_union(all, triangle_light_bounds(*m, k, phi));
        return all;
    }
    if (const auto* d = std::get_if<QuadricLight>(&light))
        return omni_light_bounds(std::visit([](const auto& shape) { return bounds(shape); }, d->shape), phi);
    if (const auto* p = std::get_if<PointLight>(&light)) {
        Aabb box;
        box.expand(p->position);
        return omni_light_bounds(box, phi);
    }
    if (const auto* s = std::get_if<SpotLight>(&light)) {
        Aabb box;
        box.expand(s->position);
        LightBounds b = omni_light_bounds(box, phi);
        b.w = s->direction;
        b.cos_theta_o = s->cos_falloff;
        // The fade between the falloff and the cone edge: theta_e = theta_cone − theta_falloff.
        const float theta_e = std::acos(std::clamp(s->cos_cone, -1.f, 1.f)) -
                              std::acos(std::clamp(s->cos_falloff, -1.f, 1.f));
        b.cos_theta_e = std::cos(std::min(theta_e * (1.f + 1e-5f) + 1e-6f, kPi));
        return b;
    }
    return std::nullopt;
}

}  // namespace spt

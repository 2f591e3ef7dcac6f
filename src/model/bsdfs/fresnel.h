// Exact Fresnel reflectance of a dielectric interface and Snell refraction.
#pragma once
#include <optional>

#include "core/vec3.h"

namespace spt {

/// Unpolarised Fresnel reflectance for light arriving with cos_i = cos(angle to the normal on
/// the incident side) ≥ 0 and eta = n_transmitted / n_incident. Returns 1 under total
/// internal reflection.
inline float fresnel_dielectric(float cos_i, float eta) {
    if (eta == 1.f) return 0.f;  // no interface (1 − cos² would round to 1 at grazing angles)
    cos_i = std::clamp(cos_i, 0.f, 1.f);
    const float sin2_t = (1.f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.f) return 1.f;
    const float cos_t = safe_sqrt(1.f - sin2_t);
    const float r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    const float r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5f * (r_parl * r_parl + r_perp * r_perp);
}

/// Mirror direction of w (pointing away from the surface) about n.
inline Vec3 reflect(const Vec3& w, const Vec3& n) { return n * (2.f * dot(w, n)) - w; }

/// Refracted direction for w pointing away from the surface on the side of n (dot(w, n) > 0),
/// eta = n_transmitted / n_incident. nullopt under total internal reflection.
inline std::optional<Vec3> refract(const Vec3& w, const Vec3& n, float eta) {
    const float cos_i = dot(w, n);
    const float sin2_t = std::max(0.f, 1.f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.f) return std::nullopt;
    const float cos_t = safe_sqrt(1.f - sin2_t);
    return normalize(-w / eta + n * (cos_i / eta - cos_t));
}

}  // namespace spt

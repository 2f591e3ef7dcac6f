// Warps from uniform numbers to directions, with their densities (solid-angle measure).
#pragma once
#include "core/vec3.h"

namespace spt {

/// Cosine-weighted direction on the +z hemisphere (Malley: concentric disk, then lift).
inline Vec3 sample_cosine_hemisphere(float u1, float u2) {
    const float a = 2.f * u1 - 1.f, b = 2.f * u2 - 1.f;
    float r = 0.f, phi = 0.f;
    if (a != 0.f || b != 0.f) {
        if (a * a > b * b) {
            r = a;
            phi = (kPi / 4.f) * (b / a);
        } else {
            r = b;
            phi = (kPi / 2.f) - (kPi / 4.f) * (a / b);
        }
    }
    const float x = r * std::cos(phi), y = r * std::sin(phi);
    return {x, y, safe_sqrt(1.f - x * x - y * y)};
}

/// Density of sample_cosine_hemisphere with respect to solid angle.
inline float cosine_hemisphere_pdf(float cos_theta) { return cos_theta > 0.f ? cos_theta * kInvPi : 0.f; }

/// Uniform direction on the unit sphere.
inline Vec3 sample_uniform_sphere(float u1, float u2) {
    const float z = 1.f - 2.f * u1;
    const float r = safe_sqrt(1.f - z * z);
    const float phi = 2.f * kPi * u2;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace spt

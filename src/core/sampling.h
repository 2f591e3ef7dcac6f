// Warps from uniform numbers to directions, with their densities (solid-angle measure).
#pragma once
#include "core/fast_math.h"
#include "core/vec3.h"

namespace spt {

/// Cosine-weighted direction on the +z hemisphere (Malley: concentric disk, then lift).
/// Written with selects: which wedge of the square a sample falls in is a coin toss.
inline Vec3 sample_cosine_hemisphere(float u1, float u2) {
    const float a = 2.f * u1 - 1.f, b = 2.f * u2 - 1.f;
    // Wedges |a| > |b| map to φ = (π/4)·(b/a); the others to φ = π/2 − (π/4)·(a/b), whose
    // sine and cosine are the cosine and sine of (π/4)·(a/b).
    const bool horizontal = a * a > b * b;
    const float r = horizontal ? a : b;
    const float num = horizontal ? b : a;
    const float s = r != 0.f ? num / r : 0.f;  // the centre (a = b = 0) maps to r = 0
    float sin_t, cos_t;
    sincos_quarter_pi(s, sin_t, cos_t);
    const float x = r * (horizontal ? cos_t : sin_t), y = r * (horizontal ? sin_t : cos_t);
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

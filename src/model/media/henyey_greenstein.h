// Henyey–Greenstein phase function (Henyey & Greenstein 1941): one parameter g, the mean
// cosine of the scattering angle (g > 0 forward, g < 0 backward, 0 isotropic).
#pragma once
#include <algorithm>
#include <cmath>

#include "core/frame.h"
#include "core/math.h"
#include "core/vec3.h"

namespace spt {

/// Directions follow the BSDF convention: wo points back along the incoming ray (towards
/// the previous vertex), wi away from the scattering point, so the scattering angle θ has
/// cos θ = dot(−wo, wi).
struct HenyeyGreenstein {
    float g = 0.f;  ///< in (−1, 1)

    /// Density per unit solid angle of the scattering angle with this cosine.
    static float density(float cos_theta, float g) {
        const float denom = 1.f + g * g - 2.f * g * cos_theta;
        return (1.f - g * g) / (4.f * kPi * denom * std::sqrt(denom));
    }

    /// p(wo, wi): the phase function's value, which is also the pdf of sample() (sampled exactly).
    float eval(const Vec3& wo, const Vec3& wi) const { return density(dot(-wo, wi), g); }

    /// A direction wi with density eval(wo, wi), from two uniforms in [0, 1).
    Vec3 sample(const Vec3& wo, float u1, float u2) const {
        float cos_theta;
        if (std::fabs(g) < 1e-3f) {
            cos_theta = 1.f - 2.f * u1;
        } else {
            // Inverse CDF of the cosine (u1 = 0 gives cos θ = 1).
            const float s = (1.f - g * g) / (1.f + g - 2.f * g * u1);
            cos_theta = (1.f + g * g - s * s) / (2.f * g);
        }
        cos_theta = std::clamp(cos_theta, -1.f, 1.f);
        const float sin_theta = std::sqrt(std::max(0.f, 1.f - cos_theta * cos_theta));
        const float phi = 2.f * kPi * u2;
        const Frame frame(-wo);
        return normalize(frame.to_world({sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta}));
    }
};

}  // namespace spt

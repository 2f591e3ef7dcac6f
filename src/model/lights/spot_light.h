// Spot light: a point light whose intensity I(λ) is confined to a cone around `direction`,
// full inside the falloff angle and fading to zero at the cone's edge by a smoothstep of
// cos θ (pbrt-v4's spot light).
#pragma once
#include <algorithm>
#include <cmath>
#include <optional>

#include "core/frame.h"
#include "core/sampling.h"
#include "model/lights/light_sample.h"
#include "spectral/spectrum.h"

namespace spt {

struct SpotLight {
    Vec3 position;
    Vec3 direction{0.f, -1.f, 0.f};  ///< unit axis of the cone
    Spectrum intensity;              ///< on the axis
    float cos_cone = 0.f;            ///< cosine of the cone's half angle (no light outside)
    float cos_falloff = 1.f;         ///< cosine of the half angle where the fade begins (≥ cos_cone)

    static constexpr LightType type = LightType::delta_position;

    /// Where the light is at `time` (spot lights stand still).
    Vec3 position_at(float /*time*/) const { return position; }
    /// Radiant intensity along w is I_max(λ)·falloff(w).
    SampledSpectrum I_max(const SampledWavelengths& lambda) const { return intensity.sample(lambda); }

    /// The angular factor in [0, 1] for light leaving along unit w.
    float falloff(const Vec3& w) const {
        const float c = dot(w, direction);
        if (c >= cos_falloff) return 1.f;
        if (c <= cos_cone) return 0.f;
        const float t = (c - cos_cone) / (cos_falloff - cos_cone);
        return t * t * (3.f - 2.f * t);
    }

    /// Mean over the sphere ×4π of the angular factor, in closed form as pbrt: the full cone
    /// up to the falloff angle and half of the fading ring.
    float power() const { return solid_angle_factor() * mean_over_visible(intensity); }
    float spectral_power(float lambda_nm) const { return solid_angle_factor() * intensity.eval(lambda_nm); }
    float solid_angle_factor() const { return 2.f * kPi * (1.f - 0.5f * (cos_falloff + cos_cone)); }

    /// A delta light, as the point light: pdf 1, L = I·falloff/r².
    bool sample_li(const LightSampleContext& ctx, const SampledWavelengths& lambda, float /*u1*/, float /*u2*/,
                   LightSample& ls) const {
        const Vec3 to_light = position - ctx.p;
        const float dist2 = length_squared(to_light);
        if (!(dist2 > 0.f)) return false;
        ls.wi = to_light / std::sqrt(dist2);
        const float f = falloff(-ls.wi);
        if (f == 0.f) return false;
        ls.L = intensity.sample(lambda) * (f / dist2);
        ls.pdf = 1.f;
        ls.p = position;
        ls.delta = true;
        return true;
    }

    /// Origin of a light subpath: the position, a direction uniform over the cone.
    std::optional<LightOrigin> sample_le(const SampledWavelengths& lambda, float u1, float u2, float /*u_side*/,
                                         float /*u3*/, float /*u4*/, float /*time*/) const {
        LightOrigin o;
        o.p = position;
        const float cos_theta = 1.f - u1 * (1.f - cos_cone);
        const float sin_theta = std::sqrt(std::max(0.f, 1.f - cos_theta * cos_theta));
        const float phi = 2.f * kPi * u2;
        o.w = normalize(Frame(direction).to_world({sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta}));
        o.Le = intensity.sample(lambda) * falloff(o.w);
        o.pdf_pos = 1.f;
        o.pdf_dir = 1.f / (2.f * kPi * (1.f - cos_cone));
        o.delta_position = true;
        return o;
    }
    /// Density of sample_le's direction w (uniform over the cone).
    float pdf_le_dir(const Vec3& /*n*/, const Vec3& w) const {
        return dot(w, direction) >= cos_cone ? 1.f / (2.f * kPi * (1.f - cos_cone)) : 0.f;
    }
};

}  // namespace spt

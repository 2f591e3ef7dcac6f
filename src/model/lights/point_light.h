// Isotropic point light: radiant intensity I(λ) (W·sr⁻¹·nm⁻¹ up to scale); irradiance at
// distance r on a surface tilted by θ is I·cos θ / r².
#pragma once
#include <optional>

#include "core/sampling.h"
#include "geometry/motion.h"
#include "model/lights/light_sample.h"
#include "spectral/spectrum.h"

namespace spt {

struct PointLight {
    Vec3 position;  ///< at rest: where `motion` starts from
    Spectrum intensity;
    RigidMotion motion;  ///< none: the light stands still

    static constexpr LightType type = LightType::delta_position;

    /// Where the light is at `time` (motion blur).
    Vec3 position_at(float time) const { return motion.is_static() ? position : motion.at(time).point(position); }

    float power() const { return 4.f * kPi * mean_over_visible(intensity); }
    float spectral_power(float lambda_nm) const { return 4.f * kPi * intensity.eval(lambda_nm); }

    /// Radiant intensity along w: I_max(λ)·falloff(w), the same in every direction.
    SampledSpectrum I_max(const SampledWavelengths& lambda) const { return intensity.sample(lambda); }
    static constexpr float falloff(const Vec3& /*w*/) { return 1.f; }

    /// A delta light: the direction is certain (pdf 1) and L = I/r² (the light where it
    /// stands at rest; the path loop asks position_at for the shutter time).
    bool sample_li(const LightSampleContext& ctx, const SampledWavelengths& lambda, float /*u1*/, float /*u2*/,
                   LightSample& ls) const {
        const Vec3 to_light = position - ctx.p;
        const float dist2 = length_squared(to_light);
        if (!(dist2 > 0.f)) return false;  // on the surface: no defined direction
        ls.wi = to_light / std::sqrt(dist2);
        ls.L = intensity.sample(lambda) / dist2;
        ls.pdf = 1.f;
        ls.p = position;
        ls.delta = true;
        return true;
    }

    /// Origin of a light subpath: the position at `time`, a direction uniform over the sphere.
    std::optional<LightOrigin> sample_le(const SampledWavelengths& lambda, float u1, float u2, float /*u_side*/,
                                         float /*u3*/, float /*u4*/, float time) const {
        LightOrigin o;
        o.w = sample_uniform_sphere(u1, u2);
        o.Le = intensity.sample(lambda);
        o.pdf_pos = 1.f;
        o.pdf_dir = 1.f / (4.f * kPi);
        o.delta_position = true;
        o.p = position_at(time);
        return o;
    }
    static float pdf_le_dir(const Vec3& /*n*/, const Vec3& /*w*/) { return 1.f / (4.f * kPi); }
};

}  // namespace spt

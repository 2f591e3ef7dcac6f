// Lambertian reflection f = kd/π on both sides of the surface (light arriving on one side
// leaves on the same side).
#pragma once
#include <optional>

#include "core/frame.h"
#include "core/sampling.h"
#include "model/bsdfs/bsdf_sample.h"
#include "spectral/spectrum.h"

namespace spt {

/// f·|cos θi| of a Lambertian lobe of reflectance kd (shared with the types that contain one).
inline SampledSpectrum lambertian_eval(const Spectrum& kd, const Vec3& wo, const Vec3& wi, const Vec3& n,
                                       const SampledWavelengths& lambda) {
    const float cos_o = dot(wo, n), cos_i = dot(wi, n);
    if (cos_o * cos_i <= 0.f) return SampledSpectrum(0.f);  // reflects, never transmits
    return kd.sample(lambda) * (std::fabs(cos_i) * kInvPi);
}

/// Solid-angle density of lambertian_sample: |cos θi|/π on wo's side.
inline float lambertian_pdf(const Vec3& wo, const Vec3& wi, const Vec3& n) {
    const float cos_o = dot(wo, n), cos_i = dot(wi, n);
    if (cos_o * cos_i <= 0.f) return 0.f;
    return std::fabs(cos_i) * kInvPi;
}

/// Cosine-weighted direction on wo's side, the lobe chosen with probability p_lobe. Always
/// inlined: as a call from the path loop, the loop saved and reloaded its vector registers
/// around every diffuse bounce (1.3 % of the time per path in a diffuse box).
[[gnu::always_inline]] inline std::optional<BsdfSample> lambertian_sample(const Spectrum& kd, const Vec3& wo,
                                                                          const Vec3& n,
                                                                          const SampledWavelengths& lambda,
                                                                          float u1, float u2, float p_lobe) {
    const Vec3 local = sample_cosine_hemisphere(u1, u2);
    if (!(local.z > 0.f)) return std::nullopt;  // pdf 0 at the horizon
    BsdfSample bs;
    bs.wi = Frame(dot(wo, n) > 0.f ? n : -n).to_world(local);
    // f·cos/pdf = (kd/π)·cos/(cos/π) = kd, divided by the lobe probability.
    bs.weight = kd.sample(lambda);
    bs.weight /= p_lobe;  // exact for p_lobe = 1, so no branch for that case (a mispredicted one)
    bs.pdf = local.z * kInvPi;
    bs.flags = {BsdfFlags::reflection | BsdfFlags::non_delta};
    return bs;
}

struct DiffuseBsdf {
    Spectrum kd;  ///< reflectance in [0, 1]

    BsdfFlags flags() const {
        return {kd.is_zero() ? std::uint8_t(0) : std::uint8_t(BsdfFlags::reflection | BsdfFlags::non_delta)};
    }
    SampledSpectrum eval(const Vec3& wo, const Vec3& wi, const Vec3& n, const SampledWavelengths& lambda,
                         TransportMode) const {
        return lambertian_eval(kd, wo, wi, n, lambda);
    }
    float pdf(const Vec3& wo, const Vec3& wi, const Vec3& n, float /*hero_nm*/) const {
        return lambertian_pdf(wo, wi, n);
    }
    [[gnu::always_inline]] std::optional<BsdfSample> sample(const Vec3& wo, const Vec3& n,
                                                            const SampledWavelengths& lambda, float u1,
                                                            float u2) const {
        return lambertian_sample(kd, wo, n, lambda, u1, u2, 1.f);
    }
};

}  // namespace spt

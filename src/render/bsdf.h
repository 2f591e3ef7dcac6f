// Sampling and evaluation of the three-lobe material (see material.h). Directions point away
// from the surface; n is the geometric normal, either side.
#pragma once
#include <optional>

#include "core/frame.h"
#include "core/sampling.h"
#include "geometry/ray.h"
#include "render/material.h"
#include "spectral/sampled.h"

namespace spt {

struct BsdfSample {
    Vec3 wi;
    SampledSpectrum weight;  ///< f·|cos θi| / pdf per wavelength (includes lobe choice)
    bool is_specular = false;
    float eta_scale = 1.f;   ///< (η_t/η_i)² on refraction, to undo radiance scaling in roulette
};

/// Lambertian lobe chosen with probability p_lobe (cos θo ≠ 0 checked by the caller).
/// Always inlined: as a call from the path loop, the loop saved and reloaded its vector
/// registers around every diffuse bounce (1.3 % of the time per path on cornell).
[[gnu::always_inline]] inline std::optional<BsdfSample> sample_diffuse(
    const Material& mat, const Vec3& wo, const Vec3& n, const SampledWavelengths& lambda, float u1, float u2,
    float p_lobe) {
    const Vec3 local = sample_cosine_hemisphere(u1, u2);
    if (!(local.z > 0.f)) return std::nullopt;  // pdf 0 at the horizon
    BsdfSample bs;
    bs.wi = Frame(dot(wo, n) > 0.f ? n : -n).to_world(local);
    // f·cos/pdf = (kd/π)·cos/(cos/π) = kd, divided by the lobe probability.
    bs.weight = mat.kd.sample(lambda);
    bs.weight /= p_lobe;  // exact for p_lobe = 1, so no branch for that case (a mispredicted one)
    return bs;
}

/// sample_bsdf for materials with more than a diffuse lobe (out of line: the rarer case).
std::optional<BsdfSample> sample_bsdf_lobes(const Material& mat, const Vec3& wo, const Vec3& n,
                                            SampledWavelengths& lambda, float u_lobe, float u1, float u2);

/// Samples a lobe, then a direction. May terminate the companion wavelengths (dispersive
/// refraction). nullopt when the sample carries no energy (absorbed or a degenerate direction).
/// Purely diffuse materials (most surfaces) are sampled inline.
[[gnu::always_inline]] inline std::optional<BsdfSample> sample_bsdf(const Material& mat, const Vec3& wo,
                                                                   const Vec3& n, SampledWavelengths& lambda,
                                                                   float u_lobe, float u1, float u2) {
    if (dot(wo, n) == 0.f) return std::nullopt;  // exactly tangent: no side to scatter to
    if (!mat.has_mirror() && !mat.has_transmission()) return sample_diffuse(mat, wo, n, lambda, u1, u2, 1.f);
    return sample_bsdf_lobes(mat, wo, n, lambda, u_lobe, u1, u2);
}

/// Non-specular part (diffuse) f·|cos θi| for light arriving from wi, for next-event estimation.
inline SampledSpectrum eval_diffuse_cos(const Material& mat, const Vec3& wo, const Vec3& wi,
                                        const Vec3& n, const SampledWavelengths& lambda) {
    const float cos_o = dot(wo, n), cos_i = dot(wi, n);
    if (cos_o * cos_i <= 0.f) return SampledSpectrum(0.f);  // Lambertian reflects, never transmits
    return mat.kd.sample(lambda) * (std::fabs(cos_i) * kInvPi);
}

/// Probability of choosing the diffuse lobe at the hero wavelength: the density the
/// bidirectional MIS weights use (the same function for every strategy, so they sum to 1).
inline float diffuse_lobe_probability_hero(const Material& mat, float hero_nm) {
    const float d = mat.kd.eval(hero_nm);
    if (!(d > 0.f)) return 0.f;
    return d / (d + mat.ks.eval(hero_nm) + mat.kt.eval(hero_nm));
}

/// Solid-angle density, for MIS, of sampling wi from wo (non-specular part only, hero
/// wavelength's lobe choice): p_diffuse · |cos θi|/π when wi is on wo's side, else 0.
inline float mis_pdf(const Material& mat, const Vec3& wo, const Vec3& wi, const Vec3& n, float hero_nm) {
    const float cos_o = dot(wo, n), cos_i = dot(wi, n);
    if (cos_o * cos_i <= 0.f) return 0.f;
    return diffuse_lobe_probability_hero(mat, hero_nm) * std::fabs(cos_i) * kInvPi;
}

/// Non-specular BSDF value f (no cosine): kd/π when wo and wi are on the same side.
inline SampledSpectrum eval_diffuse_f(const Material& mat, const Vec3& wo, const Vec3& wi,
                                      const Vec3& n, const SampledWavelengths& lambda) {
    if (dot(wo, n) * dot(wi, n) <= 0.f) return SampledSpectrum(0.f);
    return mat.kd.sample(lambda) * kInvPi;
}

}  // namespace spt

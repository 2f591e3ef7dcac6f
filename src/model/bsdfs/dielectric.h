// Dielectric interface of index η (inside relative to outside; any index model: constant,
// Cauchy, Sellmeier, tables), smooth (α = 0: delta reflection and refraction) or rough (GGX
// microfacets: reflection and refraction through a rough interface, Walter et al. 2007,
// "Microfacet models for refraction through rough surfaces", in the form of pbrt-v4's
// DielectricBxDF), with an optional thin film on it (its Airy reflectance R replaces Fresnel's,
// and 1 − R is transmitted: the film does not absorb). The normal points outside.
//
// Rough, with η' = η_t/η_i from wo's side and the generalized half vector m ∝ wo + η'·wi:
//   reflection    f = F·D·G2 / (4·|cos θo·cos θi|)
//   transmission  f = (1 − F)·D·G2·|wi·m|·|wo·m| / (|cos θo·cos θi|·(wi·m + wo·m/η')²),
//                 divided by η'² for radiance (not for importance: the adjoint).
// Sampling: a visible normal, then reflection or refraction through it chosen by the mean of
// F over the live wavelengths; MIS densities use the hero's F.
//
// Dispersion (η varies with λ): a refracted direction belongs to one wavelength. Sampling a
// refraction terminates the companions (as the smooth glass does). eval() of a transmitted
// pair is the hero's alone while the companions live, times K (kLambdaCount), and 0 for
// them: exactly what a path that had sampled that refraction carries after
// terminate_secondary() (pdf₀/K), so next-event estimation, bidirectional connections and
// merging estimate the same hero-only quantity as BSDF sampling and their MIS weights (hero
// densities) sum to one. With the companions already terminated eval() is the hero's f.
// Reflection keeps all wavelengths (each with its own F) in both cases.
#pragma once
#include <optional>

#include "model/bsdfs/bsdf_sample.h"
#include "model/bsdfs/fresnel.h"
#include "model/bsdfs/microfacet.h"
#include "model/bsdfs/microfacet_lobe.h"

namespace spt {

struct DielectricBsdf {
    Spectrum eta;  ///< index inside relative to outside, ≥ 1
    GgxDistribution ggx;
    ThinFilm film;

    bool is_dispersive() const { return !eta.is_constant(); }

    BsdfFlags flags() const {
        std::uint8_t f = BsdfFlags::reflection | BsdfFlags::transmission;
        f |= ggx.is_smooth() ? BsdfFlags::delta : BsdfFlags::non_delta;
        if (is_dispersive()) f |= BsdfFlags::dispersive;
        return {f};
    }

    /// Reflectance of the interface at cos_i (to the microfacet normal) for light arriving from
    /// outside (`from_outside`) or inside, at wavelength λ with index eta_l.
    float reflectance(float cos_i, bool from_outside, float eta_l, float lambda_nm) const {
        const float n0 = from_outside ? 1.f : eta_l, n2 = from_outside ? eta_l : 1.f;
        if (film.present())
            return thin_film_reflectance(cos_i, n0, film.eta.eval(lambda_nm), {n2, 0.f}, film.thickness_nm, lambda_nm);
        return fresnel_dielectric(cos_i, n2 / n0);
    }

    // Out of line and never inlined: LTO and the flattened light sampling of the path loop
    // would otherwise pull them into the code every scene runs.
    [[gnu::noinline]] SampledSpectrum eval(const Vec3& wo, const Vec3& wi, const Vec3& n, const SampledWavelengths& lambda,
                         TransportMode mode) const;
    [[gnu::noinline]] float pdf(const Vec3& wo, const Vec3& wi, const Vec3& n, float hero_nm) const;
    [[gnu::noinline]] std::optional<BsdfSample> sample(const Vec3& wo, const Vec3& n, SampledWavelengths& lambda,
                                                       float u_lobe, float u1, float u2, TransportMode mode) const;

private:
    /// f·|cos θi| at one wavelength (o, i local, o.z > 0; outside: wo is outside).
    float eval_one(const Vec3& o, const Vec3& i, bool outside, float eta_l, float lambda_nm, TransportMode mode) const;
};

}  // namespace spt

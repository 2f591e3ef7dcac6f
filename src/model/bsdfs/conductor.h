// Conductor (metal): spectral complex index η + ik relative to the outside, exact Fresnel per
// wavelength (or the Airy reflectance of a thin film on it), smooth (a delta mirror, α = 0) or
// rough (GGX microfacets, microfacet.h; anisotropic along a surface tangent, anisotropic_ggx.h).
// Reflects on both sides of the surface alike.
//
// Rough: f = F(wo·m)·D(m)·G2(wo, wi) / (4·cos θo·cos θi), m the half vector; sampled by visible
// normals, so the weight is F·G2/G1(wo). Single scattering only: the energy of light that
// would bounce again between microfacets is lost (the known loss of the model, which grows
// with α; tests/test_microfacet.cpp measures it).
#pragma once
#include <optional>

#include "model/bsdfs/anisotropic_ggx.h"
#include "model/bsdfs/bsdf_sample.h"
#include "model/bsdfs/fresnel.h"
#include "model/bsdfs/microfacet.h"
#include "model/bsdfs/microfacet_lobe.h"

namespace spt {

struct ConductorBsdf {
    Spectrum eta, k;  ///< complex index η + ik per wavelength (η > 0, k ≥ 0)
    GgxDistribution ggx;
    ThinFilm film;
    /// Anisotropic roughness ("roughness_u", "roughness_v"), used instead of ggx when set
    /// (α_x > 0; ggx.alpha then holds the larger α, for the flags), in the frame of `tangent`:
    /// the surface's dp/du at the hit, which Scene::textured_bsdf sets (the material is then
    /// read per hit, as a textured one).
    AnisotropicGgx aniso{};
    Vec3 tangent{};

    bool anisotropic() const { return aniso.alpha_x > 0.f; }

    /// Fresnel reflectance at cos_i (angle to the microfacet normal) for each wavelength.
    SampledSpectrum reflectance(float cos_i, const SampledWavelengths& lambda) const {
        const SampledSpectrum e = eta.sample(lambda), kk = k.sample(lambda);
        SampledSpectrum r;
        if (film.present()) {
            const SampledSpectrum nf = film.eta.sample(lambda);
            for (int i = 0; i < kLambdaCount; ++i)
                r[i] = thin_film_reflectance(cos_i, 1.f, nf[i], {e[i], kk[i]}, film.thickness_nm, lambda.lambda[i]);
        } else {
            for (int i = 0; i < kLambdaCount; ++i) r[i] = fresnel_conductor(cos_i, e[i], kk[i]);
        }
        return r;
    }

    BsdfFlags flags() const {
        return {std::uint8_t(BsdfFlags::reflection | (ggx.is_smooth() ? BsdfFlags::delta : BsdfFlags::non_delta))};
    }

    // Out of line, as the other microfacet types: inlined, they would grow the path loop that
    // visit_bsdf expands for every type (and change its register allocation) in every scene.
    [[gnu::noinline]] SampledSpectrum eval(const Vec3& wo, const Vec3& wi, const Vec3& n,
                                           const SampledWavelengths& lambda, TransportMode) const {
        if (anisotropic()) return rough_eval(aniso, anisotropic_frame(wo, n, tangent), wo, wi, lambda);
        if (ggx.is_smooth()) return SampledSpectrum(0.f);
        return rough_eval(ggx, frame_on_side_of(wo, n), wo, wi, lambda);
    }

    [[gnu::noinline]] float pdf(const Vec3& wo, const Vec3& wi, const Vec3& n, float /*hero_nm*/) const {
        if (anisotropic()) return rough_pdf(aniso, anisotropic_frame(wo, n, tangent), wo, wi);
        if (ggx.is_smooth()) return 0.f;
        return rough_pdf(ggx, frame_on_side_of(wo, n), wo, wi);
    }

    [[gnu::noinline]] std::optional<BsdfSample> sample(const Vec3& wo, const Vec3& n, SampledWavelengths& lambda,
                                                       float /*u_lobe*/, float u1, float u2, TransportMode) const {
        if (anisotropic()) return rough_sample(aniso, anisotropic_frame(wo, n, tangent), wo, lambda, u1, u2);
        if (ggx.is_smooth()) {
            const Frame f = frame_on_side_of(wo, n);
            const Vec3 o = f.to_local(wo);
            if (!(o.z > 0.f)) return std::nullopt;
            BsdfSample bs;
            bs.wi = f.to_world({-o.x, -o.y, o.z});
            bs.weight = reflectance(o.z, lambda);
            bs.flags = {BsdfFlags::reflection | BsdfFlags::delta};
            return bs;
        }
        return rough_sample(ggx, frame_on_side_of(wo, n), wo, lambda, u1, u2);
    }

private:
    // The rough lobe in frame f (z the normal on wo's side) for distribution d (isotropic or not).
    template <class Distribution>
    SampledSpectrum rough_eval(const Distribution& d, const Frame& f, const Vec3& wo, const Vec3& wi,
                               const SampledWavelengths& lambda) const {
        const Vec3 o = f.to_local(wo), i = f.to_local(wi);
        if (!(o.z > 0.f) || !(i.z > 0.f)) return SampledSpectrum(0.f);
        const Vec3 m = normalize(o + i);
        const float om = dot(o, m);
        if (!(om > 0.f)) return SampledSpectrum(0.f);
        return reflectance(om, lambda) * (d.D(m) * d.G2(o, i) / (4.f * o.z));
    }

    template <class Distribution>
    float rough_pdf(const Distribution& d, const Frame& f, const Vec3& wo, const Vec3& wi) const {
        const Vec3 o = f.to_local(wo), i = f.to_local(wi);
        if (!(o.z > 0.f) || !(i.z > 0.f)) return 0.f;
        const Vec3 m = normalize(o + i);
        const float om = dot(o, m);
        if (!(om > 0.f)) return 0.f;
        return d.visible_pdf(o, m) / (4.f * om);
    }

    template <class Distribution>
    std::optional<BsdfSample> rough_sample(const Distribution& d, const Frame& f, const Vec3& wo,
                                           const SampledWavelengths& lambda, float u1, float u2) const {
        const Vec3 o = f.to_local(wo);
        if (!(o.z > 0.f)) return std::nullopt;
        const Vec3 m = d.sample_visible_normal(o, u1, u2);
        const float om = dot(o, m);
        const Vec3 i = m * (2.f * om) - o;
        if (!(i.z > 0.f) || !(om > 0.f)) return std::nullopt;  // reflected below the surface: masked
        BsdfSample bs;
        bs.wi = f.to_world(i);
        bs.weight = reflectance(om, lambda) * (d.G2(o, i) / d.G1(o));
        bs.pdf = d.visible_pdf(o, m) / (4.f * om);
        bs.flags = {BsdfFlags::reflection | BsdfFlags::non_delta};
        return bs;
    }
};

}  // namespace spt

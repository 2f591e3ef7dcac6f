// Plastic: a Lambertian base kd under a clear dielectric coat of index η (a constant, or a
// spectrum η(λ): below), smooth (α = 0: a delta mirror) or rough (GGX). Both sides alike.
//
// Layering approximation (the energy-conserving coupling of Kelemen & Szirmay-Kalos 2001, also
// Kulla & Conty 2017): with E(μ) the directional albedo of the coat's specular lobe alone and
// E_avg = 2∫E(μ)μ dμ its cosine-weighted mean,
//   f = f_coat(wo, wi) + kd·(1 − E(μo))·(1 − E(μi)) / (π·(1 − E_avg)).
// What enters the coat is what its specular lobe does not reflect; the diffuse term is
// reciprocal and, for kd = 1, returns exactly that energy (∫ diffuse·cos = 1 − E(μo)), so a
// white base under any coat is a white furnace up to the tabulation of E. It neglects: the
// refraction of the diffuse light (its angular reshaping by the coat, and the (1 − F)
// weighting per direction in favour of the averaged E), the colour shift of light bouncing
// several times between base and coat (kd², kd³... terms), and absorption in the coat.
//
// E(μ) is tabulated at construction (make_plastic; coat_albedo.h): at the material's α, or,
// when the roughness is a texture, over α too (a table shared by plastics of the same coat
// index), read at the α of each hit.
//
// A coat whose index varies with λ (a Cauchy, Sellmeier or catalogue glass): each wavelength λ
// of the sample sees its own coat, index η(λ): the coat's lobe uses F(η(λ)), the diffuse term
// E(μ; η(λ)) and E_avg(η(λ)), read from a table over η at the material's α (coat_albedo.h,
// coat_albedo_over_index: rows over the material's own index range, ≤ 6e-4 from the direct E),
// so the white furnace holds at every λ. The plastic only reflects, and both its lobes send a
// direction that does not depend on λ (the mirror or a visible normal's reflection, and the
// cosine lobe): every wavelength follows the sampled direction and no companion is terminated
// (no `dispersive` flag). The lobe choice is one number for all λ, the coat's albedo at the
// index η̄ (the mean of η(λ) over 380–780 nm), the same in sample() and pdf(); the smooth
// coat's delta weight is F(μ, η(λ))/pc per λ. η(λ) is held within its range over 360–830 nm
// (wider --spectral-range wavelengths see the end values). A textured roughness with such a
// coat would need a table over α and η: a scene error (material_types.cpp).
#pragma once
#include <optional>

#include "model/bsdfs/bsdf_sample.h"
#include "model/bsdfs/coat_albedo.h"
#include "model/bsdfs/fresnel.h"
#include "model/bsdfs/microfacet.h"
#include "model/bsdfs/microfacet_lobe.h"

namespace spt {

/// A coat index that varies with λ and its albedo over that index (shared, process lifetime).
struct DispersiveCoat {
    Spectrum eta;                     ///< η(λ), ≥ 1
    const CoatAlbedoRows* table;     ///< E(η, μ) at the plastic's α over η's range

    /// η at λ, held within the table's range.
    float index(float lambda_nm) const { return table->clamp_parameter(eta.eval(lambda_nm)); }
};

struct PlasticBsdf {
    Spectrum kd;       ///< base reflectance in [0, 1]
    float eta = 1.5f;  ///< coat index (constant; with a dispersive coat its mean η̄)
    GgxDistribution ggx;
    CoatAlbedo coat;   ///< E(μ) at ggx.alpha (a constant roughness)
    /// A textured roughness: E over α, read at ggx.alpha (set at each hit); `coat` unused.
    const CoatAlbedoRows* coat_table = nullptr;
    float kd_mean = 0.f;  ///< mean of kd over 380–780 nm, for the lobe choice
    /// A coat index varying with λ, or null (the constant path above). With it `coat` holds
    /// E at η̄, for the lobe choice only.
    const DispersiveCoat* dispersion = nullptr;

    /// E(μ) of the coat at this BSDF's α.
    float coat_albedo_at(float mu) const { return coat_table ? coat_table->at(ggx.alpha, mu) : coat.at(mu); }
    /// E_avg of the coat at this BSDF's α.
    float coat_albedo_average() const { return coat_table ? coat_table->average(ggx.alpha) : coat.average; }

    BsdfFlags flags() const {
        std::uint8_t f = BsdfFlags::reflection | BsdfFlags::non_delta;
        if (ggx.is_smooth()) f |= BsdfFlags::delta;
        return {f};
    }

    // Out of line and never inlined: LTO and the flattened light sampling of the path loop
    // would otherwise pull them into the code every scene runs.
    [[gnu::noinline]] SampledSpectrum eval(const Vec3& wo, const Vec3& wi, const Vec3& n, const SampledWavelengths& lambda,
                         TransportMode) const;
    [[gnu::noinline]] float pdf(const Vec3& wo, const Vec3& wi, const Vec3& n, float hero_nm) const;
    [[gnu::noinline]] std::optional<BsdfSample> sample(const Vec3& wo, const Vec3& n, SampledWavelengths& lambda,
                                                       float u_lobe, float u1, float u2, TransportMode mode) const;

    /// Probability of sampling the coat rather than the base, seen from cos θo = mu (one
    /// number for every λ, also with a dispersive coat).
    float coat_probability(float mu) const {
        const float e = coat_albedo_at(mu);
        const float d = (1.f - e) * kd_mean;
        return e + d > 0.f ? e / (e + d) : 1.f;
    }

private:
    /// eval() of a dispersive coat: each λ with its own index (o, i local, both above).
    SampledSpectrum eval_dispersive(const Vec3& o, const Vec3& i, const SampledWavelengths& lambda) const;
};

/// A plastic with its coat albedo computed (kd in [0, 1], eta ≥ 1, alpha in [0, 1]); with
/// textured_roughness, the table over α (coat_albedo_table), read at each hit's α.
PlasticBsdf make_plastic(Spectrum kd, float eta, float alpha, bool textured_roughness = false);

/// A plastic whose coat index is a spectrum (η ≥ 1 over 360–830 nm): a constant one gives
/// make_plastic(kd, η, ...) exactly; one varying with λ the dispersive coat (its table
/// computed or shared here). A varying index with a textured roughness throws
/// std::invalid_argument (the scene loader reports it first, with its position).
PlasticBsdf make_plastic(Spectrum kd, const Spectrum& eta, float alpha, bool textured_roughness = false);

}  // namespace spt

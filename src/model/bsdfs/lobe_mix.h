// The renderer's first material: a sum of three lobes, each weighted by a spectrum,
//   kd  Lambertian diffuse,
//   ks  perfect mirror (no Fresnel: a grey coat, as on the Cornell plastic sphere),
//   kt  smooth dielectric interface of index eta: Fresnel-weighted mirror reflection and
//       refraction, total internal reflection included (kt = 1 is clear glass),
// with kd + ks + kt ≤ 1 at every wavelength (checked when the scene is built). Plastic,
// clear and dispersive glass and their mixes are all of this form.
//
// One-sample lobe selection: a lobe is picked with probability proportional to its mean
// weight over the live wavelengths, and its weight divided by that probability, so the
// estimator stays unbiased at every wavelength while throughput stays near the albedo. The
// density reported for MIS uses the hero wavelength's choice instead (the same function for
// every strategy, which is what MIS needs).
#pragma once
#include <optional>

#include "model/bsdfs/bsdf_sample.h"
#include "model/bsdfs/diffuse.h"
#include "spectral/spectrum.h"

namespace spt {

struct LobeMixBsdf {
    Spectrum kd, ks, kt;
    Spectrum eta;  ///< index of refraction inside relative to outside (used when kt > 0)

    bool has_diffuse() const { return !kd.is_zero(); }
    bool has_mirror() const { return !ks.is_zero(); }
    bool has_transmission() const { return !kt.is_zero(); }
    /// Index that varies with wavelength: refraction splits the hero wavelength set.
    bool is_dispersive() const { return has_transmission() && !eta.is_constant(); }

    BsdfFlags flags() const;

    /// The diffuse lobe's f·|cos θi| (the specular lobes are deltas).
    SampledSpectrum eval(const Vec3& wo, const Vec3& wi, const Vec3& n, const SampledWavelengths& lambda,
                         TransportMode) const {
        return lambertian_eval(kd, wo, wi, n, lambda);
    }

    /// Probability of choosing the diffuse lobe at the hero wavelength.
    float diffuse_probability_hero(float hero_nm) const {
        const float d = kd.eval(hero_nm);
        if (!(d > 0.f)) return 0.f;
        return d / (d + ks.eval(hero_nm) + kt.eval(hero_nm));
    }

    float pdf(const Vec3& wo, const Vec3& wi, const Vec3& n, float hero_nm) const {
        const float cos_o = dot(wo, n), cos_i = dot(wi, n);
        if (cos_o * cos_i <= 0.f) return 0.f;
        return diffuse_probability_hero(hero_nm) * std::fabs(cos_i) * kInvPi;
    }

    /// May terminate the companion wavelengths (dispersive refraction).
    std::optional<BsdfSample> sample(const Vec3& wo, const Vec3& n, SampledWavelengths& lambda, float u_lobe,
                                     float u1, float u2, TransportMode mode) const;
};

}  // namespace spt

// A free-standing thin film with the same medium (air, index 1) on both sides: a soap bubble.
// Light is reflected specularly with the film's Airy reflectance R(λ, θ) (thin_film.h) or
// passes straight through with 1 − R (the film neither absorbs nor, being parallel-sided,
// deviates: the direction is the same at every wavelength, so nothing disperses). Both lobes
// are deltas; the two sides are alike.
#pragma once
#include <optional>

#include "model/bsdfs/bsdf_sample.h"
#include "model/bsdfs/microfacet_lobe.h"

namespace spt {

struct ThinSheetBsdf {
    ThinFilm film;  ///< index and thickness (nm) of the sheet

    SampledSpectrum reflectance(float cos_i, const SampledWavelengths& lambda) const {
        const SampledSpectrum nf = film.eta.sample(lambda);
        SampledSpectrum r;
        for (int k = 0; k < kLambdaCount; ++k)
            r[k] = thin_film_reflectance(cos_i, 1.f, nf[k], {1.f, 0.f}, film.thickness_nm, lambda.lambda[k]);
        return r;
    }

    BsdfFlags flags() const { return {BsdfFlags::reflection | BsdfFlags::transmission | BsdfFlags::delta}; }
    SampledSpectrum eval(const Vec3&, const Vec3&, const Vec3&, const SampledWavelengths&, TransportMode) const {
        return SampledSpectrum(0.f);
    }
    float pdf(const Vec3&, const Vec3&, const Vec3&, float) const { return 0.f; }

    [[gnu::noinline]] std::optional<BsdfSample> sample(const Vec3& wo, const Vec3& n, SampledWavelengths& lambda,
                                                       float u_lobe, float, float, TransportMode) const {
        const float cos_o = dot(wo, n);
        const SampledSpectrum R = reflectance(std::fabs(cos_o), lambda);
        // Choose by the mean over the live wavelengths: interference makes R vary a lot with λ.
        const float p_reflect = mean_over_live(R, lambda);
        BsdfSample bs;
        if (u_lobe < p_reflect) {
            bs.wi = n * (2.f * cos_o) - wo;
            bs.weight = R / p_reflect;
            bs.flags = {BsdfFlags::reflection | BsdfFlags::delta};
        } else {
            bs.wi = -wo;
            bs.weight = (SampledSpectrum(1.f) - R) / (1.f - p_reflect);
            bs.flags = {BsdfFlags::transmission | BsdfFlags::delta};
        }
        return bs;
    }
};

}  // namespace spt

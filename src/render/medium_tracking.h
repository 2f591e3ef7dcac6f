// Free-flight sampling through a medium against a majorant (pbrt-v4's SampleT_maj; Novák et
// al. 2014, "Residual ratio tracking"): collisions are drawn with the hero wavelength's
// majorant σ_maj(λ0) = σt(λ0)·max density, and at each one the caller sees the local
// coefficients, the majorant and the majorant transmittance T_maj of the step at every
// wavelength, so it can weight the companions (spectral MIS) and choose absorption,
// scattering or a null collision (delta tracking) or multiply by σn/σ_maj (ratio tracking).
#pragma once
#include <cmath>

#include "core/rng.h"
#include "model/media/medium.h"

namespace spt {

/// exp(−σ·d) per wavelength, with σ = 0 giving 1 even for an infinite d.
inline SampledSpectrum majorant_transmittance(const SampledSpectrum& sigma, float d) {
    SampledSpectrum T;
    for (int i = 0; i < kLambdaCount; ++i) T[i] = sigma[i] > 0.f ? std::exp(-sigma[i] * d) : 1.f;
    return T;
}

/// What the tracking callback sees at a collision.
struct MediumCollision {
    Vec3 p;
    SampledSpectrum sigma_a, sigma_s;  ///< at p (density included)
    SampledSpectrum sigma_maj;         ///< the majorant
    SampledSpectrum T_maj;             ///< exp(−σ_maj·step) of the step that ended here
};

/// Tracks `ray` (unit direction) through `medium` over (0, t_end): at each tentative
/// collision calls `on_collision(const MediumCollision&)`, which returns whether to go on.
/// Returns T_maj from the last collision (or the start) to t_end, or 1 when the callback
/// stopped the walk. `u` is the first uniform; later ones come from `rng`.
template <typename OnCollision>
SampledSpectrum track_majorant(const Medium& medium, const Ray& ray, float t_end, const SampledWavelengths& lambda,
                               float u, Rng& rng, OnCollision&& on_collision) {
    float t0 = 0.f, t1 = t_end;
    if (!medium.clip(ray, t0, t1)) return SampledSpectrum(1.f);
    SampledSpectrum sa, ss;
    medium.coefficients(lambda, sa, ss);
    const SampledSpectrum sigma_maj = (sa + ss) * medium.max_density(ray, t0, t1);
    // The hero sees no extinction: no collision can be drawn; the companions' majorant
    // transmittance is weighted by the caller.
    if (!(sigma_maj[0] > 0.f)) return majorant_transmittance(sigma_maj, t1 - t0);
    float t = t0;
    for (;;) {
        const float step = -std::log1p(-u) / sigma_maj[0];
        if (!(t + step < t1)) return majorant_transmittance(sigma_maj, t1 - t);
        t += step;
        MediumCollision c;
        c.p = ray.o + ray.d * t;
        const float d = medium.density_at(c.p);
        c.sigma_a = sa * d;
        c.sigma_s = ss * d;
        c.sigma_maj = sigma_maj;
        c.T_maj = majorant_transmittance(sigma_maj, step);
        if (!on_collision(c)) return SampledSpectrum(1.f);
        u = rng.uniform();
    }
}

/// σn = σ_maj − σa − σs, never negative (the majorant bounds the density).
inline SampledSpectrum null_coefficient(const MediumCollision& c) {
    SampledSpectrum n = c.sigma_maj - c.sigma_a - c.sigma_s;
    for (int i = 0; i < kLambdaCount; ++i) n[i] = std::max(0.f, n[i]);
    return n;
}

/// Unbiased estimate of the transmittance exp(−∫σt) along (0, t_end) at every wavelength by
/// ratio tracking: collisions are drawn with the hero's majorant, and each wavelength's
/// null-collision path weight (T_maj·σn per collision, T_maj to the end, with its own
/// majorant) is divided by the hero's density of that path (importance sampling, unbiased
/// since the hero's density is positive wherever a wavelength's weight is).
inline SampledSpectrum ratio_tracking_transmittance(const Medium& medium, const Ray& ray, float t_end,
                                                    const SampledWavelengths& lambda, Rng& rng) {
    SampledSpectrum T(1.f);
    const SampledSpectrum T_end = track_majorant(medium, ray, t_end, lambda, rng.uniform(), rng, [&](const MediumCollision& c) {
        // Collision density with the hero's majorant: T_maj[0]·σ_maj[0]; each wavelength's
        // null-path weight T_maj·σn over it.
        T *= c.T_maj * null_coefficient(c) / (c.T_maj[0] * c.sigma_maj[0]);
        return !T.is_zero();
    });
    return T * T_end / T_end[0];
}

/// Delta tracking: 1 if the hero passes (0, t_end) without a real collision, else 0 (the
/// hero's transmittance in expectation). Tests compare it with ratio tracking.
inline float delta_tracking_transmittance(const Medium& medium, const Ray& ray, float t_end,
                                          const SampledWavelengths& lambda, Rng& rng) {
    bool passed = true;
    track_majorant(medium, ray, t_end, lambda, rng.uniform(), rng, [&](const MediumCollision& c) {
        const float p_real = (c.sigma_a[0] + c.sigma_s[0]) / c.sigma_maj[0];
        if (rng.uniform() < p_real) passed = false;
        return passed;
    });
    return passed ? 1.f : 0.f;
}

}  // namespace spt

#include "model/bsdfs/lobe_mix.h"

#include "model/bsdfs/fresnel.h"

namespace spt {

namespace {

float live_mean(const SampledSpectrum& s, const SampledWavelengths& lambda) {
    if (lambda.secondary_terminated()) return s[0];
    return s.average();
}

/// Smooth dielectric: reflect with the hero wavelength's Fresnel probability, else refract.
std::optional<BsdfSample> sample_dielectric(const Spectrum& eta, const Vec3& wo, const Vec3& n,
                                            SampledWavelengths& lambda, SampledSpectrum lobe_weight, float u,
                                            TransportMode mode) {
    const float cos_o = dot(wo, n);
    const bool entering = cos_o > 0.f;
    const Vec3 n_wo = entering ? n : -n;  // normal on the side of wo
    const float eta_hero = eta.eval(lambda.lambda[0]);
    const float eta_rel = entering ? eta_hero : 1.f / eta_hero;  // η_t / η_i
    const float f_hero = fresnel_dielectric(std::fabs(cos_o), eta_rel);
    const bool dispersive = !eta.is_constant();

    BsdfSample bs;
    if (u < f_hero) {
        bs.wi = reflect(wo, n_wo);
        bs.weight = lobe_weight;
        bs.flags = {BsdfFlags::reflection | BsdfFlags::delta};
        // Companions reflect in the same direction with their own Fresnel factor.
        if (dispersive && !lambda.secondary_terminated()) {
            for (int i = 1; i < kLambdaCount; ++i) {
                const float eta_i = eta.eval(lambda.lambda[i]);
                const float f_i = fresnel_dielectric(std::fabs(cos_o), entering ? eta_i : 1.f / eta_i);
                bs.weight[i] *= f_i / f_hero;
            }
        }
        return bs;
    }
    const std::optional<Vec3> wt = refract(wo, n_wo, eta_rel);
    if (!wt) return std::nullopt;  // unreachable: TIR has f_hero = 1
    bs.wi = *wt;
    bs.flags = {BsdfFlags::transmission | BsdfFlags::delta};
    if (dispersive && !lambda.secondary_terminated()) {
        // Other wavelengths would bend elsewhere: only the hero follows this direction.
        lambda.terminate_secondary();
        for (int i = 1; i < kLambdaCount; ++i) lobe_weight[i] = 0.f;
        bs.flags.bits |= BsdfFlags::dispersive;
    }
    // Radiance is compressed by (η_i/η_t)² when it crosses into the denser medium;
    // importance is not (the adjoint BSDF has no such factor).
    bs.weight = mode == TransportMode::radiance ? lobe_weight / (eta_rel * eta_rel) : lobe_weight;
    bs.eta_scale = eta_rel * eta_rel;
    return bs;
}

}  // namespace

BsdfFlags LobeMixBsdf::flags() const {
    std::uint8_t f = 0;
    if (has_diffuse()) f |= BsdfFlags::reflection | BsdfFlags::non_delta;
    if (has_mirror()) f |= BsdfFlags::reflection | BsdfFlags::delta;
    if (has_transmission()) f |= BsdfFlags::reflection | BsdfFlags::transmission | BsdfFlags::delta;
    if (is_dispersive()) f |= BsdfFlags::dispersive;
    return {f};
}

std::optional<BsdfSample> LobeMixBsdf::sample(const Vec3& wo, const Vec3& n, SampledWavelengths& lambda,
                                              float u_lobe, float u1, float u2, TransportMode mode) const {
    const SampledSpectrum d = kd.sample(lambda);
    const SampledSpectrum s = ks.sample(lambda);
    const SampledSpectrum t = kt.sample(lambda);
    const float w_d = live_mean(d, lambda), w_s = live_mean(s, lambda), w_t = live_mean(t, lambda);
    const float total = w_d + w_s + w_t;
    if (!(total > 0.f)) return std::nullopt;

    float u = u_lobe * total;
    if (u < w_d) {
        std::optional<BsdfSample> bs = lambertian_sample(kd, wo, n, lambda, u1, u2, w_d / total);
        if (bs) bs->pdf *= diffuse_probability_hero(lambda.lambda[0]);
        return bs;
    }
    u -= w_d;
    // Rounding of u near the top of [0, 1) must never select a lobe of zero weight.
    if (u < w_s || !(w_t > 0.f)) {
        BsdfSample bs;
        bs.flags = {BsdfFlags::reflection | BsdfFlags::delta};
        bs.wi = reflect(wo, dot(wo, n) > 0.f ? n : -n);
        bs.weight = s * (total / w_s);
        return bs;
    }
    return sample_dielectric(eta, wo, n, lambda, t * (total / w_t), u1, mode);
}

}  // namespace spt

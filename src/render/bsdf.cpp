// One-sample lobe selection: the lobe is picked with probability proportional to its mean
// reflectance over the live wavelengths, and its weight divided by that probability, so the
// estimator stays unbiased at every wavelength while throughput stays near the albedo.
#include "render/bsdf.h"

#include "render/fresnel.h"

namespace spt {

namespace {

float live_mean(const SampledSpectrum& s, const SampledWavelengths& lambda) {
    if (lambda.secondary_terminated()) return s[0];
    return s.average();
}

/// Smooth dielectric: reflect with the hero wavelength's Fresnel probability, else refract.
std::optional<BsdfSample> sample_dielectric(const Material& mat, const Vec3& wo, const Vec3& n,
                                            SampledWavelengths& lambda, SampledSpectrum lobe_weight,
                                            float u) {
    const float cos_o = dot(wo, n);
    const bool entering = cos_o > 0.f;
    const Vec3 n_wo = entering ? n : -n;  // normal on the side of wo
    const float eta_hero = mat.eta.eval(lambda.lambda[0]);
    const float eta_rel = entering ? eta_hero : 1.f / eta_hero;  // η_t / η_i
    const float f_hero = fresnel_dielectric(std::fabs(cos_o), eta_rel);
    const bool dispersive = !mat.eta.is_constant();

    BsdfSample bs;
    bs.is_specular = true;
    if (u < f_hero) {
        bs.wi = reflect(wo, n_wo);
        bs.weight = lobe_weight;
        // Companions reflect in the same direction with their own Fresnel factor.
        if (dispersive && !lambda.secondary_terminated()) {
            for (int i = 1; i < kLambdaCount; ++i) {
                const float eta_i = mat.eta.eval(lambda.lambda[i]);
                const float f_i = fresnel_dielectric(std::fabs(cos_o), entering ? eta_i : 1.f / eta_i);
                bs.weight[i] *= f_i / f_hero;
            }
        }
        return bs;
    }
    const std::optional<Vec3> wt = refract(wo, n_wo, eta_rel);
    if (!wt) return std::nullopt;  // unreachable: TIR has f_hero = 1
    bs.wi = *wt;
    if (dispersive && !lambda.secondary_terminated()) {
        // Other wavelengths would bend elsewhere: only the hero follows this direction.
        lambda.terminate_secondary();
        for (int i = 1; i < kLambdaCount; ++i) lobe_weight[i] = 0.f;
    }
    // Radiance is compressed by (η_i/η_t)² when it crosses into the denser medium.
    bs.weight = lobe_weight / (eta_rel * eta_rel);
    bs.eta_scale = eta_rel * eta_rel;
    return bs;
}

}  // namespace

std::optional<BsdfSample> sample_bsdf_lobes(const Material& mat, const Vec3& wo, const Vec3& n,
                                            SampledWavelengths& lambda, float u_lobe, float u1, float u2) {
    const SampledSpectrum kd = mat.kd.sample(lambda);
    const SampledSpectrum ks = mat.ks.sample(lambda);
    const SampledSpectrum kt = mat.kt.sample(lambda);
    const float w_d = live_mean(kd, lambda), w_s = live_mean(ks, lambda), w_t = live_mean(kt, lambda);
    const float total = w_d + w_s + w_t;
    if (!(total > 0.f)) return std::nullopt;

    float u = u_lobe * total;
    if (u < w_d) return sample_diffuse(mat, wo, n, lambda, u1, u2, w_d / total);
    u -= w_d;
    // Rounding of u near the top of [0, 1) must never select a lobe of zero weight.
    if (u < w_s || !(w_t > 0.f)) {
        BsdfSample bs;
        bs.is_specular = true;
        bs.wi = reflect(wo, dot(wo, n) > 0.f ? n : -n);
        bs.weight = ks * (total / w_s);
        return bs;
    }
    return sample_dielectric(mat, wo, n, lambda, kt * (total / w_t), u1);
}

}  // namespace spt

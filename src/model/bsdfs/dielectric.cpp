#include "model/bsdfs/dielectric.h"

namespace spt {

namespace {

/// The generalized half vector of the pair (o, i) on the +z side (o.z > 0; reflection when
/// i.z > 0, else refraction with η' = etap), or nullopt when no microfacet facing o scatters o
/// into i (m·o ≤ 0, or i on the wrong side of m).
std::optional<Vec3> half_vector(const Vec3& o, const Vec3& i, float etap) {
    const bool reflect = i.z > 0.f;
    Vec3 m = reflect ? o + i : o + i * etap;
    if (!(length_squared(m) > 0.f)) return std::nullopt;
    m = normalize(m);
    if (m.z < 0.f) m = -m;
    const float om = dot(o, m), im = dot(i, m);
    if (!(om > 0.f) || (reflect ? !(im > 0.f) : !(im < 0.f))) return std::nullopt;
    return m;
}

}  // namespace

float DielectricBsdf::eval_one(const Vec3& o, const Vec3& i, bool outside, float eta_l, float lambda_nm,
                               TransportMode mode) const {
    const bool reflect = i.z > 0.f;
    const float etap = reflect ? 1.f : (outside ? eta_l : 1.f / eta_l);
    const std::optional<Vec3> m = half_vector(o, i, etap);
    if (!m) return 0.f;
    const float om = dot(o, *m), im = dot(i, *m);
    const float F = reflectance(om, outside, eta_l, lambda_nm);
    const float dg = ggx.D(*m) * ggx.G2(o, i);
    if (reflect) return F * dg / (4.f * o.z);
    const float ft_cos = (1.f - F) * dg * std::fabs(im * om) / (o.z * sqr(im + om / etap));
    return mode == TransportMode::radiance ? ft_cos / (etap * etap) : ft_cos;
}

SampledSpectrum DielectricBsdf::eval(const Vec3& wo, const Vec3& wi, const Vec3& n,
                                     const SampledWavelengths& lambda, TransportMode mode) const {
    if (ggx.is_smooth()) return SampledSpectrum(0.f);
    const bool outside = dot(wo, n) > 0.f;
    const Frame f(outside ? n : -n);
    const Vec3 o = f.to_local(wo), i = f.to_local(wi);
    if (!(o.z > 0.f) || i.z == 0.f) return SampledSpectrum(0.f);
    const bool terminated = lambda.secondary_terminated();
    SampledSpectrum r(0.f);
    if (i.z < 0.f && is_dispersive()) {
        // The hero's refraction alone, as a path that sampled it carries it (see the header).
        const float l0 = lambda.lambda[0];
        r[0] = eval_one(o, i, outside, eta.eval(l0), l0, mode) * (terminated ? 1.f : float(kLambdaCount));
        return r;
    }
    if (!film.present() && !is_dispersive()) {
        const float l0 = lambda.lambda[0];
        return SampledSpectrum(eval_one(o, i, outside, eta.eval(l0), l0, mode));
    }
    const int lanes = terminated ? 1 : kLambdaCount;
    for (int k = 0; k < lanes; ++k) r[k] = eval_one(o, i, outside, eta.eval(lambda.lambda[k]), lambda.lambda[k], mode);
    return r;
}

float DielectricBsdf::pdf(const Vec3& wo, const Vec3& wi, const Vec3& n, float hero_nm) const {
    if (ggx.is_smooth()) return 0.f;
    const bool outside = dot(wo, n) > 0.f;
    const Frame f(outside ? n : -n);
    const Vec3 o = f.to_local(wo), i = f.to_local(wi);
    if (!(o.z > 0.f) || i.z == 0.f) return 0.f;
    const float eta_h = eta.eval(hero_nm);
    const bool reflect = i.z > 0.f;
    const float etap = reflect ? 1.f : (outside ? eta_h : 1.f / eta_h);
    const std::optional<Vec3> m = half_vector(o, i, etap);
    if (!m) return 0.f;
    const float om = dot(o, *m), im = dot(i, *m);
    const float F = reflectance(om, outside, eta_h, hero_nm);
    const float pdf_m = ggx.visible_pdf(o, *m);
    if (reflect) return pdf_m / (4.f * om) * F;
    return pdf_m * std::fabs(im) / sqr(im + om / etap) * (1.f - F);
}

std::optional<BsdfSample> DielectricBsdf::sample(const Vec3& wo, const Vec3& n, SampledWavelengths& lambda,
                                                 float u_lobe, float u1, float u2, TransportMode mode) const {
    const bool outside = dot(wo, n) > 0.f;
    const Frame f(outside ? n : -n);
    const Vec3 o = f.to_local(wo);
    if (!(o.z > 0.f)) return std::nullopt;
    const bool smooth = ggx.is_smooth();
    const Vec3 m = smooth ? Vec3{0.f, 0.f, 1.f} : ggx.sample_visible_normal(o, u1, u2);
    const float om = dot(o, m);
    if (!(om > 0.f)) return std::nullopt;

    // Reflectance through this microfacet at each live wavelength.
    const bool terminated = lambda.secondary_terminated();
    const float eta_h = eta.eval(lambda.lambda[0]);
    SampledSpectrum R(reflectance(om, outside, eta_h, lambda.lambda[0]));
    if (film.present() || is_dispersive())
        for (int k = 1; k < (terminated ? 1 : kLambdaCount); ++k)
            R[k] = reflectance(om, outside, eta.eval(lambda.lambda[k]), lambda.lambda[k]);
    const float p_reflect = mean_over_live(R, lambda);

    BsdfSample bs;
    const std::uint8_t lobe = smooth ? BsdfFlags::delta : BsdfFlags::non_delta;
    if (u_lobe < p_reflect) {
        const Vec3 i = m * (2.f * om) - o;
        if (!(i.z > 0.f)) return std::nullopt;
        bs.wi = f.to_world(i);
        bs.weight = R / p_reflect;
        if (!smooth) {
            bs.weight *= ggx.G2(o, i) / ggx.G1(o);
            bs.pdf = ggx.visible_pdf(o, m) / (4.f * om) * R[0];
        }
        bs.flags = {std::uint8_t(BsdfFlags::reflection | lobe)};
        return bs;
    }
    const float etap = outside ? eta_h : 1.f / eta_h;
    const std::optional<Vec3> t = refract(o, m, etap);
    if (!t || !(t->z < 0.f)) return std::nullopt;  // total internal reflection at the hero: R₀ = 1
    const Vec3 i = *t;
    bs.wi = f.to_world(i);
    bs.weight = (SampledSpectrum(1.f) - R) / (1.f - p_reflect);
    if (!smooth) {
        const float im = dot(i, m);
        bs.weight *= ggx.G2(o, i) / ggx.G1(o);
        bs.pdf = ggx.visible_pdf(o, m) * std::fabs(im) / sqr(im + om / etap) * (1.f - R[0]);
    }
    bs.flags = {std::uint8_t(BsdfFlags::transmission | lobe)};
    if (is_dispersive() && !terminated) {
        // Other wavelengths would bend elsewhere: only the hero follows this direction.
        lambda.terminate_secondary();
        for (int k = 1; k < kLambdaCount; ++k) bs.weight[k] = 0.f;
        bs.flags.bits |= BsdfFlags::dispersive;
    }
    // Radiance is compressed by (η_i/η_t)² crossing into the denser side; importance is not.
    if (mode == TransportMode::radiance) bs.weight /= etap * etap;
    bs.eta_scale = etap * etap;
    return bs;
}

}  // namespace spt

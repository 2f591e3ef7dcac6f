#include "model/bsdfs/plastic.h"

#include "core/sampling.h"

namespace spt {

namespace {

/// f·cos θi of the rough coat alone (o, i local on the +z side).
float coat_eval(const GgxDistribution& ggx, float eta, const Vec3& o, const Vec3& i) {
    if (!(o.z > 0.f) || !(i.z > 0.f)) return 0.f;
    const Vec3 m = normalize(o + i);
    const float om = dot(o, m);
    if (!(om > 0.f)) return 0.f;
    return fresnel_dielectric(om, eta) * ggx.D(m) * ggx.G2(o, i) / (4.f * o.z);
}

float coat_pdf(const GgxDistribution& ggx, const Vec3& o, const Vec3& i) {
    if (!(o.z > 0.f) || !(i.z > 0.f)) return 0.f;
    const Vec3 m = normalize(o + i);
    const float om = dot(o, m);
    if (!(om > 0.f)) return 0.f;
    return ggx.visible_pdf(o, m) / (4.f * om);
}

/// Directional albedo of the coat's specular lobe at cos θo = mu.
double coat_albedo(const GgxDistribution& ggx, float eta, float mu) {
    mu = std::max(mu, 1e-4f);
    if (ggx.is_smooth()) return fresnel_dielectric(mu, eta);
    const Vec3 o{std::sqrt(std::max(0.f, 1.f - mu * mu)), 0.f, mu};
    constexpr int kSide = 64;
    double sum = 0;
    for (int a = 0; a < kSide; ++a)
        for (int b = 0; b < kSide; ++b) {
            const Vec3 m = ggx.sample_visible_normal(o, (a + 0.5f) / kSide, (b + 0.5f) / kSide);
            const float om = dot(o, m);
            const Vec3 i = m * (2.f * om) - o;
            if (!(i.z > 0.f) || !(om > 0.f)) continue;
            sum += fresnel_dielectric(om, eta) * ggx.G2(o, i) / ggx.G1(o);
        }
    return sum / (kSide * kSide);
}

}  // namespace

PlasticBsdf make_plastic(Spectrum kd, float eta, float alpha) {
    PlasticBsdf p;
    p.eta = eta;
    p.ggx.alpha = alpha;
    constexpr int N = PlasticBsdf::kAlbedoPoints;
    for (int j = 0; j < N; ++j) p.coat_albedo[j] = static_cast<float>(coat_albedo(p.ggx, eta, float(j) / (N - 1)));
    // E_avg = 2∫E(μ)μ dμ of the piecewise-linear E, exactly: on [a, b] with E from ea to eb,
    // ∫μE dμ = h·(ea·(2a + b) + eb·(a + 2b))/6.
    double avg = 0;
    for (int j = 0; j + 1 < N; ++j) {
        const double a = double(j) / (N - 1), b = double(j + 1) / (N - 1), h = b - a;
        avg += 2.0 * h * (p.coat_albedo[j] * (2 * a + b) + p.coat_albedo[j + 1] * (a + 2 * b)) / 6.0;
    }
    p.coat_albedo_avg = static_cast<float>(avg);
    double sum = 0;
    int count = 0;
    for (double l = Spectrum::kBinMin; l <= Spectrum::kBinMax; l += 1.0, ++count) sum += kd.eval(static_cast<float>(l));
    p.kd_mean = static_cast<float>(sum / count);
    p.kd = std::move(kd);
    return p;
}

SampledSpectrum PlasticBsdf::eval(const Vec3& wo, const Vec3& wi, const Vec3& n, const SampledWavelengths& lambda,
                                  TransportMode) const {
    const Frame f = frame_on_side_of(wo, n);
    const Vec3 o = f.to_local(wo), i = f.to_local(wi);
    if (!(o.z > 0.f) || !(i.z > 0.f)) return SampledSpectrum(0.f);
    const float diffuse = (1.f - coat_albedo_at(o.z)) * (1.f - coat_albedo_at(i.z)) /
                          (kPi * (1.f - coat_albedo_avg)) * i.z;
    SampledSpectrum r = kd.sample(lambda) * diffuse;
    if (!ggx.is_smooth()) r += SampledSpectrum(coat_eval(ggx, eta, o, i));
    return r;
}

float PlasticBsdf::pdf(const Vec3& wo, const Vec3& wi, const Vec3& n, float) const {
    const Frame f = frame_on_side_of(wo, n);
    const Vec3 o = f.to_local(wo), i = f.to_local(wi);
    if (!(o.z > 0.f) || !(i.z > 0.f)) return 0.f;
    const float pc = coat_probability(o.z);
    const float diffuse = (1.f - pc) * i.z * kInvPi;
    return ggx.is_smooth() ? diffuse : diffuse + pc * coat_pdf(ggx, o, i);
}

std::optional<BsdfSample> PlasticBsdf::sample(const Vec3& wo, const Vec3& n, SampledWavelengths& lambda,
                                              float u_lobe, float u1, float u2, TransportMode mode) const {
    const Frame f = frame_on_side_of(wo, n);
    const Vec3 o = f.to_local(wo);
    if (!(o.z > 0.f)) return std::nullopt;
    const float pc = coat_probability(o.z);
    BsdfSample bs;
    if (u_lobe < pc) {
        if (ggx.is_smooth()) {  // the coat's mirror: a delta lobe, F the same at every λ
            bs.wi = f.to_world({-o.x, -o.y, o.z});
            bs.weight = SampledSpectrum(fresnel_dielectric(o.z, eta) / pc);
            bs.flags = {BsdfFlags::reflection | BsdfFlags::delta};
            return bs;
        }
        const Vec3 m = ggx.sample_visible_normal(o, u1, u2);
        bs.wi = f.to_world(m * (2.f * dot(o, m)) - o);
    } else {
        bs.wi = f.to_world(sample_cosine_hemisphere(u1, u2));
    }
    // Both lobes could have produced wi: weight by the mixture density (one-sample MIS).
    bs.pdf = pdf(wo, bs.wi, n, lambda.lambda[0]);
    if (!(bs.pdf > 0.f)) return std::nullopt;
    bs.weight = eval(wo, bs.wi, n, lambda, mode) / bs.pdf;
    bs.flags = {BsdfFlags::reflection | BsdfFlags::non_delta};
    return bs;
}

}  // namespace spt

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

}  // namespace

PlasticBsdf make_plastic(Spectrum kd, float eta, float alpha, bool textured_roughness) {
    PlasticBsdf p;
    p.eta = eta;
    p.ggx.alpha = alpha;
    if (textured_roughness) p.coat_table = &coat_albedo_table(eta);
    else p.coat = make_coat_albedo(alpha, eta);
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
                          (kPi * (1.f - coat_albedo_average())) * i.z;
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

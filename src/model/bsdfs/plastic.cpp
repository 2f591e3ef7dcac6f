#include "model/bsdfs/plastic.h"

#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <utility>
#include <vector>

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

/// The dispersive coat of index eta at roughness alpha, shared by plastics whose indices agree
/// at every nm of 360–830 (one table per α and index range); kept for the process, so a BSDF
/// holds a plain pointer to it.
const DispersiveCoat& dispersive_coat(const Spectrum& eta, float alpha) {
    static std::mutex mutex;
    static std::map<std::pair<float, std::vector<float>>, std::unique_ptr<const DispersiveCoat>> coats;
    std::vector<float> key{eta.min_value(), eta.max_value()};
    for (float l = kLambdaMin; l <= kLambdaMax; l += 1.f) key.push_back(eta.eval(l));
    const std::lock_guard<std::mutex> lock(mutex);
    std::unique_ptr<const DispersiveCoat>& slot = coats[{alpha, std::move(key)}];
    if (!slot) slot = std::make_unique<const DispersiveCoat>(
                   DispersiveCoat{eta, &coat_albedo_over_index(alpha, eta.min_value(), eta.max_value())});
    return *slot;
}

}  // namespace

PlasticBsdf make_plastic(Spectrum kd, const Spectrum& eta, float alpha, bool textured_roughness) {
    if (eta.is_constant()) return make_plastic(std::move(kd), eta.eval(550.f), alpha, textured_roughness);
    if (textured_roughness)
        throw std::invalid_argument("a plastic's coat index varying with wavelength cannot have a textured roughness");
    const DispersiveCoat& d = dispersive_coat(eta, alpha);
    // The lobe choice's coat: E at the mean index, read from the same table.
    double sum = 0;
    int count = 0;
    for (double l = Spectrum::kBinMin; l <= Spectrum::kBinMax; l += 1.0, ++count)
        sum += d.index(static_cast<float>(l));
    const float eta_mean = static_cast<float>(sum / count);
    PlasticBsdf p = make_plastic(std::move(kd), eta_mean, alpha, false);
    for (int j = 0; j < CoatAlbedo::kPoints; ++j)
        p.coat.e[static_cast<std::size_t>(j)] = d.table->at(eta_mean, float(j) / (CoatAlbedo::kPoints - 1));
    p.coat.average = d.table->average(eta_mean);
    p.dispersion = &d;
    return p;
}

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
    if (dispersion) return eval_dispersive(o, i, lambda);
    const float diffuse = (1.f - coat_albedo_at(o.z)) * (1.f - coat_albedo_at(i.z)) /
                          (kPi * (1.f - coat_albedo_average())) * i.z;
    SampledSpectrum r = kd.sample(lambda) * diffuse;
    if (!ggx.is_smooth()) r += SampledSpectrum(coat_eval(ggx, eta, o, i));
    return r;
}

SampledSpectrum PlasticBsdf::eval_dispersive(const Vec3& o, const Vec3& i, const SampledWavelengths& lambda) const {
    const CoatAlbedoRows& t = *dispersion->table;
    // The rough coat's D·G2/(4 cos θo) is the same at every λ; only F depends on η(λ).
    float om = 0.f, dg = 0.f;
    if (!ggx.is_smooth()) {
        const Vec3 m = normalize(o + i);
        om = dot(o, m);
        if (om > 0.f) dg = ggx.D(m) * ggx.G2(o, i) / (4.f * o.z);
    }
    const SampledSpectrum kd_l = kd.sample(lambda);
    SampledSpectrum r(0.f);
    for (int k = 0; k < kLambdaCount; ++k) {
        const float eta_k = dispersion->index(lambda.lambda[k]);
        const float diffuse =
            (1.f - t.at(eta_k, o.z)) * (1.f - t.at(eta_k, i.z)) / (kPi * (1.f - t.average(eta_k))) * i.z;
        r[k] = kd_l[k] * diffuse + (dg > 0.f ? fresnel_dielectric(om, eta_k) * dg : 0.f);
    }
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
        if (ggx.is_smooth()) {  // the coat's mirror: a delta lobe (a constant coat: F the same at every λ)
            bs.wi = f.to_world({-o.x, -o.y, o.z});
            bs.weight = SampledSpectrum(fresnel_dielectric(o.z, eta) / pc);
            // A dispersive coat: each λ's own F (the mirror direction is every λ's).
            if (dispersion)
                for (int k = 0; k < kLambdaCount; ++k)
                    bs.weight[k] = fresnel_dielectric(o.z, dispersion->index(lambda.lambda[k])) / pc;
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

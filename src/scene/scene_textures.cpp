// Texture look-ups at hits and on lights, and the tangent of anisotropic BSDFs. Out of line
// and called only from the textured instances of the integrators, so scenes without textures
// never reach this code.
#include <array>

#include "scene/scene.h"

namespace spt {

namespace {

/// Room for the value of any texture: a spectrum at the finest resolution, or a number.
using TextureValue = std::array<float, std::max(kExactTextureBins, SpectralResolution::kMaxBins)>;

/// Bin values at the path's wavelengths, interpolated as Spectrum::eval does.
SampledSpectrum sample_bins(std::span<const float> bins, const SampledWavelengths& lambda) {
    SampledSpectrum s;
    const int n = static_cast<int>(bins.size());
    if (n == 1) return SampledSpectrum(bins[0]);
    const float inv_width = static_cast<float>(n / double(Spectrum::kBinMax - Spectrum::kBinMin));
    for (int k = 0; k < kLambdaCount; ++k) {
        const float x = std::clamp((lambda.lambda[k] - Spectrum::kBinMin) * inv_width - 0.5f, 0.f, float(n - 1));
        const int i = std::min(static_cast<int>(x), n - 2);
        s[k] = lerp(x - static_cast<float>(i), bins[i], bins[i + 1]);
    }
    return s;
}

/// Surface coordinates of a point on an area light, as the light's shape defines them (on
/// a mesh light, on its triangle `triangle`).
void light_point_uv(const Scene& scene, const Light& light, const Vec3& p, std::uint32_t triangle, float& u,
                    float& v) {
    u = v = 0.f;
    if (const TriangleMeshLight* m = std::get_if<TriangleMeshLight>(&light))
        return scene.triangle_uv(m->triangles[triangle], p, u, v);
    if (const SphereLight* s = std::get_if<SphereLight>(&light)) return s->sphere.uv(p, u, v);
    if (const PlaneLight* pl = std::get_if<PlaneLight>(&light)) return pl->plane.uv(p, u, v);
    if (const QuadricLight* q = std::get_if<QuadricLight>(&light))
        return std::visit([&](const auto& shape) { shape.uv(p, u, v); }, q->shape);
    if (const QuadLight* q = std::get_if<QuadLight>(&light)) {
        // p = o + u·e1 + v·e2, solved by least squares in double (as Triangle::uv).
        const DVec3 e1(q->e1), e2(q->e2), w = DVec3(p) - DVec3(q->o);
        const double d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2);
        const double w1 = dot(w, e1), w2 = dot(w, e2), det = d11 * d22 - d12 * d12;
        u = static_cast<float>(std::clamp((d22 * w1 - d12 * w2) / det, 0.0, 1.0));
        v = static_cast<float>(std::clamp((d11 * w2 - d12 * w1) / det, 0.0, 1.0));
    }
}

SampledSpectrum texture_spectrum(const Texture& t, float u, float v, const SampledWavelengths& lambda) {
    TextureValue value;
    const std::span<float> out(value.data(), static_cast<std::size_t>(t.bins));
    t.eval(u, v, out);
    return sample_bins(out, lambda);
}

}  // namespace

const Bsdf& Scene::textured_bsdf(const Hit& hit, Bsdf& scratch) const {
    const Material& m = materials[static_cast<std::size_t>(hit.material)];
    scratch = m.bsdf;
    float u, v;
    surface_uv(hit, u, v);
    TextureValue value;
    for (const TextureBinding& b : m.textures) {
        const Texture& t = textures[static_cast<std::size_t>(b.texture)];
        const std::span<float> out(value.data(), static_cast<std::size_t>(t.bins));
        t.eval(u, v, out);
        if (b.parameter->spectrum) b.parameter->spectrum(scratch)->assign_bins(out);
        else *b.parameter->number(scratch) = out[0];
    }
    if (ConductorBsdf* c = std::get_if<ConductorBsdf>(&scratch); c && c->anisotropic()) c->tangent = surface_tangent(hit);
    return scratch;
}

SampledSpectrum Scene::texture_emission(const Hit& hit, const Vec3& wo, const SampledWavelengths& lambda) const {
    if (!light_emits_towards(lights[static_cast<std::size_t>(hit.light)], hit.n, wo)) return SampledSpectrum(0.f);
    float u, v;
    surface_uv(hit, u, v);
    return texture_spectrum(textures[static_cast<std::size_t>(light_textures[static_cast<std::size_t>(hit.light)])], u,
                            v, lambda);
}

SampledSpectrum Scene::light_point_emission(int index, const Vec3& p, std::uint32_t triangle,
                                            const SampledWavelengths& lambda) const {
    float u, v;
    light_point_uv(*this, lights[static_cast<std::size_t>(index)], p, triangle, u, v);
    return texture_spectrum(textures[static_cast<std::size_t>(light_textures[static_cast<std::size_t>(index)])], u, v,
                            lambda);
}

}  // namespace spt

// GGX (Trowbridge–Reitz) microfacet distribution, isotropic, with the height-correlated Smith
// masking-shadowing function, sampled by its distribution of visible normals (Heitz 2018,
// "Sampling the GGX distribution of visible normals"). Shared by every rough BSDF type.
//
// Directions are in the local frame of the macro-surface (z = the normal). α is the GGX
// roughness (the slope scale: α = 0 is a mirror, α = 1 very rough). The anisotropic lobe
// (anisotropic_ggx.h) shares the visible-normal sampling below.
#pragma once
#include "core/math.h"
#include "core/vec3.h"

namespace spt {

/// A GGX microfacet normal m (m.z ≥ 0) visible from w (w.z > 0) for roughness α_x along x and
/// α_y along y, distributed as the distribution's visible_pdf (Heitz 2018): stretch w to the
/// configuration of α = 1, sample the visible hemisphere there (a projected disk, its far half
/// squeezed), and unstretch the normal. With α_x = α_y the isotropic lobe's sampling.
inline Vec3 sample_ggx_visible_normal(const Vec3& w, float alpha_x, float alpha_y, float u1, float u2) {
    const Vec3 vh = normalize(Vec3{alpha_x * w.x, alpha_y * w.y, w.z});
    const float len2 = vh.x * vh.x + vh.y * vh.y;
    const Vec3 t1 = len2 > 0.f ? Vec3{-vh.y, vh.x, 0.f} / std::sqrt(len2) : Vec3{1.f, 0.f, 0.f};
    const Vec3 t2 = cross(vh, t1);
    const float r = std::sqrt(u1), phi = 2.f * kPi * u2;
    const float p1 = r * std::cos(phi);
    float p2 = r * std::sin(phi);
    const float s = 0.5f * (1.f + vh.z);
    p2 = (1.f - s) * safe_sqrt(1.f - p1 * p1) + s * p2;
    const Vec3 nh = t1 * p1 + t2 * p2 + vh * safe_sqrt(1.f - p1 * p1 - p2 * p2);
    return normalize(Vec3{alpha_x * nh.x, alpha_y * nh.y, std::max(1e-7f, nh.z)});
}

struct GgxDistribution {
    float alpha = 0.f;

    /// Below this α the distribution is treated as a perfect mirror (delta lobe): D would
    /// overflow single precision.
    static constexpr float kSmoothAlpha = 1e-4f;
    bool is_smooth() const { return alpha < kSmoothAlpha; }

    /// Microfacet normal density D(m) (per unit solid angle of m, projected: ∫D cos θm = 1).
    float D(const Vec3& m) const {
        const float cos2 = m.z * m.z;
        if (!(cos2 > 0.f)) return 0.f;
        const float a2 = alpha * alpha;
        const float t = cos2 * (a2 - 1.f) + 1.f;  // = cos²θ·(α² + tan²θ)
        return a2 / (kPi * t * t);
    }
    /// Smith Λ(w): masking of one direction is 1/(1 + Λ).
    float Lambda(const Vec3& w) const {
        const float cos2 = w.z * w.z;
        if (!(cos2 > 0.f)) return 0.f;
        const float tan2 = std::max(0.f, 1.f - cos2) / cos2;
        return 0.5f * (std::sqrt(1.f + alpha * alpha * tan2) - 1.f);
    }
    float G1(const Vec3& w) const { return 1.f / (1.f + Lambda(w)); }
    /// Height-correlated masking-shadowing of the pair (Heitz 2014, eq. 99).
    float G2(const Vec3& wo, const Vec3& wi) const { return 1.f / (1.f + Lambda(wo) + Lambda(wi)); }

    /// Density of visible normals from w (w.z > 0): G1(w)·max(0, w·m)·D(m)/w.z, the density
    /// of sample_visible_normal per unit solid angle of m.
    float visible_pdf(const Vec3& w, const Vec3& m) const {
        const float wm = dot(w, m);
        if (!(wm > 0.f) || !(w.z > 0.f)) return 0.f;
        return G1(w) * wm * D(m) / w.z;
    }

    /// A microfacet normal m (m.z ≥ 0) visible from w (w.z > 0), distributed as visible_pdf.
    Vec3 sample_visible_normal(const Vec3& w, float u1, float u2) const {
        return sample_ggx_visible_normal(w, alpha, alpha, u1, u2);
    }
};

}  // namespace spt

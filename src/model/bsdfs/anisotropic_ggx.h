// Anisotropic GGX: α_x along the surface tangent, α_y across it (Heitz 2014, "Understanding
// the masking-shadowing function", §5.2 and eq. 86), with the height-correlated Smith
// masking-shadowing and sampling of the visible normals in the stretched configuration
// (Heitz 2018, "Sampling the GGX distribution of visible normals"). With α_x = α_y it is the
// isotropic GgxDistribution (microfacet.h), which the isotropic types keep using unchanged.
//
// Directions are in the local frame: x the tangent, y = z × x, z the normal (anisotropic_frame).
#pragma once
#include "core/frame.h"
#include "core/math.h"
#include "core/vec3.h"
#include "model/bsdfs/microfacet.h"

namespace spt {

struct AnisotropicGgx {
    float alpha_x = 0.f, alpha_y = 0.f;

    /// D(m): ∫D(m) cos θm dωm = 1.
    float D(const Vec3& m) const {
        if (!(m.z > 0.f)) return 0.f;
        const float x = m.x / alpha_x, y = m.y / alpha_y;
        const float t = x * x + y * y + m.z * m.z;  // = cos²θm·(1 + tan²θm·(cos²φ/α_x² + sin²φ/α_y²))
        return 1.f / (kPi * alpha_x * alpha_y * t * t);
    }
    /// Smith Λ(w) with the projected roughness α(φ)² = α_x² cos²φ + α_y² sin²φ.
    float Lambda(const Vec3& w) const {
        const float cos2 = w.z * w.z;
        if (!(cos2 > 0.f)) return 0.f;
        const float a2_tan2 = (alpha_x * alpha_x * w.x * w.x + alpha_y * alpha_y * w.y * w.y) / cos2;
        return 0.5f * (std::sqrt(1.f + a2_tan2) - 1.f);
    }
    float G1(const Vec3& w) const { return 1.f / (1.f + Lambda(w)); }
    float G2(const Vec3& wo, const Vec3& wi) const { return 1.f / (1.f + Lambda(wo) + Lambda(wi)); }

    /// Density of visible normals from w (w.z > 0) per unit solid angle of m.
    float visible_pdf(const Vec3& w, const Vec3& m) const {
        const float wm = dot(w, m);
        if (!(wm > 0.f) || !(w.z > 0.f)) return 0.f;
        return G1(w) * wm * D(m) / w.z;
    }

    /// A microfacet normal visible from w (w.z > 0), distributed as visible_pdf.
    Vec3 sample_visible_normal(const Vec3& w, float u1, float u2) const {
        return sample_ggx_visible_normal(w, alpha_x, alpha_y, u1, u2);
    }
};

/// The local frame of an anisotropic lobe: z the normal on wo's side, x the tangent made
/// perpendicular to it (any perpendicular direction if the tangent is zero or along n).
inline Frame anisotropic_frame(const Vec3& wo, const Vec3& n, const Vec3& tangent) {
    Frame f(dot(wo, n) > 0.f ? n : -n);
    const Vec3 x = tangent - f.n * dot(tangent, f.n);
    const float len = length(x);
    if (!(len > 1e-6f) || !std::isfinite(len)) return f;
    f.s = x / len;
    f.t = cross(f.n, f.s);
    return f;
}

}  // namespace spt

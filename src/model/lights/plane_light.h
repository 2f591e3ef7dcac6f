// An emitting infinite plane (the Cornell ceiling): Le from both sides. It has no finite
// area, so next-event estimation samples a direction, and every direction of the half-space
// facing the plane (m·ω > 0, m its normal turned towards it) reaches it with radiance Le.
// At a reference point that gathers light on one side (normal ns), the integrand of a
// Lambertian surface is Le·(ρ/π)·cos θ over the lune where both ns·ω > 0 and m·ω > 0, so
// the sampler draws exactly that: cosine-weighted about ns, restricted to the lune. Seen
// from above (Malley), the lune is the part of the unit disk with x > −c·√(1 − y²)
// (c = ns·m, x towards m's tangent part), each row (1 + c) times as wide as the half
// disk x ∈ [0, √(1 − y²)]: a point uniform in the half disk, stretched along its row,
// is uniform in the lune. Its density is cos θ / (π(1 + c)/2), and a diffuse surface's
// estimate Le·ρ·(1 + c)/2 (the view factor) is the same for every sample: only shadows
// leave noise. Where both sides gather light (a transmitting BSDF), directions are
// cosine-weighted about m instead; every one reaches the plane, the density falling to 0
// towards its horizon, where it recedes. It cannot start light subpaths (no area to sample).
#pragma once
#include <algorithm>
#include <cmath>
#include <optional>

#include "core/frame.h"
#include "core/sampling.h"
#include "geometry/plane.h"
#include "model/lights/light_sample.h"
#include "spectral/spectrum.h"

namespace spt {

struct PlaneLight {
    Plane plane;
    Spectrum Le;  ///< radiance, both sides
    /// The radius of the scene's bounding sphere: the plane's power for light selection is
    /// what it sends into a disk of that radius, π·Le·πR² (it has no finite power).
    float scene_radius = 1.f;

    float power() const { return kPi * kPi * scene_radius * scene_radius * mean_over_visible(Le); }

    /// Signed distance of p from the plane along its normal (double: p may lie far away).
    double side(const Vec3& p) const {
        return double(plane.normal.x) * p.x + double(plane.normal.y) * p.y + double(plane.normal.z) * p.z -
               plane.offset;
    }
    /// Unit normal of the plane turned towards it from p; zero when p lies on the plane.
    Vec3 towards(const Vec3& p) const {
        const double s = side(p);
        if (s == 0.0) return {};
        return s > 0.0 ? -plane.normal : plane.normal;
    }

    /// Below this 1 + c the lune is empty for a float sampler (the plane lies behind the
    /// gathering side): no sample, density 0.
    static constexpr float kMinLune = 1e-6f;

    std::optional<LightSample> sample_li(const LightSampleContext& ctx, const SampledWavelengths& lambda, float u1,
                                         float u2) const {
        const double s = side(ctx.p);
        if (s == 0.0) return std::nullopt;
        const Vec3 m = s > 0.0 ? -plane.normal : plane.normal;
        LightSample ls;
        if (ctx.both_sides) {
            const Vec3 local = sample_cosine_hemisphere(u1, u2);
            if (!(local.z > 0.f)) return std::nullopt;
            ls.wi = Frame(m).to_world(local);
            ls.pdf = local.z * kInvPi;
        } else {
            const float c = dot(ctx.ns, m);
            if (!(1.f + c > kMinLune)) return std::nullopt;
            // Tangent towards m (any tangent when m is along ns: then the lune is the whole
            // hemisphere and the row stretch is 2 with offset −c·w = −w, or the lune is empty).
            Vec3 t = m - ctx.ns * c;
            const float t_len = length(t);
            t = t_len > 1e-6f ? t / t_len : Frame(ctx.ns).s;
            const Vec3 b = cross(ctx.ns, t);
            // A point uniform in the half disk x ≥ 0 (polar), stretched along its row.
            const float r = std::sqrt(u1), phi = kPi * (u2 - 0.5f);
            const float y = r * std::sin(phi), x_half = r * std::cos(phi);
            const float w = safe_sqrt(1.f - y * y);
            const float x = std::clamp(-c * w + (1.f + c) * x_half, -w, w);
            const float z = safe_sqrt(1.f - x * x - y * y);
            ls.wi = normalize(t * x + b * y + ctx.ns * z);
            const float cos_n = dot(ls.wi, ctx.ns);
            if (!(cos_n > 0.f) || !(dot(ls.wi, m) > 0.f)) return std::nullopt;
            ls.pdf = lune_pdf(cos_n, c);
        }
        // The distance along wi: |side| / cos θ to the plane (the shadow ray needs no point on it).
        ls.plane_distance = static_cast<float>(std::fabs(s) / dot(ls.wi, m));
        if (!std::isfinite(ls.plane_distance) || !(ls.plane_distance > 0.f)) return std::nullopt;
        ls.L = Le.sample(lambda);
        return ls;
    }

    float pdf_li(const LightSampleContext& ctx, const Vec3& wi) const {
        const Vec3 m = towards(ctx.p);
        if (ctx.both_sides) return cosine_hemisphere_pdf(dot(wi, m));
        const float c = dot(ctx.ns, m), cos_n = dot(wi, ctx.ns);
        if (!(1.f + c > kMinLune) || !(cos_n > 0.f) || !(dot(wi, m) > 0.f)) return 0.f;
        return lune_pdf(cos_n, c);
    }

    /// Solid-angle density of the lune sampler: cos θ over the lune's projected area π(1 + c)/2.
    static float lune_pdf(float cos_n, float c) { return 2.f * cos_n / (kPi * (1.f + c)); }
};

}  // namespace spt

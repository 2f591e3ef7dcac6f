// Emission sampling shared by the area lights: both sides of an area emitter emit Le, so a
// light subpath leaves a sampled surface point on a side chosen with probability 1/2, in a
// cosine-weighted direction on it.
#pragma once
#include <optional>

#include "core/frame.h"
#include "core/sampling.h"
#include "model/lights/light_sample.h"

namespace spt {

/// Fills o.w, o.Le and o.pdf_dir for the point o.p of normal o.n; nullopt at the horizon.
inline std::optional<LightOrigin> emit_two_sided(LightOrigin o, const SampledSpectrum& Le, float u_side,
                                                 float u1, float u2) {
    const Vec3 side = u_side < 0.5f ? o.n : -o.n;
    const Vec3 local = sample_cosine_hemisphere(u1, u2);
    if (!(local.z > 0.f)) return std::nullopt;
    o.w = Frame(side).to_world(local);
    o.Le = Le;
    o.pdf_dir = 0.5f * local.z * kInvPi;
    return o;
}

/// Solid-angle density of emitting towards w from a two-sided area emitter of normal n.
inline float two_sided_direction_pdf(const Vec3& n, const Vec3& w) { return 0.5f * std::fabs(dot(n, w)) * kInvPi; }

/// Area density at a light point turned into solid angle at the reference point:
/// pdf_area · r² / |cos θ_light|; 0 when the light is seen edge-on.
inline float area_to_solid_angle(float pdf_area, const Vec3& ref, const Vec3& p_light, const Vec3& n_light) {
    const Vec3 d = p_light - ref;
    const float dist2 = length_squared(d);
    const float cos_l = std::fabs(dot(n_light, d)) / std::sqrt(dist2);
    if (!(cos_l > 0.f) || !(dist2 > 0.f)) return 0.f;
    return pdf_area * dist2 / cos_l;
}

/// Completes a sample of an area light whose point, normal and solid-angle density are set:
/// the direction from the reference point and the radiance; false when the point coincides
/// with the reference point or the density is not a finite positive number (seen edge-on).
inline bool finish_area_sample(LightSample& ls, const Vec3& ref, const SampledSpectrum& Le) {
    const Vec3 d = ls.p - ref;
    const float dist = length(d);
    if (!(dist > 0.f) || !(ls.pdf > 0.f) || !std::isfinite(ls.pdf)) return false;
    ls.wi = d / dist;
    ls.L = Le;
    return true;
}

}  // namespace spt

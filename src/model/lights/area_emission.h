// What the area lights share: which sides emit, emission sampling, and the conversion of an
// area density to solid angle. A two-sided emitter emits Le from both sides of its surface; a
// one-sided one only from its front, the side its normal (Hit::n, the shape's orientation)
// points to, and is black seen from behind. A light subpath leaves a sampled surface point in
// a cosine-weighted direction on an emitting side (for a two-sided light, each side with
// probability 1/2).
#pragma once
#include <algorithm>
#include <cmath>
#include <optional>

#include "core/frame.h"
#include "core/sampling.h"
#include "model/lights/light_sample.h"

namespace spt {

/// Whether an area light of normal n at a point emits along w: from both sides, or
/// (one-sided) only towards its front.
[[gnu::always_inline]] inline bool emits_towards(bool two_sided, const Vec3& n, const Vec3& w) {
    return two_sided || dot(n, w) > 0.f;
}

/// Emitted power of an area light of uniform radiance: ∫∫ L |cos| dA dω = π·A·Le per side;
/// with `lambda_nm`, per nm at that wavelength (spectral_power of the contract).
template <typename SpectrumT>
float area_light_power(bool two_sided, float area, const SpectrumT& Le) {
    return (two_sided ? 2.f : 1.f) * kPi * area * mean_over_visible(Le);
}
template <typename SpectrumT>
float area_light_power(bool two_sided, float area, const SpectrumT& Le, float lambda_nm) {
    return (two_sided ? 2.f : 1.f) * kPi * area * Le.eval(lambda_nm);
}

/// Fills o.w, o.Le and o.pdf_dir for the point o.p of normal o.n (a side chosen by u_side
/// when both emit, else the front); nullopt at the horizon.
inline std::optional<LightOrigin> emit_from_surface(LightOrigin o, const SampledSpectrum& Le, bool two_sided,
                                                    float u_side, float u1, float u2) {
    const Vec3 side = !two_sided || u_side < 0.5f ? o.n : -o.n;
    const Vec3 local = sample_cosine_hemisphere(u1, u2);
    if (!(local.z > 0.f)) return std::nullopt;
    o.w = Frame(side).to_world(local);
    o.Le = Le;
    o.pdf_dir = (two_sided ? 0.5f : 1.f) * local.z * kInvPi;
    return o;
}

/// Solid-angle density of emitting towards w from an area emitter of normal n (emit_from_surface's).
inline float emission_direction_pdf(bool two_sided, const Vec3& n, const Vec3& w) {
    if (two_sided) return 0.5f * std::fabs(dot(n, w)) * kInvPi;
    return std::max(0.f, dot(n, w)) * kInvPi;
}

/// Solid-angle density of emitting towards w from a two-sided area emitter of normal n.
inline float two_sided_direction_pdf(const Vec3& n, const Vec3& w) { return emission_direction_pdf(true, n, w); }

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

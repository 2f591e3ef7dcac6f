// Specular next-event estimation off smooth spheres: reflection caustics (light → mirror
// reflection off a ball → diffuse surface → eye) sampled from the diffuse vertex instead of
// waiting for BSDF sampling to hit a small light after the mirror bounce (fireflies beside
// shiny and glass balls). The sibling of the refraction chain (render/caustic_nee.h), with
// the same light choice, area sampling and shadow tests; exact, without clamping:
//
//   At a vertex x with a non-delta lobe, the reflection chain is chosen with probability
//   1 − SphereChains::refraction_share (sphere_chains.cpp says why it is 0.1 beside glass
//   spheres) and one sphere of SphereChains::reflecting_spheres uniformly (together
//   P_s = (1 − share)/N; x's own sphere gives nothing: no ray leaving a convex ball meets it
//   again), one light of SphereChains::light_choice by power (P_l) and a point y on it by
//   area (p_A: caustic_light_sample, the cap of a sphere light that the ball can see). The
//   chain x → reflect at P1 → y is solved for all its roots (geometry/sphere_caustics.h,
//   Alhazen's problem: up to four) and each root contributes
//     f(x, ω)·|cos| · ρ(θ) · Le(y) · |dω_x/dA_y| / (P_s·P_l·p_A(y)) · w_snee
//   when the two segments (x → P1, P1 → y) are clear. ρ(θ) = ks + kt·F(cos θ) is what the
//   ball's BSDF returns for the reflection, summed over the lobes that produce it (the
//   mirror lobe ks, no Fresnel; the dielectric lobe's Fresnel reflection kt·F, F the
//   renderer's fresnel_dielectric of the constant index; a DielectricBsdf is kt = 1).
//
//   MIS (power heuristic) against BSDF sampling of the same path, whose density is
//   p_bsdf(ω_x)·P_r(θ): LobeMixBsdf::sample picks the mirror lobe with probability k̄s/k̄ and
//   the dielectric lobe with k̄t/k̄ (k̄ = k̄d + k̄s + k̄t, each the mean over the wavelengths
//   still live), and the dielectric reflects with the hero's F, so P_r = (k̄s + k̄t·F)/k̄
//   (DielectricBsdf: mean_over_live of F, the same F for a constant index). Both sides take
//   k̄ over the wavelengths live at x before x sampled its direction (the path loop keeps
//   that flag): the same function of the path for both strategies, and the exact density
//   except when x's own sampling terminates the companions (a rough dispersive refraction
//   at x), where MIS stays unbiased with a slightly worse weight. The density for this
//   strategy is p_snee = P_s·P_l·p_A(y)/|dω_x/dA_y|. The path loop, when its BSDF sampling
//   goes x (non-delta) → reflects off a reflecting sphere from outside → an emitter, weights
//   that emission by p_chain²/(p_chain² + p_snee²), but only if the solver, given x and y,
//   returns the path's root (reflection_emission_weight asks it): a root the 16-cell scan
//   misses near a fold keeps weight 1 there, and the sum stays exact.
//
//   Depth: x at depth d samples only when d + 1 < max_depth (the reflection is bounce d + 1).
//   Lights, media and --light-sampling as in the refraction chain.
#pragma once
#include <cmath>

#include "render/caustic_nee.h"

namespace spt {

/// The probability with which the ball's BSDF picks the reflection at incidence cos θ: see
/// the header. `terminated`: the wavelengths' state the lobe means are taken over.
inline float sphere_reflection_probability(const ReflectingSphere& rs, float cos_theta,
                                           const SampledWavelengths& lambda, bool terminated) {
    const auto mean = [&](const Spectrum& k) {
        const SampledSpectrum v = k.sample(lambda);
        return terminated ? v[0] : v.average();
    };
    const float w_s = mean(rs.ks);
    const float w_t = rs.has_kt ? mean(rs.kt) : 0.f;
    const float w_d = rs.has_kd ? mean(rs.kd) : 0.f;
    const float total = w_d + w_s + w_t;
    if (!(total > 0.f)) return 0.f;
    const float F = rs.has_kt ? fresnel_dielectric(cos_theta, rs.eta) : 0.f;
    return (w_s + w_t * F) / total;
}

/// ρ(θ) = ks + kt·F(cos θ): what the ball's BSDF returns for the reflection (see the header).
inline SampledSpectrum sphere_reflectance(const ReflectingSphere& rs, float cos_theta,
                                          const SampledWavelengths& lambda, CausticNeeBug bug) {
    SampledSpectrum rho = rs.ks.sample(lambda);
    if (rs.has_kt) {
        const float eta = bug == CausticNeeBug::wrong_reflectance ? 1.f / rs.eta : rs.eta;
        rho += rs.kt.sample(lambda) * fresnel_dielectric(cos_theta, eta);
    }
    return rho;
}

/// The strategy's contribution at vertex `hit` (BSDF `bsdf`, outgoing wo); see the header.
/// u_sphere, u_light: the choices; u1, u2: the point on the light.
[[gnu::noinline]] inline SampledSpectrum sample_reflection_nee(const Scene& scene, const Bsdf& bsdf, const Hit& hit,
                                                               const Vec3& wo, const SampledWavelengths& lambda,
                                                               float time, float u_sphere, float u_light, float u1,
                                                               float u2, CausticNeeBug bug, PathStats& stats) {
    const SphereChains& chains = scene.sphere_chains;
    const int n_spheres = static_cast<int>(chains.reflecting_spheres.size());
    const int k = std::min(static_cast<int>(u_sphere * static_cast<float>(n_spheres)), n_spheres - 1);
    const ReflectingSphere& rs = chains.reflecting_spheres[static_cast<std::size_t>(k)];
    if (hit.prim.kind() == ShapeKind::sphere && hit.prim.index() == static_cast<std::uint32_t>(rs.sphere))
        return SampledSpectrum(0.f);
    ChainLightSample ls;
    if (!sample_chain_light(scene, rs.sphere, *chains.reflection_nodes, hit.p,
                            (1.f - chains.refraction_share) / static_cast<float>(n_spheres), u_light, u1, u2, ls))
        return SampledSpectrum(0.f);
    const Vec3 y = ls.y;
    const float p_choice = ls.p_choice;
    const int light = ls.light;
    const bool terminated = lambda.secondary_terminated();
    SampledSpectrum sum(0.f);
    for (int i = 0; i < ls.n; ++i) {
        const SphereChainRoot& r = ls.roots[i];
        const Vec3 wx = r.wx.to_float();
        const float dw_dA = chain_root_area_density(ls, r, bug);
        if (dw_dA == 0.f) continue;
        const SampledSpectrum f_cos = bsdf_eval(bsdf, wo, wx, hit.ns, lambda, TransportMode::radiance);
        if (f_cos.is_zero()) continue;
        const float cos_in = static_cast<float>(r.cos_in);
        const SampledSpectrum rho = sphere_reflectance(rs, cos_in, lambda, bug);
        if (rho.is_zero()) continue;
        const Vec3 p = r.entry.to_float();
        stats.rays += 2;
        const Ray to_p = spawn_ray_to(hit, p);
        if (dot(to_p.d, wx) < 0.99f) continue;  // x within rounding of the ball: no defined segment
        if (scene.occluded(to_p, {}, time) || caustic_segment_blocked(scene, p, y, time)) continue;
        const float p_snee = p_choice / dw_dA;
        const float p_chain = bsdf_pdf(bsdf, wo, wx, hit.ns, lambda.lambda[0]) *
                              sphere_reflection_probability(rs, cos_in, lambda, terminated);
        const SampledSpectrum Le =
            light_emitted(scene.lights[static_cast<std::size_t>(light)], y, ls.n_y, -r.w_exit.to_float(), lambda);
        sum += f_cos * rho * Le * (power_heuristic(p_snee, p_chain) / p_snee);
    }
    return sum;
}

/// The BSDF side's MIS weight of emission found along a chain x → reflect → `hit` (light
/// `light`): see the header. 1 when the strategy could not have produced this path.
[[gnu::noinline]] inline float reflection_emission_weight(const Scene& scene, const CausticChainState& s,
                                                          const Hit& hit, int light, const SampledWavelengths& lambda,
                                                          CausticNeeBug bug) {
    if (bug == CausticNeeBug::no_bsdf_side_weight) return 1.f;
    const SphereChains& chains = scene.sphere_chains;
    const float choice = chains.light_choice.probability(light);
    if (!(choice > 0.f)) return 1.f;
    const ReflectingSphere& rs = chains.reflecting_spheres[static_cast<std::size_t>(s.sphere)];
    const Sphere& ball = scene.spheres[static_cast<std::size_t>(rs.sphere)];
    const float pdf_area = caustic_light_area_pdf(scene, rs.sphere, light, hit.p);
    if (!(pdf_area > 0.f)) return 1.f;
    SphereChainRoot r{};
    float dw_dA = 0.f;
    if (!matched_chain_root(s, ball, *chains.reflection_nodes, hit, r, dw_dA)) return 1.f;
    const float p_snee =
        choice * pdf_area * ((1.f - chains.refraction_share) / static_cast<float>(chains.reflecting_spheres.size())) /
        dw_dA;
    const float p_r = sphere_reflection_probability(rs, static_cast<float>(r.cos_in), lambda, s.terminated_at_x);
    return power_heuristic(s.pdf_x * p_r, p_snee);
}

}  // namespace spt

// Next-event estimation in two halves, for the wavefront renderer (wavefront.cpp): a light
// sample with its shadow ray, queued for the shadow-ray stage, then what it adds once the ray
// is found clear. They mirror sample_point_lights and sample_area_light of integrator.cpp
// operation for operation, so both compute the same bits; the path loop shares shadow_ray_to
// and emission_weight with them but keeps its own light-sampling functions, flattened for
// the compiler (rewritten on these they compiled to different, slower code);
// test_parallel_strategies.cpp compares the two renderers bit for bit on every light type
// and setting, so any drift between the copies fails there.
#pragma once
#include <optional>

#include "model/bsdfs/bsdf.h"
#include "model/lights/light.h"
#include "render/mis.h"
#include "render/nee_light_choice.h"
#include "scene/scene.h"

namespace spt {

/// A delta-position light's shadow ray from a hit and what it adds through it when clear:
/// f·|cos| times the intensity I_max·falloff along the way out, over r².
struct DeltaLightRay {
    Ray shadow;
    SampledSpectrum contribution;
};

/// nullopt when the light cannot contribute (on the surface itself, outside its falloff,
/// or f·|cos| = 0).
[[gnu::always_inline]] inline std::optional<DeltaLightRay> delta_light_ray(const Light& delta_light, const Bsdf& bsdf,
                                                                           const Hit& hit, const Vec3& wo,
                                                                           const SampledWavelengths& lambda,
                                                                           float time) {
    return visit_light_of<kDeltaPositionLights>(delta_light, [&](const auto& light) -> std::optional<DeltaLightRay> {
        const Vec3 position = light.position_at(time);
        const Vec3 to_light = position - hit.p;
        const float dist2 = length_squared(to_light);
        if (!(dist2 > 0.f)) return std::nullopt;  // light exactly on the surface: no defined direction
        const Vec3 wi = to_light / std::sqrt(dist2);
        const float falloff = light.falloff(-wi);
        if (falloff == 0.f) return std::nullopt;
        const SampledSpectrum f_cos = bsdf_eval(bsdf, wo, wi, hit.ns, lambda, TransportMode::radiance);
        if (f_cos.is_zero()) return std::nullopt;
        return DeltaLightRay{spawn_ray_to(hit, position), f_cos * (light.I_max(lambda) * falloff) / dist2};
    });
}

/// The shadow ray from a hit to a sample of light `light` (not a point or spot light), and
/// the light's own shapes it may skip. Shared by the path loop and the wavefront renderer.
struct ShadowRay {
    Ray ray;
    ShadowSkip skip;
    bool past_planes = false;  ///< it crosses no infinite plane: Scene::occluded_past_planes
};
/// Whether anything blocks a shadow ray (at shutter time `time`).
[[gnu::always_inline]] inline bool shadow_blocked(const Scene& scene, const ShadowRay& shadow, float time) {
    return shadow.past_planes ? scene.occluded_past_planes(shadow.ray, shadow.skip, time)
                              : scene.occluded(shadow.ray, shadow.skip, time);
}
[[gnu::always_inline]] inline ShadowRay shadow_ray_to(const Scene& scene, const Hit& hit, const LightSample& ls,
                                                      int light) {
    if (ls.unoccluding_sphere >= 0 && !scene.uses_bvh())
        // The light's sphere is not tested: only the origin needs its offset.
        return {spawn_ray_to(hit, ls.p), {ls.unoccluding_sphere, -1}};
    if (ls.infinite) return {spawn_ray(hit, ls.wi), {}};
    if (ls.plane_distance > 0.f) {
        // Short of the plane by a relative margin far above the origin's offset.
        Ray shadow = spawn_ray(hit, ls.wi);
        shadow.t_max = ls.plane_distance * (1.f - 1e-4f);
        return {shadow, {}, ls.past_planes};
    }
    if (ls.planar && !scene.uses_bvh())
        // A quad's own triangles are not tested: only the origin needs its offset, and the ray
        // stops short of the light's plane by 1e-4 of its length, so those triangles could not
        // stop it anyway (skipping them changes no verdict and saves their exact tests and
        // the target's offset, a large share of a quad light's next-event estimation).
        return {spawn_ray_to(hit, ls.p), {-1, light}};
    return {spawn_ray_between(hit.p, hit.p_err, hit.n, ls.p, ls.p_err, ls.n), {}};
}

/// One light other than points and spots, chosen by `choices`, with its shadow ray (and the
/// light's own shapes the ray may skip).
struct AreaLightRay {
    Ray shadow;
    ShadowSkip skip;
    bool past_planes;
    SampledSpectrum f_cos, L;
    Vec3 wi;
    float pdf_light;  ///< solid angle, the light's choice included
};

/// kTextured: the scene has textures, and a light with an emission texture gives the
/// texture's radiance at the sampled point. nullopt when the sample cannot contribute.
template <bool kTextured>
[[gnu::always_inline]] inline std::optional<AreaLightRay> area_light_ray(
    const Scene& scene, const NeeLightChoice& choices, const Bsdf& bsdf, const Hit& hit,
    const LightSampleContext& ctx, const Vec3& wo, const SampledWavelengths& lambda, float u_light, float u1,
    float u2) {
    float choice = 0.f;
    int triangle = -1;
    const int index = choices.sample(ctx, u_light, choice, triangle);
    if (index < 0) return std::nullopt;
    std::optional<LightSample> ls{std::in_place};
    if (!light_sample_li_on(scene.lights[index], triangle, ctx, lambda, u1, u2, *ls)) return std::nullopt;
    if constexpr (kTextured)
        if (scene.light_textured(index)) ls->L = scene.light_point_emission(index, ls->p, ls->triangle, lambda);
    const SampledSpectrum f_cos = bsdf_eval(bsdf, wo, ls->wi, hit.ns, lambda, TransportMode::radiance);
    if (f_cos.is_zero()) return std::nullopt;
    const ShadowRay shadow = shadow_ray_to(scene, hit, *ls, index);
    return AreaLightRay{shadow.ray, shadow.skip, shadow.past_planes, f_cos, ls->L, ls->wi, choice * ls->pdf};
}

/// What the sample adds through a clear shadow ray, weighted against BSDF sampling by the
/// power heuristic (Veach 1997, §9.2) when `mis`.
[[gnu::always_inline]] inline SampledSpectrum area_light_contribution(const AreaLightRay& r, const Bsdf& bsdf,
                                                                      const Hit& hit, const Vec3& wo,
                                                                      const SampledWavelengths& lambda, bool mis) {
    if (!mis) return r.f_cos * r.L / r.pdf_light;
    const float pdf_bsdf = bsdf_pdf(bsdf, wo, r.wi, hit.ns, lambda.lambda[0]);
    return r.f_cos * r.L * (power_heuristic(r.pdf_light, pdf_bsdf) / r.pdf_light);
}

/// MIS weight of emission that BSDF sampling found along `wi` from `prev` (light `index`,
/// reached at `hit`, or escaped when hit is null) against sampling that light directly.
[[gnu::noinline]] inline float emission_weight(const Scene& scene, const NeeLightChoice& choices, int index,
                                               const LightSampleContext& prev, float pdf_bsdf, const Vec3& wi,
                                               const Hit* hit) {
    const float choice = choices.probability(prev, index, hit);
    if (choice == 0.f) return 1.f;  // a light that next-event estimation never samples
    return power_heuristic(pdf_bsdf, choice * light_pdf_li(scene.lights[index], prev, wi, hit));
}

}  // namespace spt

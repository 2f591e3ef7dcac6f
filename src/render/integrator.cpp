// The path loop. State carried between bounces: throughput beta, the accumulated radiance L,
// eta_scale (so roulette ignores the radiance scaling of refraction) and what the MIS weight
// of emission found by the next bounce needs: the BSDF density of its direction and the
// vertex it left from.
#include "render/integrator.h"

#include "core/sample_dimensions.h"
#include "core/sobol_sampler.h"
#include "model/bsdfs/bsdf.h"
#include "render/caustic_nee.h"
#include "render/reflection_nee.h"
#include "render/direct_light.h"
#include "render/light_context.h"
#include "render/mis.h"

namespace spt {

namespace {

/// Direct light from every point and spot light through one shadow ray each (delta lights:
/// no MIS).
/// Out of line: scenes without point lights never call it, and inlined it changes the
/// register allocation of the whole path loop (about 3 % more instructions per path).
[[gnu::noinline]] SampledSpectrum sample_point_lights(const Scene& scene, const Bsdf& bsdf, const Hit& hit,
                                                      const Vec3& wo, const SampledWavelengths& lambda, float time,
                                                      PathStats& stats) {
    SampledSpectrum Ld(0.f);
    for (int i : scene.point_light_indices) {
        const PointLight& light = *std::get_if<PointLight>(&scene.lights[i]);
        const Vec3 position = light.position_at(time);
        const Vec3 to_light = position - hit.p;
        const float dist2 = length_squared(to_light);
        if (!(dist2 > 0.f)) continue;  // light exactly on the surface: no defined direction
        const Vec3 wi = to_light / std::sqrt(dist2);
        const SampledSpectrum f_cos = bsdf_eval(bsdf, wo, wi, hit.ns, lambda, TransportMode::radiance);
        if (f_cos.is_zero()) continue;
        ++stats.rays;
        if (scene.occluded(spawn_ray_to(hit, position), {}, time)) continue;
        Ld += f_cos * light.intensity.sample(lambda) / dist2;
    }
    for (int i : scene.spot_light_indices) {
        const std::optional<LightSample> ls = std::get_if<SpotLight>(&scene.lights[i])->sample_li(
            {hit.p, hit.p_err, hit.n, hit.ns, false}, lambda);
        if (!ls) continue;
        const SampledSpectrum f_cos = bsdf_eval(bsdf, wo, ls->wi, hit.ns, lambda, TransportMode::radiance);
        if (f_cos.is_zero()) continue;
        ++stats.rays;
        if (scene.occluded(spawn_ray_to(hit, ls->p), {}, time)) continue;
        Ld += f_cos * ls->L;
    }
    return Ld;
}

/// Direct light from one of the other lights, chosen by power, through one shadow ray,
/// weighted against BSDF sampling by the power heuristic (Veach 1997, §9.2). Flattened (all
/// its callees inlined into it, the shadow ray's offsets above all): out of line, they took
/// 13 % of the time per path on cornell-sphere; the path loop, which calls it, stays small.
/// kTextured: the scene has textures, and a light with an emission texture gives the
/// texture's radiance at the sampled point.
template <bool kTextured>
[[gnu::noinline, gnu::flatten]] SampledSpectrum sample_area_light(
    const Scene& scene, const LightDistribution& choices, const Bsdf& bsdf, const Hit& hit,
    const LightSampleContext& ctx, const Vec3& wo, const SampledWavelengths& lambda, float time, float u_light,
    float u1, float u2, bool mis, PathStats& stats) {
    float choice = 0.f;
    const int index = choices.sample(u_light, choice);
    // A plane light writes its sample in place (PlaneLight::sample_li); the others return it.
    LightSample plane_sample;
    std::optional<LightSample> other_sample;
    LightSample* ls = &plane_sample;
    if (const PlaneLight* plane = std::get_if<PlaneLight>(&scene.lights[index])) {
        if (!plane->sample_li(ctx, lambda, u1, u2, plane_sample)) return SampledSpectrum(0.f);
    } else {
        other_sample = light_sample_li(scene.lights[index], ctx, lambda, u1, u2);
        if (!other_sample) return SampledSpectrum(0.f);
        ls = &*other_sample;
    }
    if constexpr (kTextured)
        if (scene.light_textured(index)) ls->L = scene.light_point_emission(index, ls->p, ls->triangle, lambda);
    const SampledSpectrum f_cos = bsdf_eval(bsdf, wo, ls->wi, hit.ns, lambda, TransportMode::radiance);
    if (f_cos.is_zero()) return SampledSpectrum(0.f);
    ++stats.rays;
    const ShadowRay shadow = shadow_ray_to(scene, hit, *ls, index);
    if (shadow_blocked(scene, shadow, time)) return SampledSpectrum(0.f);
    const float pdf_light = choice * ls->pdf;
    if (!mis) return f_cos * ls->L / pdf_light;
    const float pdf_bsdf = bsdf_pdf(bsdf, wo, ls->wi, hit.ns, lambda.lambda[0]);
    return f_cos * ls->L * (power_heuristic(pdf_light, pdf_bsdf) / pdf_light);
}

struct NoScratch {};

/// The path loop. kTextured (scenes with textures only): materials with textures take their
/// BSDF from the scene at each hit, and emitters their radiance; without, this is the loop
/// of before, unchanged. kCaustic (scenes with Effects::caustic_spheres, light sampling mis):
/// specular next-event estimation through glass spheres and the MIS weight of the emission
/// it competes with (render/caustic_nee.h); without, the loop of before. Sampler: Rng (independent numbers, drawn in sequence) or
/// SobolSampler (each number from its dimension of core/sample_dimensions.h; for Rng the
/// seek_dimension calls are no-ops and the loop is the one of before).
template <bool kTextured, bool kCaustic, class Sampler>
[[gnu::always_inline]] inline SampledSpectrum path_loop(const Scene& scene, const IntegratorSettings& settings,
                                                        Ray ray, float time, SampledWavelengths& lambda,
                                                        Sampler& rng, PathStats& stats) {
    // Where a textured material's BSDF is made at each hit (kept across bounces: no allocation).
    [[maybe_unused]] std::conditional_t<kTextured, Bsdf, NoScratch> scratch;
    SampledSpectrum L(0.f), beta(1.f);
    float eta_scale = 1.f;
    const bool point_nee = scene.effects.point_lights;
    // Lights other than points are sampled only when the scene has them: scenes without
    // them draw no random numbers for it and take the loop of before.
    const LightDistribution& choices =
        settings.sample_planes ? scene.area_light_choice_with_planes : scene.area_light_choice;
    const bool area_nee = settings.light_sampling != LightSampling::bsdf && !choices.empty();
    // Emission found by BSDF sampling where a light could also have been sampled: weighted
    // by MIS after a non-delta bounce (the state below); from the camera or after a delta
    // bounce no light sample could have found it (weight 1).
    bool mis_emission = false;
    float prev_pdf = 0.f;
    LightSampleContext prev_ctx;
    [[maybe_unused]] std::conditional_t<kCaustic, CausticChainState, NoScratch> chain;
    for (int depth = 0;; ++depth) {
        // ---- Find the next vertex; escaping rays see the environment ----
        ++stats.rays;
        const std::optional<Hit> hit = scene.intersect(ray, time);
        if (!hit) {
            if (const EnvironmentLight* env = scene.environment()) {
                const float w = mis_emission ? emission_weight(scene, choices, scene.environment_index, prev_ctx,
                                                               prev_pdf, ray.d, nullptr)
                                             : 1.f;
                L += beta * env->Le.sample(lambda) * w;
            }
            break;
        }
        const Material& mat = scene.materials[hit->material];
        const Vec3 wo = -ray.d;

        // ---- Emission found by the path ----
        if (hit->light >= 0) {
            float w =
                mis_emission ? emission_weight(scene, choices, hit->light, prev_ctx, prev_pdf, ray.d, &*hit) : 1.f;
            if constexpr (kCaustic) {
                if (chain.stage == CausticChainState::out)
                    w = caustic_emission_weight(scene, chain, *hit, hit->light, settings.caustic_nee_bug);
                else if (chain.stage == CausticChainState::reflected)
                    w = reflection_emission_weight(scene, chain, *hit, hit->light, lambda, settings.caustic_nee_bug);
            }
            if constexpr (kTextured) L += beta * scene.emitted_textured(*hit, lambda) * w;
            else L += beta * scene.emitted(*hit, lambda) * w;
        }
        if (!mat.reflects() || depth == settings.max_depth) break;
        const Bsdf* bsdf_at_hit = &mat.bsdf;
        if constexpr (kTextured)
            if (mat.textured) bsdf_at_hit = &scene.textured_bsdf(*hit, scratch);
        const Bsdf& bsdf = *bsdf_at_hit;

        // ---- Next-event estimation at vertices with a non-delta lobe: every point light,
        // and one other light chosen by power ----
        const bool non_delta = mat.has_non_delta();
        if (point_nee && non_delta) L += beta * sample_point_lights(scene, bsdf, *hit, wo, lambda, time, stats);
        LightSampleContext ctx;
        if (area_nee && non_delta) {
            ctx = light_context(*hit, mat, wo);
            seek_dimension(rng, dims::bounce(depth, dims::kLightChoice));
            const float ul = rng.uniform(), ul1 = rng.uniform(), ul2 = rng.uniform();
            L += beta * sample_area_light<kTextured>(scene, choices, bsdf, *hit, ctx, wo, lambda, time, ul, ul1, ul2,
                                          settings.light_sampling == LightSampling::mis, stats);
        }
        // ---- Specular next-event estimation through a glass sphere and off a reflecting
        // one, where BSDF sampling could reach the same path before max_depth (the two
        // refractions are bounces depth + 1 and depth + 2, the reflection depth + 1) ----
        [[maybe_unused]] bool caustic_here = false;
        [[maybe_unused]] bool terminated_at_x = false;
        if constexpr (kCaustic) {
            const bool unbounded = settings.max_depth == IntegratorSettings::kUnbounded;
            caustic_here = non_delta && (unbounded || depth + 1 < settings.max_depth);
            if (caustic_here) {
                // One chain per vertex: refraction with probability refraction_nee_share,
                // else reflection (its first number picks the family, then the sphere).
                seek_dimension(rng, dims::kCausticNee);
                const float us = rng.uniform(), ul = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
                const float share = scene.refraction_nee_share;
                if (us < share) {
                    if (unbounded || depth + 2 < settings.max_depth)
                        L += beta * sample_caustic_nee(scene, bsdf, *hit, wo, lambda, time, us / share, ul, u1, u2,
                                                       settings.caustic_nee_bug, stats);
                } else {
                    L += beta * sample_reflection_nee(scene, bsdf, *hit, wo, lambda, time,
                                                      (us - share) / (1.f - share), ul, u1, u2,
                                                      settings.caustic_nee_bug, stats);
                }
            }
            terminated_at_x = lambda.secondary_terminated();
        }

        // ---- Continue the path ----
        seek_dimension(rng, dims::bounce(depth, dims::kBsdfLobe));
        const float u_lobe = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
        const std::optional<BsdfSample> bs =
            bsdf_sample(bsdf, wo, hit->ns, lambda, u_lobe, u1, u2, TransportMode::radiance);
        if (!bs) break;
        beta *= bs->weight;
        eta_scale *= bs->eta_scale;
        if constexpr (kCaustic) {
            // Where the sampled path stands on a chain x → in → out → emitter or x → reflect
            // → emitter. (A chain the depth leaves no room for cannot reach its emitter.)
            const bool refracted = bs->is_delta() && bs->flags.has(BsdfFlags::transmission);
            const bool reflected = bs->is_delta() && !bs->flags.has(BsdfFlags::transmission);
            if (!bs->is_delta() && caustic_here) {
                chain.stage = CausticChainState::left_x;
                chain.x = hit->p, chain.wx = bs->wi, chain.pdf_x = bs->pdf;
                chain.terminated_at_x = terminated_at_x;
            } else if (chain.stage == CausticChainState::left_x && reflected && dot(wo, hit->n) > 0.f &&
                       (chain.sphere = CausticChainState::reflecting_sphere_at(scene, *hit)) >= 0) {
                chain.stage = CausticChainState::reflected;
            } else if (chain.stage == CausticChainState::left_x && refracted && dot(wo, hit->n) > 0.f &&
                       (chain.sphere = CausticChainState::caustic_sphere_at(scene, *hit)) >= 0) {
                chain.stage = CausticChainState::inside;
            } else if (chain.stage == CausticChainState::inside && refracted && dot(wo, hit->n) < 0.f &&
                       CausticChainState::caustic_sphere_at(scene, *hit) == chain.sphere) {
                chain.stage = CausticChainState::out;
            } else {
                chain.stage = CausticChainState::none;
            }
        }
        ray = spawn_ray(*hit, bs->wi);
        if (area_nee) {
            mis_emission = !bs->is_delta() && settings.light_sampling == LightSampling::mis;
            prev_pdf = bs->pdf;
            prev_ctx = ctx;
            // Light sampling alone: emission that BSDF sampling finds after a non-delta
            // bounce is left to the light samples (weight 0), except from lights they never choose.
            if (settings.light_sampling == LightSampling::light && !bs->is_delta()) {
                mis_emission = true;
                prev_pdf = 0.f;
            }
        }

        // ---- Russian roulette: survive with probability ~ throughput, at most 0.95 so that
        // lossless paths (mirrors, albedo 1) still end ----
        if (settings.roulette && depth + 1 >= settings.roulette_depth) {
            const float survive = std::min(0.95f, beta.max_value() * eta_scale);
            seek_dimension(rng, dims::bounce(depth, dims::kRoulette));
            if (!(rng.uniform() < survive)) break;
            beta /= survive;
        }
    }
    return L;
}

template <class Sampler>
[[gnu::noinline]] SampledSpectrum textured_path(const Scene& scene, const IntegratorSettings& settings, Ray ray,
                                                float time, SampledWavelengths& lambda, Sampler& rng,
                                                PathStats& stats) {
    if (scene.effects.caustic_spheres && settings.caustic_nee && settings.light_sampling == LightSampling::mis)
        return path_loop<true, true>(scene, settings, ray, time, lambda, rng, stats);
    return path_loop<true, false>(scene, settings, ray, time, lambda, rng, stats);
}

/// Scenes with glass spheres that specular next-event estimation sees through, out of line
/// like the textured loop: every other scene keeps the loop of before.
template <class Sampler>
[[gnu::noinline]] SampledSpectrum caustic_path(const Scene& scene, const IntegratorSettings& settings, Ray ray,
                                               float time, SampledWavelengths& lambda, Sampler& rng,
                                               PathStats& stats) {
    return path_loop<false, true>(scene, settings, ray, time, lambda, rng, stats);
}

}  // namespace

// Inlined into the renderer's sample loop at link time (LTO builds): the ray, wavelengths and
// random state then stay in registers instead of passing through memory, and the loop is
// optimised together with its caller (5 % of the time per path). Defining it in the header
// instead gives worse code. Not `inline`, hence GCC's warning, which is expected here.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wattributes"
[[gnu::always_inline]] SampledSpectrum trace_path(const Scene& scene, const IntegratorSettings& settings, Ray ray,
                                                  float time, SampledWavelengths& lambda, Rng& rng, PathStats& stats) {
    // Textured scenes take their own instance of the loop, out of line.
    if (scene.effects.textures) [[unlikely]] return textured_path(scene, settings, ray, time, lambda, rng, stats);
    if (scene.effects.caustic_spheres && settings.caustic_nee && settings.light_sampling == LightSampling::mis)
        [[unlikely]] return caustic_path(scene, settings, ray, time, lambda, rng, stats);
    return path_loop<false, false>(scene, settings, ray, time, lambda, rng, stats);
}
#pragma GCC diagnostic pop

// Out of line: the independent sampler's loop above keeps its inlining and registers.
[[gnu::noinline]] SampledSpectrum trace_path(const Scene& scene, const IntegratorSettings& settings, Ray ray,
                                             float time, SampledWavelengths& lambda, SobolSampler& sampler,
                                             PathStats& stats) {
    if (scene.effects.textures) [[unlikely]] return textured_path(scene, settings, ray, time, lambda, sampler, stats);
    if (scene.effects.caustic_spheres && settings.caustic_nee && settings.light_sampling == LightSampling::mis)
        [[unlikely]] return caustic_path(scene, settings, ray, time, lambda, sampler, stats);
    return path_loop<false, false>(scene, settings, ray, time, lambda, sampler, stats);
}

}  // namespace spt

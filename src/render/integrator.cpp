// The path loop. State carried between bounces: throughput beta, the accumulated radiance L,
// eta_scale (so roulette ignores the radiance scaling of refraction) and what the MIS weight
// of emission found by the next bounce needs: the BSDF density of its direction and the
// vertex it left from.
#include "render/integrator.h"

#include "core/sample_dimensions.h"
#include "core/sobol_sampler.h"
#include "model/bsdfs/bsdf.h"
#include "model/fluorescence.h"
#include "render/direct_light.h"
#include "render/guiding/guide_recorder.h"
#include "render/guiding/guided_bounce.h"
#include "render/light_context.h"
#include "render/mis.h"
#include "render/path_vertex.h"
#include "render/sphere_chain_nee.h"

namespace spt {

namespace {

/// Direct light from every delta-position light (point, spot) through one shadow ray each
/// (no MIS: no other strategy finds them).
/// Out of line: scenes without point lights never call it, and inlined it changes the
/// register allocation of the whole path loop (about 3 % more instructions per path).
[[gnu::noinline]] SampledSpectrum sample_point_lights(const Scene& scene, const Bsdf& bsdf, const Hit& hit,
                                                      const Vec3& wo, const SampledWavelengths& lambda, float time,
                                                      PathStats& stats) {
    SampledSpectrum Ld(0.f);
    // Intensity I_max·falloff along the way out, over r² (a point light's falloff is the
    // constant 1: its test and product fold away).
    auto add = [&](int i) {
        visit_light_of<kDeltaPositionLights>(scene.lights[i], [&](const auto& light) {
            const Vec3 position = light.position_at(time);
            const Vec3 to_light = position - hit.p;
            const float dist2 = length_squared(to_light);
            if (!(dist2 > 0.f)) return;  // light exactly on the surface: no defined direction
            const Vec3 wi = to_light / std::sqrt(dist2);
            const float falloff = light.falloff(-wi);
            if (falloff == 0.f) return;
            const SampledSpectrum f_cos = bsdf_eval(bsdf, wo, wi, hit.ns, lambda, TransportMode::radiance);
            if (f_cos.is_zero()) return;
            ++stats.rays;
            if (scene.occluded(spawn_ray_to(hit, position), {}, time)) return;
            Ld += f_cos * (light.I_max(lambda) * falloff) / dist2;
        });
    };
    for (int i : scene.point_light_indices) add(i);
    for (int i : scene.spot_light_indices) add(i);
    return Ld;
}

/// Direct light from one of the other lights, chosen by `choices`, through one shadow ray,
/// weighted against BSDF sampling by the power heuristic (Veach 1997, §9.2). Flattened (all
/// its callees inlined into it, the shadow ray's offsets above all: as calls they cost a
/// large share of the time per path); itself out of line, so the path loop stays small.
/// kTextured: the scene has textures, and a light with an emission texture gives the
/// texture's radiance at the sampled point. kGuided: the vertex continues by guided sampling
/// (render/guiding/guided_bounce.h), whose mixture density `guide` gives the weight.
template <bool kTextured, bool kGuided = false>
[[gnu::noinline, gnu::flatten]] SampledSpectrum sample_area_light(
    const Scene& scene, const NeeLightChoice& choices, const Bsdf& bsdf, const Hit& hit,
    const LightSampleContext& ctx, const Vec3& wo, const SampledWavelengths& lambda, float time, float u_light,
    float u1, float u2, bool mis, PathStats& stats, [[maybe_unused]] const VertexGuide* guide = nullptr,
    [[maybe_unused]] GuidingBug guiding_bug = GuidingBug::none) {
    float choice = 0.f;
    int triangle = -1;
    const int index = choices.sample(ctx, u_light, choice, triangle);
    if (index < 0) return SampledSpectrum(0.f);
    LightSample ls;
    if (!light_sample_li_on(scene.lights[index], triangle, ctx, lambda, u1, u2, ls)) return SampledSpectrum(0.f);
    if constexpr (kTextured)
        if (scene.light_textured(index)) ls.L = scene.light_point_emission(index, ls.p, ls.triangle, lambda);
    const SampledSpectrum f_cos = bsdf_eval(bsdf, wo, ls.wi, hit.ns, lambda, TransportMode::radiance);
    if (f_cos.is_zero()) return SampledSpectrum(0.f);
    ++stats.rays;
    const ShadowRay shadow = shadow_ray_to(scene, hit, ls, index);
    if (shadow_blocked(scene, shadow, time)) return SampledSpectrum(0.f);
    const float pdf_light = choice * ls.pdf;
    if (!mis) return f_cos * ls.L / pdf_light;
    float pdf_bsdf = bsdf_pdf(bsdf, wo, ls.wi, hit.ns, lambda.lambda[0]);
    if constexpr (kGuided)
        if (guiding_bug == GuidingBug::none) pdf_bsdf = guide->mixture_pdf(ls.wi, pdf_bsdf);
    return f_cos * ls.L * (power_heuristic(pdf_light, pdf_bsdf) / pdf_light);
}

struct NoScratch {};

/// The path loop, one bounce per iteration. kTextured (scenes with textures): materials
/// with textures take their BSDF from the scene at each hit, and emitters their radiance.
/// kCaustic (scenes with Effects::caustic_spheres, light sampling mis): the specular chains
/// through and off spheres as a second next-event strategy (render/sphere_chain_nee.h).
/// Sampler: Rng (independent numbers, drawn in sequence; seek_dimension is a no-op) or
/// SobolSampler (each number from its dimension of core/sample_dimensions.h). kFluorescent
/// (scenes with Effects::fluorescence): fluorescent vertices reflect or re-emit
/// (model/fluorescence.h), which changes the path's wavelengths; the film's are restored at
/// the end. kGuided (path guiding, render/guiding/): vertices with a non-delta lobe sample
/// the mixture of the learned field and the BSDF where the field has learnt something, and
/// training samples record what they find into it (render/guiding/guide_recorder.h). Each
/// flag off compiles its code away, so the scenes without it pay nothing for it.
template <bool kTextured, bool kCaustic, bool kFluorescent, bool kGuided, class Sampler>
[[gnu::always_inline]] inline SampledSpectrum path_loop(const Scene& scene, const IntegratorSettings& settings,
                                                        Ray ray, float time, SampledWavelengths& lambda,
                                                        Sampler& rng, PathStats& stats,
                                                        [[maybe_unused]] const PathGuide& guide = {}) {
    // Where a textured material's BSDF is made at each hit (kept across bounces: no allocation).
    [[maybe_unused]] std::conditional_t<kTextured, Bsdf, NoScratch> scratch;
    SampledSpectrum L(0.f), beta(1.f);
    float eta_scale = 1.f;
    const bool point_nee = scene.effects.point_lights;
    // Lights other than points are sampled only when the scene has them: scenes without
    // them draw no random numbers for it.
    const NeeLightChoice choices(scene, settings);
    const bool area_nee = settings.light_sampling != LightSampling::bsdf && !choices.empty();
    EmissionMis mis;
    [[maybe_unused]] std::conditional_t<kCaustic, SphereChainNee, NoScratch> chains;
    [[maybe_unused]] const std::array<float, kLambdaCount> film_lambda = lambda.lambda;
    // Guiding: the radiance the training records see (emission unweighted), and its vertices.
    [[maybe_unused]] std::conditional_t<kGuided, SampledSpectrum, NoScratch> guide_radiance;
    [[maybe_unused]] std::conditional_t<kGuided, GuideRecorder, NoScratch> recorder;
    if constexpr (kGuided) guide_radiance = SampledSpectrum(0.f);
    for (int depth = 0;; ++depth) {
        // ---- Find the next vertex; escaping rays see the infinite lights ----
        ++stats.rays;
        const std::optional<Hit> hit = scene.intersect(ray, time);
        if (!hit) {
            for (int i : scene.infinite_light_indices) {
                const float w = mis.weight(scene, choices, i, ray.d, nullptr);
                const SampledSpectrum arriving = beta * light_arriving(scene.lights[i], ray.d, lambda);
                L += arriving * w;
                if constexpr (kGuided) guide_radiance += arriving;
            }
            break;
        }
        const Material& mat = scene.materials[hit->material];
        const Vec3 wo = -ray.d;

        // ---- Emission found by the path, weighted against the strategies that sample it ----
        if (hit->light >= 0) {
            float w = mis.weight(scene, choices, hit->light, ray.d, &*hit);
            if constexpr (kCaustic)
                w = chains.emission_weight(scene, *hit, hit->light, lambda, settings.caustic_nee_bug, w);
            const SampledSpectrum emitted = beta * scene.emitted<kTextured>(*hit, wo, lambda);
            L += emitted * w;
            if constexpr (kGuided) guide_radiance += emitted;
        }
        if (!mat.reflects() || depth == settings.max_depth) break;
        const Bsdf* bsdf_at_hit = &mat.bsdf;
        if constexpr (kTextured)
            if (mat.textured) bsdf_at_hit = &scene.textured_bsdf(*hit, scratch);
        const Bsdf& bsdf = *bsdf_at_hit;

        // ---- Next-event estimation at vertices with a non-delta lobe: every point light,
        // one other light (render/nee_light_choice.h), and the specular chains ----
        const bool non_delta = mat.has_non_delta();
        // What the surface's own lobes carry: under a fluorescent dye layer, only what the
        // layer lets through (model/fluorescence.h).
        SampledSpectrum surface_beta = beta;
        if constexpr (kFluorescent)
            if (mat.fluorescence) surface_beta *= mat.fluorescence->passed(lambda);
        // The guide at this vertex (its distribution, if it has one, and its leaf for records).
        [[maybe_unused]] std::conditional_t<kGuided, VertexGuide, NoScratch> vertex_guide;
        if constexpr (kGuided)
            if (non_delta && (guide.sample || guide.record)) {
                const Vec3 side = dot(wo, hit->ns) >= 0.f ? hit->ns : -hit->ns;
                const bool reflects_only = !bsdf_flags(bsdf).has(BsdfFlags::transmission);
                vertex_guide = VertexGuide(*guide.field, hit->p, lambda.lambda[0], guide.sample, guide.record,
                                           reflects_only ? &side : nullptr);
            }
        [[maybe_unused]] const SampledSpectrum radiance_before = L;
        if (point_nee && non_delta) L += surface_beta * sample_point_lights(scene, bsdf, *hit, wo, lambda, time, stats);
        LightSampleContext ctx;
        if (area_nee && non_delta) {
            ctx = light_context(*hit, mat, wo);
            seek_dimension(rng, dims::bounce(depth, dims::kLightChoice));
            const float ul = rng.uniform(), ul1 = rng.uniform(), ul2 = rng.uniform();
            const bool with_mis = settings.light_sampling == LightSampling::mis;
            if constexpr (kGuided) {
                if (vertex_guide.usable())
                    L += surface_beta * sample_area_light<kTextured, true>(scene, choices, bsdf, *hit, ctx, wo, lambda,
                                                                           time, ul, ul1, ul2, with_mis, stats,
                                                                           &vertex_guide, settings.guiding_bug);
                else
                    L += surface_beta * sample_area_light<kTextured>(scene, choices, bsdf, *hit, ctx, wo, lambda, time,
                                                                     ul, ul1, ul2, with_mis, stats);
            } else {
                L += surface_beta * sample_area_light<kTextured>(scene, choices, bsdf, *hit, ctx, wo, lambda, time, ul,
                                                                 ul1, ul2, with_mis, stats);
            }
        }
        if constexpr (kGuided) guide_radiance += L - radiance_before;
        if constexpr (kCaustic)
            chains.sample(scene, settings, non_delta, depth, bsdf, *hit, wo, lambda, time, rng, beta, L, stats);

        // ---- A fluorescent vertex: next-event estimation of its re-emission too (at one
        // sampled excitation wavelength), then the path continues by reflection or by
        // re-emission (model/fluorescence.h) ----
        [[maybe_unused]] const Bsdf* scatter = &bsdf;
        if constexpr (kFluorescent)
            if (mat.fluorescence) {
                const Fluorescence& fl = *mat.fluorescence;
                seek_dimension(rng, dims::kFluorescence);
                if (point_nee || area_nee) {
                    const float u_lambda = rng.uniform(), ul = rng.uniform(), ul1 = rng.uniform(), ul2 = rng.uniform();
                    SampledWavelengths excited = lambda;
                    SampledSpectrum weight = beta;
                    if (reemit(fl, excited, weight, u_lambda, 1.f)) {
                        if (point_nee) L += weight * sample_point_lights(scene, fl.lobe(), *hit, wo, excited, time, stats);
                        if (area_nee)
                            L += weight * sample_area_light<kTextured>(scene, choices, fl.lobe(), *hit, ctx, wo, excited,
                                                                     time, ul, ul1, ul2,
                                                                     settings.light_sampling == LightSampling::mis, stats);
                    }
                }
                const float u_branch = rng.uniform(), u_lambda = rng.uniform();
                scatter = fluoresce_or_reflect(fl, bsdf, lambda, beta, u_branch, u_lambda);
                if (!scatter) break;
            }

        // ---- Continue the path: sample the BSDF, carry f·cos/p ----
        std::optional<BsdfSample> bs;
        [[maybe_unused]] std::conditional_t<kGuided, GuidedDensities, NoScratch> densities;
        if constexpr (kGuided) {
            if (vertex_guide.usable())
                bs = sample_guided_bounce(bsdf, *hit, wo, lambda, depth, vertex_guide, rng, densities);
            else bs = sample_bounce(bsdf, *hit, wo, lambda, depth, rng);
        } else {
            bs = sample_bounce(kFluorescent ? *scatter : bsdf, *hit, wo, lambda, depth, rng);
        }
        if (!bs) break;
        [[maybe_unused]] const SampledSpectrum beta_before = beta;
        beta *= bs->weight;
        if constexpr (kGuided)
            if (guide.record && !bs->is_delta())
                recorder.add(vertex_guide.leaf(), bs->wi, bs->pdf, beta, guide_radiance,
                             vertex_guide.usable() ? &densities : nullptr, beta_before);
        eta_scale *= bs->eta_scale;
        if constexpr (kCaustic) chains.follow(scene, *bs, *hit, wo);
        ray = spawn_ray(*hit, bs->wi);
        if (area_nee) mis.leave(*bs, settings.light_sampling, ctx);

        // ---- Russian roulette ----
        if (!survives_roulette(settings, depth, [&] { return beta.max_value() * eta_scale; }, beta, rng)) break;
    }
    if constexpr (kFluorescent) lambda.lambda = film_lambda;
    if constexpr (kGuided)
        if (guide.record) recorder.finish(*guide.field, guide_radiance, lambda);
    return L;
}

template <class Sampler>
[[gnu::noinline]] SampledSpectrum textured_path(const Scene& scene, const IntegratorSettings& settings, Ray ray,
                                                float time, SampledWavelengths& lambda, Sampler& rng,
                                                PathStats& stats) {
    if (scene.effects.caustic_spheres && settings.caustic_nee && settings.light_sampling == LightSampling::mis)
        return path_loop<true, true, false, false>(scene, settings, ray, time, lambda, rng, stats);
    return path_loop<true, false, false, false>(scene, settings, ray, time, lambda, rng, stats);
}

/// Scenes with spheres for the specular chains, out of line like the textured loop: the
/// loop of every other scene stays as small as it is.
template <class Sampler>
[[gnu::noinline]] SampledSpectrum caustic_path(const Scene& scene, const IntegratorSettings& settings, Ray ray,
                                               float time, SampledWavelengths& lambda, Sampler& rng,
                                               PathStats& stats) {
    return path_loop<false, true, false, false>(scene, settings, ray, time, lambda, rng, stats);
}

/// Scenes with fluorescent materials, out of line too; textured or not (the textured loop
/// reads each material's flag), without the specular chains (BSDF sampling and the other
/// lights' next-event estimation still find every light they would).
template <class Sampler>
[[gnu::noinline]] SampledSpectrum fluorescent_path(const Scene& scene, const IntegratorSettings& settings, Ray ray,
                                                   float time, SampledWavelengths& lambda, Sampler& rng,
                                                   PathStats& stats) {
    return path_loop<true, false, true, false>(scene, settings, ray, time, lambda, rng, stats);
}

/// Guided paths (render/guiding/), out of line too; textured or not, without the specular
/// chains (their MIS weights assume BSDF sampling) and fluorescence (the renderer refuses it).
template <class Sampler>
[[gnu::noinline]] SampledSpectrum guided_path(const Scene& scene, const IntegratorSettings& settings, Ray ray,
                                              float time, SampledWavelengths& lambda, Sampler& rng, PathStats& stats,
                                              const PathGuide& guide) {
    if (scene.effects.textures)
        return path_loop<true, false, false, true>(scene, settings, ray, time, lambda, rng, stats, guide);
    return path_loop<false, false, false, true>(scene, settings, ray, time, lambda, rng, stats, guide);
}

}  // namespace

SampledSpectrum trace_guided_path(const Scene& scene, const IntegratorSettings& settings, Ray ray, float time,
                                  SampledWavelengths& lambda, Rng& rng, PathStats& stats, const PathGuide& guide) {
    return guided_path(scene, settings, ray, time, lambda, rng, stats, guide);
}

SampledSpectrum trace_guided_path(const Scene& scene, const IntegratorSettings& settings, Ray ray, float time,
                                  SampledWavelengths& lambda, SobolSampler& sampler, PathStats& stats,
                                  const PathGuide& guide) {
    return guided_path(scene, settings, ray, time, lambda, sampler, stats, guide);
}

// Inlined into the renderer's sample loop at link time (LTO builds): the ray, wavelengths and
// random state then stay in registers instead of passing through memory, and the loop is
// optimised together with its caller (5 % of the time per path). Defining it in the header
// instead gives worse code. Not `inline`, hence GCC's warning, which is expected here.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wattributes"
[[gnu::always_inline]] SampledSpectrum trace_path(const Scene& scene, const IntegratorSettings& settings, Ray ray,
                                                  float time, SampledWavelengths& lambda, Rng& rng, PathStats& stats) {
    // Textured scenes and scenes with the specular chains take their own instances of the
    // loop, out of line.
    if (scene.effects.fluorescence) [[unlikely]] return fluorescent_path(scene, settings, ray, time, lambda, rng, stats);
    if (scene.effects.textures) [[unlikely]] return textured_path(scene, settings, ray, time, lambda, rng, stats);
    if (scene.effects.caustic_spheres && settings.caustic_nee && settings.light_sampling == LightSampling::mis)
        [[unlikely]] return caustic_path(scene, settings, ray, time, lambda, rng, stats);
    return path_loop<false, false, false, false>(scene, settings, ray, time, lambda, rng, stats);
}
#pragma GCC diagnostic pop

// Out of line: the independent sampler's loop above keeps its inlining and registers.
[[gnu::noinline]] SampledSpectrum trace_path(const Scene& scene, const IntegratorSettings& settings, Ray ray,
                                             float time, SampledWavelengths& lambda, SobolSampler& sampler,
                                             PathStats& stats) {
    if (scene.effects.fluorescence) [[unlikely]]
        return fluorescent_path(scene, settings, ray, time, lambda, sampler, stats);
    if (scene.effects.textures) [[unlikely]] return textured_path(scene, settings, ray, time, lambda, sampler, stats);
    if (scene.effects.caustic_spheres && settings.caustic_nee && settings.light_sampling == LightSampling::mis)
        [[unlikely]] return caustic_path(scene, settings, ray, time, lambda, sampler, stats);
    return path_loop<false, false, false, false>(scene, settings, ray, time, lambda, sampler, stats);
}

}  // namespace spt

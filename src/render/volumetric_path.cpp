// The volumetric path loop. State carried between events: throughput beta (f/p with the
// hero's densities), the spectral-MIS ratios r_u and r_l (volumetric_path.h), eta_scale
// for roulette, the current medium, and for the MIS weight of emission found by the next
// segment the point it left from.
#include "render/volumetric_path.h"

#include "model/bsdfs/bsdf.h"
#include "render/light_context.h"
#include "render/medium_tracking.h"
#include "render/path_vertex.h"
#include "render/surfaceless_crossing.h"

namespace spt {

namespace {

/// Mean of MIS ratios over the wavelengths the path still carries (only the hero after
/// a dispersive refraction or in one-wavelength mode: its ratio is then the whole estimate).
inline float mean_active(const SampledSpectrum& r, const SampledWavelengths& lambda) {
    return lambda.secondary_terminated() ? r[0] : r.average();
}

/// The value f (BSDF·|cos| or phase function) and solid-angle density of scattering into wi.
struct ScatterEval {
    SampledSpectrum f;
    float pdf = 0.f;
};

/// Where a path scatters: a surface point (n its geometric normal) or a point in a medium (n
/// zero: rays leave it without offset), and which medium a direction leads into.
struct ScatterPoint {
    Vec3 p, p_err, n;
    int medium_front;  ///< the medium on wo's side (the path's current medium)
    int medium_back;   ///< the medium behind the surface (the same in a medium)
    Vec3 wo;
    int medium_towards(const Vec3& wi) const {
        return dot(wi, n) * dot(wo, n) < 0.f ? medium_back : medium_front;
    }
};

/// Direct light at a scattering point: every delta light (point, spot) and one other light
/// chosen by NeeLightChoice, each through segment_transmittance; r_p is the path's r_u so far.
template <typename Eval>
SampledSpectrum direct_light(const Scene& scene, const IntegratorSettings& settings, const NeeLightChoice& choices,
                             bool area_nee, const ScatterPoint& sp, const LightSampleContext& ctx, const Eval& eval,
                             const SampledSpectrum& r_p, const SampledWavelengths& lambda, Rng& rng,
                             PathStats& stats) {
    SampledSpectrum Ld(0.f);
    auto delta_light = [&](int index) {
        const std::optional<LightSample> ls = light_sample_li(scene.lights[index], ctx, lambda, 0.f, 0.f);
        if (!ls) return;
        const ScatterEval se = eval(ls->wi);
        if (se.f.is_zero()) return;
        const Ray shadow = spawn_ray_between(sp.p, sp.p_err, sp.n, ls->p, Vec3{}, Vec3{});
        const SegmentTransmittance st =
            segment_transmittance(scene, shadow, sp.medium_towards(ls->wi), lambda, rng, stats);
        if (st.T.is_zero()) return;
        Ld += se.f * st.T * ls->L / mean_active(r_p * st.r_l, lambda);
    };
    for (int i : scene.point_light_indices) delta_light(i);
    for (int i : scene.spot_light_indices) delta_light(i);
    if (!area_nee) return Ld;

    float choice = 0.f;
    int triangle = -1;
    const int index = choices.sample(ctx, rng.uniform(), choice, triangle);
    const float u1 = rng.uniform(), u2 = rng.uniform();
    if (index < 0) return Ld;
    std::optional<LightSample> ls{std::in_place};
    if (!light_sample_li_on(scene.lights[index], triangle, ctx, lambda, u1, u2, *ls)) return Ld;
    if (scene.light_textured(index)) ls->L = scene.light_point_emission(index, ls->p, ls->triangle, lambda);
    const ScatterEval se = eval(ls->wi);
    if (se.f.is_zero()) return Ld;
    // The shadow ray, as the surface path tracer builds it (integrator.cpp).
    Ray shadow;
    const Vec3 o = offset_ray_origin(sp.p, sp.p_err, sp.n, ls->wi);
    if (ls->infinite) {
        shadow = {o, ls->wi, kInfinity};
    } else if (ls->plane_distance > 0.f) {
        shadow = {o, ls->wi, ls->plane_distance * (1.f - 1e-4f)};
    } else {
        shadow = spawn_ray_between(sp.p, sp.p_err, sp.n, ls->p, ls->p_err, ls->n);
    }
    const SegmentTransmittance st = segment_transmittance(scene, shadow, sp.medium_towards(ls->wi), lambda, rng, stats);
    if (st.T.is_zero()) return Ld;
    const SampledSpectrum r_l = r_p * st.r_l * (choice * ls->pdf);
    const SampledSpectrum r_u = r_p * st.r_u * se.pdf;
    const float mean = settings.light_sampling == LightSampling::mis ? mean_active(r_l + r_u, lambda)
                                                                     : mean_active(r_l, lambda);
    Ld += se.f * st.T * ls->L / mean;
    return Ld;
}

}  // namespace

SegmentTransmittance segment_transmittance(const Scene& scene, Ray ray, int medium, const SampledWavelengths& lambda,
                                           Rng& rng, PathStats& stats) {
    SegmentTransmittance r;
    for (int crossings = 0;; ++crossings) {
        ++stats.rays;
        const std::optional<Hit> hit = scene.intersect(ray);
        if ((hit && hit->material != scene.interface_material) || crossings == kMaxSurfacelessCrossings) {
            r.T = SampledSpectrum(0.f);
            return r;
        }
        if (medium >= 0) {
            const Medium& m = scene.media[static_cast<std::size_t>(medium)];
            const float t_end = hit ? hit->t : ray.t_max;
            if (m.is_uniform()) {
                SampledSpectrum sa, ss;
                m.coefficients(lambda, sa, ss);
                const SampledSpectrum T = majorant_transmittance(sa + ss, t_end);
                r.T *= T;
                r.r_u *= T;  // free flight passes with probability T; nothing was sampled here
            } else {
                const SampledSpectrum T_end =
                    track_majorant(m, ray, t_end, lambda, rng.uniform(), rng, [&](const MediumCollision& c) {
                        // Ratio tracking: the null-path weight over the hero's collision density.
                        const SampledSpectrum sigma_n = null_coefficient(c);
                        const float pdf = c.T_maj[0] * c.sigma_maj[0];
                        r.T *= c.T_maj * sigma_n / pdf;
                        r.r_l *= c.T_maj * c.sigma_maj / pdf;
                        r.r_u *= c.T_maj * sigma_n / pdf;
                        // Russian roulette once the estimate is small (it stays unbiased).
                        if ((r.T / mean_active(r.r_l + r.r_u, lambda)).max_value() < 0.05f) {
                            if (rng.uniform() < 0.75f) r.T = SampledSpectrum(0.f);
                            else r.T /= 0.25f;
                        }
                        return !r.T.is_zero();
                    });
                r.T *= T_end / T_end[0];
                r.r_l *= T_end / T_end[0];
                r.r_u *= T_end / T_end[0];
            }
            if (r.T.is_zero()) return r;
        }
        if (!hit) return r;
        medium = cross_surfaceless(scene, *hit, ray);
    }
}

// Out of line (also under LTO): the surface loop that calls it stays as it was.
[[gnu::noinline]] SampledSpectrum trace_volumetric_path(const Scene& scene, const IntegratorSettings& settings,
                                                        Ray ray, SampledWavelengths& lambda, Rng& rng,
                                                        PathStats& stats) {
    SampledSpectrum L(0.f), beta(1.f), r_u(1.f), r_l(1.f);
    float eta_scale = 1.f;
    int medium = scene.camera_medium;
    const NeeLightChoice choices(scene, settings);
    const bool area_nee = settings.light_sampling != LightSampling::bsdf && !choices.empty();
    const bool delta_nee = scene.effects.point_lights;
    // Emission found after a non-delta scattering event, which light sampling could also
    // have found from prev_ctx: weighted against it (r_l). From the camera or after a delta
    // bounce: r_u alone.
    bool mis_emission = false;
    LightSampleContext prev_ctx;
    int depth = 0, crossings = 0;

    // Emission Le arriving along the ray from light `index` (reached at `hit`, or escaped).
    auto add_emission = [&](int index, const SampledSpectrum& Le, const Hit* hit) {
        if (!mis_emission) {
            L += beta * Le / mean_active(r_u, lambda);
            return;
        }
        const float choice = choices.probability(prev_ctx, index, hit);
        if (choice == 0.f) {  // a light that next-event estimation never samples
            L += beta * Le / mean_active(r_u, lambda);
        } else if (settings.light_sampling == LightSampling::mis) {
            const float p_l = choice * light_pdf_li(scene.lights[index], prev_ctx, ray.d, hit);
            L += beta * Le / mean_active(r_u + r_l * p_l, lambda);
        }  // light sampling alone: left to the light samples
    };
    // Russian roulette after a scattering event (depth counts it already), on the
    // throughput the film will see.
    auto survives = [&]() {
        return survives_roulette(
            settings, depth - 1, [&] { return (beta / mean_active(r_u, lambda)).max_value() * eta_scale; }, beta,
            rng);
    };

    for (;;) {
        ++stats.rays;
        const std::optional<Hit> hit = scene.intersect(ray);

        // ---- The medium up to the hit: absorption, real scattering, or passing through ----
        if (medium >= 0) {
            const Medium& m = scene.media[static_cast<std::size_t>(medium)];
            const bool uniform = m.is_uniform();
            bool scattered = false, terminated = false;
            const SampledSpectrum T_end = track_majorant(
                m, ray, hit ? hit->t : kInfinity, lambda, rng.uniform(), rng, [&](const MediumCollision& c) {
                    // Choose the event with the hero's probabilities (a homogeneous medium's
                    // majorant is σt: no null collisions).
                    const float p_absorb = c.sigma_a[0] / c.sigma_maj[0];
                    const float p_scatter = uniform ? 1.f - p_absorb : c.sigma_s[0] / c.sigma_maj[0];
                    const float u_event = rng.uniform();
                    if (u_event < p_absorb) {
                        terminated = true;
                        return false;
                    }
                    if (u_event < p_absorb + p_scatter) {
                        // Real scattering: density T_maj·σs for each wavelength as hero.
                        const float pdf = c.T_maj[0] * c.sigma_s[0];
                        beta *= c.T_maj * c.sigma_s / pdf;
                        r_u *= c.T_maj * c.sigma_s / pdf;
                        if (depth == settings.max_depth || beta.is_zero()) {
                            terminated = true;
                            return false;
                        }
                        ++depth;
                        const Vec3 wo = -ray.d;
                        const ScatterPoint sp{c.p, Vec3{}, Vec3{}, medium, medium, wo};
                        const LightSampleContext ctx{c.p, Vec3{}, Vec3{}, Vec3{}, true};
                        if (delta_nee || area_nee) {
                            auto eval = [&](const Vec3& wi) {
                                const float p = m.phase.eval(wo, wi);
                                return ScatterEval{SampledSpectrum(p), p};
                            };
                            L += beta * direct_light(scene, settings, choices, area_nee, sp, ctx, eval, r_u, lambda,
                                                     rng, stats);
                        }
                        // The phase function is sampled exactly: beta is unchanged.
                        const float u1 = rng.uniform(), u2 = rng.uniform();
                        const Vec3 wi = m.phase.sample(wo, u1, u2);
                        r_l = r_u / m.phase.eval(wo, wi);
                        prev_ctx = ctx;
                        mis_emission = area_nee;
                        ray = {c.p, wi, kInfinity};
                        scattered = true;
                        return false;
                    }
                    // Null collision: density T_maj·σn as hero for free flight, T_maj·σ_maj
                    // for the light strategy's ratio tracking.
                    const SampledSpectrum sigma_n = null_coefficient(c);
                    const float pdf = c.T_maj[0] * sigma_n[0];
                    if (!(pdf > 0.f)) {
                        terminated = true;
                        return false;
                    }
                    beta *= c.T_maj * sigma_n / pdf;
                    r_u *= c.T_maj * sigma_n / pdf;
                    r_l *= c.T_maj * c.sigma_maj / pdf;
                    return !beta.is_zero() && !r_u.is_zero();
                });
            if (terminated || beta.is_zero()) break;
            if (scattered) {
                if (!survives()) break;
                continue;
            }
            // Passed without a real collision: probability T_maj[0] for the hero.
            beta *= T_end / T_end[0];
            r_u *= T_end / T_end[0];
            // The light strategy's homogeneous transmittance is exact (not sampled).
            r_l *= (uniform ? SampledSpectrum(1.f) : T_end) / T_end[0];
        }

        // ---- Escaped: the infinite lights ----
        if (!hit) {
            for (int i : scene.infinite_light_indices) add_emission(i, light_arriving(scene.lights[i], ray.d, lambda), nullptr);
            break;
        }
        // ---- A shape without a surface: straight on, into the medium behind it ----
        if (hit->material == scene.interface_material) {
            if (++crossings == kMaxSurfacelessCrossings) break;
            medium = cross_surfaceless(scene, *hit, ray);
            continue;
        }
        crossings = 0;
        const Material& mat = scene.materials[hit->material];
        const Vec3 wo = -ray.d;
        if (hit->light >= 0) add_emission(hit->light, scene.emitted<true>(*hit, wo, lambda), &*hit);
        if (!mat.reflects() || depth == settings.max_depth) break;
        ++depth;
        const Bsdf& bsdf = scene.bsdf_at(*hit);

        // ---- Next-event estimation at vertices with a non-delta lobe ----
        const MediumInterface sides = scene.medium_interface(hit->prim);
        const ScatterPoint sp{hit->p, hit->p_err, hit->n, medium, sides.after(hit->n, -wo), wo};
        const LightSampleContext ctx = light_context(*hit, mat, wo);
        if (mat.has_non_delta() && (delta_nee || area_nee)) {
            auto eval = [&](const Vec3& wi) {
                return ScatterEval{bsdf_eval(bsdf, wo, wi, hit->ns, lambda, TransportMode::radiance),
                                   bsdf_pdf(bsdf, wo, wi, hit->ns, lambda.lambda[0])};
            };
            L += beta * direct_light(scene, settings, choices, area_nee, sp, ctx, eval, r_u, lambda, rng, stats);
        }

        // ---- Continue the path; a refraction changes the medium ----
        const std::optional<BsdfSample> bs = sample_bounce(bsdf, *hit, wo, lambda, depth - 1, rng);
        if (!bs) break;
        beta *= bs->weight;
        eta_scale *= bs->eta_scale;
        mis_emission = area_nee && !bs->is_delta();
        if (mis_emission) {
            r_l = r_u / bs->pdf;
            prev_ctx = ctx;
        }
        medium = sp.medium_towards(bs->wi);
        ray = spawn_ray(*hit, bs->wi);
        if (!survives()) break;
    }
    return L;
}

}  // namespace spt

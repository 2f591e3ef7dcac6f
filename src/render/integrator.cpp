// The path loop. State carried between bounces: throughput beta, the accumulated radiance L
// and eta_scale (so roulette ignores the radiance scaling of refraction).
#include "render/integrator.h"

#include "render/bsdf.h"

namespace spt {

namespace {

/// Direct light from every point light through one shadow ray each (delta lights: no MIS).
/// Out of line: scenes without point lights never call it, and inlined it changes the
/// register allocation of the whole path loop (about 3 % more instructions per path).
[[gnu::noinline]] SampledSpectrum sample_point_lights(const Scene& scene, const Material& mat, const Hit& hit,
                                    const Vec3& wo, const SampledWavelengths& lambda,
                                    PathStats& stats) {
    SampledSpectrum Ld(0.f);
    for (const PointLight& light : scene.point_lights) {
        const Vec3 to_light = light.position - hit.p;
        const float dist2 = length_squared(to_light);
        if (!(dist2 > 0.f)) continue;  // light exactly on the surface: no defined direction
        const Vec3 wi = to_light / std::sqrt(dist2);
        const SampledSpectrum f_cos = eval_diffuse_cos(mat, wo, wi, hit.n, lambda);
        if (f_cos.is_zero()) continue;
        ++stats.rays;
        if (scene.occluded(spawn_ray_to(hit, light.position))) continue;
        Ld += f_cos * light.intensity.sample(lambda) / dist2;
    }
    return Ld;
}

}  // namespace

// Inlined into the renderer's sample loop at link time (LTO builds): the ray, wavelengths and
// random state then stay in registers instead of passing through memory, and the loop is
// optimised together with its caller (5 % of the time per path). Defining it in the header
// instead gives worse code. Not `inline`, hence GCC's warning, which is expected here.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wattributes"
[[gnu::always_inline]] SampledSpectrum trace_path(const Scene& scene, const IntegratorSettings& settings, Ray ray,
                           SampledWavelengths& lambda, Rng& rng, PathStats& stats) {
    SampledSpectrum L(0.f), beta(1.f);
    float eta_scale = 1.f;
    const bool nee = scene.effects.point_lights;
    for (int depth = 0;; ++depth) {
        // ---- Find the next vertex; escaping rays see the environment ----
        ++stats.rays;
        const std::optional<Hit> hit = scene.intersect(ray);
        if (!hit) {
            if (scene.effects.background) L += beta * scene.background.sample(lambda);
            break;
        }
        const Material& mat = scene.materials[hit->material];
        const Vec3 wo = -ray.d;

        // ---- Emission found by the path (area lights have no light sampling: no MIS) ----
        if (mat.is_emissive()) L += beta * mat.emission.sample(lambda);
        if (!mat.reflects() || depth == settings.max_depth) break;

        // ---- Next-event estimation at vertices with a non-specular lobe ----
        if (nee && mat.has_diffuse()) L += beta * sample_point_lights(scene, mat, *hit, wo, lambda, stats);

        // ---- Continue the path ----
        const float u_lobe = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
        const std::optional<BsdfSample> bs = sample_bsdf(mat, wo, hit->n, lambda, u_lobe, u1, u2);
        if (!bs) break;
        beta *= bs->weight;
        eta_scale *= bs->eta_scale;
        ray = spawn_ray(*hit, bs->wi);

        // ---- Russian roulette: survive with probability ~ throughput, at most 0.95 so that
        // lossless paths (mirrors, albedo 1) still end ----
        if (settings.roulette && depth + 1 >= settings.roulette_depth) {
            const float survive = std::min(0.95f, beta.max_value() * eta_scale);
            if (!(rng.uniform() < survive)) break;
            beta /= survive;
        }
    }
    return L;
}
#pragma GCC diagnostic pop

}  // namespace spt

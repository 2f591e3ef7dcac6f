// Free flight and transmittance through homogeneous media for bdpt (see bdpt_media.h).
#include "render/bdpt_media.h"

#include "render/medium_tracking.h"
#include "render/surfaceless_crossing.h"

namespace spt {

bool is_chromatic(const SampledSpectrum& sigma_t, const SampledWavelengths& lambda) {
    if (lambda.secondary_terminated()) return false;
    for (int i = 1; i < kLambdaCount; ++i)
        if (sigma_t[i] != sigma_t[0]) return true;
    return false;
}

FreeFlight free_flight(const Scene& scene, Ray ray, int medium, const SampledWavelengths& lambda, Rng& rng,
                       PathStats& stats) {
    FreeFlight f;
    for (int crossings = 0;; ++crossings) {
        ++stats.rays;
        f.hit = scene.intersect(ray);
        f.medium = medium;
        if (medium >= 0) {
            const Medium& m = scene.media[static_cast<std::size_t>(medium)];
            SampledSpectrum sa, ss;
            m.coefficients(lambda, sa, ss);
            const SampledSpectrum st = sa + ss;
            const float t_end = f.hit ? f.hit->t : ray.t_max;
            f.chromatic |= t_end > 0.f && is_chromatic(st, lambda);
            const float t = st[0] > 0.f ? -std::log1p(-rng.uniform()) / st[0] : kInfinity;
            if (t < t_end) {
                const SampledSpectrum T = majorant_transmittance(st, t);
                f.weight *= ss * T / (st[0] * T[0]);
                f.T_hero *= T[0];
                f.sigma_t_hero = st[0];
                f.scattered = true;
                f.p = ray.o + ray.d * t;
                f.hit.reset();
                return f;
            }
            const SampledSpectrum T = majorant_transmittance(st, t_end);
            if (!(T[0] > 0.f)) {  // an infinite segment: nothing passes
                f.weight = SampledSpectrum(0.f);
                f.hit.reset();
                return f;
            }
            f.weight *= T / T[0];
            f.T_hero *= T[0];
        }
        if (!f.hit || f.hit->material != scene.interface_material) return f;
        if (crossings == kMaxSurfacelessCrossings) {
            f.hit.reset();
            f.weight = SampledSpectrum(0.f);
            return f;
        }
        medium = cross_surfaceless(scene, *f.hit, ray);
    }
}

Transmittance connection_transmittance(const Scene& scene, Ray ray, int medium, const SampledWavelengths& lambda,
                                       PathStats& stats) {
    Transmittance r;
    for (int crossings = 0;; ++crossings) {
        ++stats.rays;
        const std::optional<Hit> hit = scene.intersect(ray);
        if ((hit && hit->material != scene.interface_material) || crossings == kMaxSurfacelessCrossings) {
            r.T = SampledSpectrum(0.f);
            return r;
        }
        if (medium >= 0) {
            SampledSpectrum sa, ss;
            scene.media[static_cast<std::size_t>(medium)].coefficients(lambda, sa, ss);
            const float t_end = hit ? hit->t : ray.t_max;
            r.chromatic |= t_end > 0.f && is_chromatic(sa + ss, lambda);
            r.T *= majorant_transmittance(sa + ss, t_end);
        }
        if (!hit) return r;
        medium = cross_surfaceless(scene, *hit, ray);
    }
}

int medium_at(const Scene& scene, const Vec3& eye, const Vec3& p, PathStats& stats) {
    int medium = scene.camera_medium;
    const Vec3 d = p - eye;
    const float dist = length(d);
    if (!(dist > 0.f)) return medium;
    Ray ray{eye, d / dist, dist};
    for (int crossings = 0; crossings < kMaxSurfacelessCrossings; ++crossings) {
        ++stats.rays;
        const std::optional<Hit> hit = scene.intersect(ray);
        if (!hit) break;
        // Only shapes without a surface bound media; a surface in the way (opaque or glass)
        // may stand in a medium without naming it as its exterior (then vacuum).
        const bool surfaceless = hit->material == scene.interface_material;
        const int behind = cross_surfaceless(scene, *hit, ray);
        if (surfaceless) medium = behind;
    }
    return medium;
}

}  // namespace spt

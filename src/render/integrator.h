// Unidirectional path tracing (Kajiya) with Russian roulette and next-event estimation: every
// point light at each vertex with a non-delta lobe, and one other light (emitting shapes,
// emitting planes, infinite lights) chosen by power or by a light BVH (render/nee_light_choice.h), combined with BSDF sampling by multiple
// importance sampling (power heuristic).
#pragma once
#include <cstdint>
#include <optional>
#include <string_view>

#include "core/rng.h"
#include "core/sobol_sampler.h"
#include "render/integrator_kind.h"
#include "scene/scene.h"
#include "spectral/sampled.h"

namespace spt {

/// Planted bugs of specular next-event estimation, for its unbiasedness tests only (the tests
/// must catch each): the BSDF side's MIS weight dropped (1), or the Jacobian's cos θ_y, or
/// (reflection chain) the Fresnel reflectance taken from the inside of the ball (1/η).
enum class CausticNeeBug : std::uint8_t { none, no_bsdf_side_weight, no_cos_y, wrong_reflectance };

/// A planted bug of path guiding, for its tests only: next-event estimation weighted against
/// the BSDF's density instead of the guided mixture's (render/guiding/guided_bounce.h).
enum class GuidingBug : std::uint8_t { none, nee_weight_without_guide };

struct IntegratorSettings {
    static constexpr int kUnbounded = -1;
    IntegratorKind kind = IntegratorKind::path;
    int max_depth = kUnbounded;  ///< scattering events allowed; kUnbounded relies on roulette
    bool roulette = true;
    int roulette_depth = 3;      ///< first bounce at which roulette may end a path
    LightSampling light_sampling = LightSampling::mis;
    /// How next-event estimation chooses its light (integrator_kind.h).
    LightSelection light_selection = LightSelection::power;
    /// Next-event estimation to emitting infinite planes too (path, volumetric path and
    /// wavefront; bdpt and vcm never sample planes: they cannot start light subpaths). On by
    /// default: the sampler of what the other planes leave open (model/lights/plane_light.h,
    /// plane_visibility.h) costs more per path than BSDF sampling alone but lowers the error
    /// of a room lit by its ceiling several times over, a higher efficiency
    /// (validation/results/benchmark.txt).
    bool sample_planes = true;
    /// 4: the hero wavelength set (default); 1: the hero alone, for measuring what the
    /// companions save (the film weights stay unbiased either way).
    int wavelengths_per_path = kLambdaCount;
    /// vcm: merging radius of the first pass in scene units; 0 lets default_merge_radius
    /// (vertex_merging.h) choose it. Pass k uses r·(k + 1)^(−1/8) (progressive photon
    /// mapping with α = 3/4: the bias vanishes as passes accumulate).
    float merge_radius = 0.f;
    /// bdpt, for tests: only the strategies with this many light vertices (s) or camera
    /// vertices (t), each with weight 1 (−1: every strategy, weighted by MIS). s = 0, s = 1
    /// and t = 1 each estimate the whole image on their own (but the emitter seen directly,
    /// s = 0 and t = 2, which is kept in every class), so a strategy that is wrong alone shows.
    int bdpt_only_s = -1, bdpt_only_t = -1;
    /// path with light_sampling mis: specular next-event estimation through smooth glass
    /// spheres (render/caustic_nee.h) and off spheres with a delta reflection lobe
    /// (render/reflection_nee.h) in scenes that have them (Effects::caustic_spheres).
    bool caustic_nee = true;
    CausticNeeBug caustic_nee_bug = CausticNeeBug::none;  ///< tests only
    GuidingBug guiding_bug = GuidingBug::none;            ///< tests only
};

struct PathStats {
    std::uint64_t rays = 0;  ///< every ray cast: camera, bounce and shadow rays
};

/// Radiance arriving along `ray` at the path's wavelengths (may terminate the companions),
/// the scene as it stands at shutter time `time` (every ray of the path sees that time), in a
/// scene without participating media (the renderer sends scenes with media to
/// trace_volumetric_path, render/volumetric_path.h).
SampledSpectrum trace_path(const Scene& scene, const IntegratorSettings& settings, Ray ray, float time,
                           SampledWavelengths& lambda, Rng& rng, PathStats& stats);
/// The same with the low-discrepancy sampler (core/sobol_sampler.h): the same estimate, each
/// random number from its dimension of core/sample_dimensions.h.
SampledSpectrum trace_path(const Scene& scene, const IntegratorSettings& settings, Ray ray, float time,
                           SampledWavelengths& lambda, SobolSampler& sampler, PathStats& stats);

struct PathGuide;  // render/guiding/guided_bounce.h

/// trace_path with path guiding (render/guiding/): vertices with a non-delta lobe sample the
/// mixture of `guide.field` and the BSDF, and, when guide.record, the path records into the
/// field what it found. Not for scenes with fluorescence; the specular chains are not used.
SampledSpectrum trace_guided_path(const Scene& scene, const IntegratorSettings& settings, Ray ray, float time,
                                  SampledWavelengths& lambda, Rng& rng, PathStats& stats, const PathGuide& guide);
SampledSpectrum trace_guided_path(const Scene& scene, const IntegratorSettings& settings, Ray ray, float time,
                                  SampledWavelengths& lambda, SobolSampler& sampler, PathStats& stats,
                                  const PathGuide& guide);

}  // namespace spt

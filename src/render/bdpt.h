// Bidirectional path tracing (Veach 1997; structure of pbrt-v3's BDPTIntegrator).
//
// Per sample: a light subpath (a light chosen ∝ power, importance transport: refraction has
// no 1/η² factor) and a camera subpath (radiance transport) are traced, then every pair of
// prefixes (s light vertices, t camera vertices) is connected, each weighted by the balance
// heuristic over all strategies that could have produced the same path. Vertex densities are
// kept in area measure (pdf_fwd along the subpath's own direction, pdf_rev the other way);
// specular scattering and point lights are flagged delta and skipped as connection points.
//
// Strategies: s = 0 (the camera path hits an emitter), s = 1 (connect to the light's origin),
// t = 1 (connect a light vertex to the pinhole, or to a lens point it samples for a thin
// lens: a splat on another pixel) and s, t ≥ 2.
// Emitting infinite planes cannot be sampled: they are reached by s = 0 only, with MIS weight
// 1 (see light_sampling.h). An infinite light is a light like the others, as a vertex at
// infinity (pbrt's infinite lights): a camera path that escapes ends on each (s = 0, each
// with its own weight), s = 1 connects towards the direction its light subpath sampled, and
// its subpaths start on a disk (light_sampling.h). Its densities are in solid angle at the
// vertex itself and planar (the disk's) for the next vertex, with no 1/r² conversion.
//
// Film estimator: pixel = Σ(camera-side contributions)/count + Σ(splats)/M, M = light paths
// per pixel (Film::add_light_paths); the camera importance We = 1/(A·cos⁴θ) of the whole
// image plane makes the splats of M·W·H light paths estimate M × each pixel's value.
//
// Wavelengths: one SampledWavelengths per sample, shared by both subpaths, each subpath with
// its own copy of the termination state. A strategy whose vertices include a dispersive
// refraction (on either side) keeps only the hero wavelength, weighted as after
// terminate_secondary(); the others keep all four. The MIS densities are those of the hero
// wavelength (lobe choice included), the same function for every strategy.
//
// Participating media (homogeneous; bdpt_media.h): scattering points in a medium are vertices
// of either subpath, and every connection carries the transmittance between its ends. Spot
// lights start light subpaths like point lights, with directions uniform over their cone.
#pragma once
#include <cstdint>
#include <vector>

#include "core/rng.h"
#include "render/bdpt_vertex.h"
#include "model/camera.h"
#include "render/integrator.h"
#include "render/light_sampling.h"
#include "render/photon_grid.h"
#include "spectral/cie.h"
#include "spectral/cie.h"

namespace spt {

/// A light-to-camera contribution for film pixel `pixel` (y·width + x), already in XYZ.
struct Splat {
    std::uint32_t pixel;
    float x, y, z;
};

struct BdptContext {
    const Scene& scene;
    const Camera& camera;
    const LightSampler& lights;
    const IntegratorSettings& settings;
    int width;  ///< film width, for splat pixel indices
    const Observer* observer = &Cie1931::get();  ///< the film's, for splats
};

/// Vertex merging (bidirectional path tracing with photon density estimation, Georgiev et al.
/// 2012 "VCM"): the light subpaths of a whole pass, traced before any camera subpath, and a
/// grid over their mergeable vertices (photons). A camera vertex merges with every photon
/// within the radius r; merging is one more strategy in the MIS sums, with a density
/// π r² × (light subpaths in the pass) times that of the connection it replaces (`eta`).
/// Every subpath of the pass uses the same wavelengths, so photons and camera paths agree.
/// Merging happens at every surface vertex with a non-delta lobe, glossy ones included (as
/// SmallVCM; no roughness threshold): the merge point's BSDF densities between the camera's
/// and the photon's directions enter the weights per merge, so where a sharp lobe makes
/// connections or BSDF sampling better the merge weighs little, and the kernel's blur with it.
struct MergeContext {
    /// A mergeable light vertex with what a merge needs of its subpath, so that merging reads
    /// one record (the grid keeps them in its own order, for locality).
    struct Photon {
        Vec3 p, n;             ///< position, geometric normal
        Vec3 wo;               ///< towards the previous vertex of its subpath
        SampledSpectrum beta;  ///< light subpath throughput arriving here
        /// The light side of the MIS sum of a merge here, per unit of the camera's area
        /// density of this point: light_connection + light_per_density·p, p the solid-angle
        /// density with which the merge point's BSDF samples wo from the camera's direction
        /// (known only per merge: Bdpt::merge).
        float light_connection = 0.f, light_per_density = 0.f;
        int s = 0;                ///< vertices of its light subpath up to and including it
        bool terminated = false;  ///< a dispersive refraction happened before it
    };
    const std::vector<BdptVertex>& vertices;       ///< the pass's light subpaths, one after another
    const std::vector<std::uint32_t>& path_begin;  ///< subpath i is [path_begin[i], path_begin[i + 1])
    const std::vector<Photon>& photons;            ///< grid slot j is photons[j]
    const PhotonGrid& grid;
    float eta;  ///< π r² × light subpaths in the pass
};

/// The photon of light subpath vertex path[s − 1] (s ≥ 3, a mergeable surface vertex whose
/// BdptVertex::mis_sum values are filled) for a pass with merging density `eta`.
MergeContext::Photon make_photon(const Scene& scene, const BdptVertex* path, int s, float eta);

/// Vertex merging, first phase: traces one light subpath at `lambda` (the pass's wavelengths),
/// appends its vertices to `out` and its light-to-camera (t = 1) contributions to `splats`,
/// weighted with merging among the strategies (`eta` as in MergeContext).
void trace_light_subpath(const BdptContext& ctx, const SampledWavelengths& lambda, float eta, Rng& rng,
                         PathStats& stats, std::vector<BdptVertex>& out, std::vector<Splat>& splats);

/// Vertex merging, second phase: the camera subpath for `ray`, connected to light subpath
/// `light_path` of the pass (every strategy with t ≥ 2) and merged with the photons around
/// each of its vertices. Returns what to add to the ray's pixel, like trace_bdpt.
SampledSpectrum trace_camera_subpath(const BdptContext& ctx, const MergeContext& merge,
                                     std::uint32_t light_path, const Ray& ray,
                                     const SampledWavelengths& lambda, Rng& rng, PathStats& stats);

/// One bidirectional sample for the camera ray `ray` (at wavelengths `lambda`, not modified) at
/// shutter time `time` (the light subpath and every connection share it).
/// Returns what to add to the ray's pixel with Film::add_sample(…, lambda) (strategies that
/// kept only the hero are folded into its channel) and appends the t = 1 splats.
SampledSpectrum trace_bdpt(const BdptContext& ctx, const Ray& ray, float time, const SampledWavelengths& lambda,
                           Rng& rng, PathStats& stats, std::vector<Splat>& splats);

}  // namespace spt

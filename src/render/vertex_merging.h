// The per-pass state of vertex merging (the vcm integrator, bdpt.h's MergeContext): the
// light subpaths traced by the pass's tasks, gathered in task order, their photons (the
// vertices where merging may happen) in a PhotonGrid, the pass's radius and wavelengths.
#pragma once
#include <cstdint>
#include <vector>

#include "render/bdpt.h"
#include "model/camera.h"
#include "render/renderer.h"

namespace spt {

/// What one task of the light phase produced: its subpaths one after another (ends[i] is
/// the end of its i-th subpath in `vertices`) and its light-to-camera splats.
struct LightSubpathBatch {
    std::vector<BdptVertex> vertices;
    std::vector<std::uint32_t> ends;
    std::vector<Splat> splats;

    /// Traces one more subpath (trace_light_subpath) and records where it ends.
    void trace(const BdptContext& ctx, const SampledWavelengths& lambda, float eta, Rng& rng, PathStats& stats) {
        trace_light_subpath(ctx, lambda, eta, rng, stats, vertices, splats);
        ends.push_back(static_cast<std::uint32_t>(vertices.size()));
    }
};

class MergePass {
public:
    /// Concatenates the batches (consumed) and indexes the photons: surface vertices from
    /// each subpath's second hit on (light index ≥ 2), on materials with a non-delta lobe.
    /// eta = π r² × the number of subpaths (the light phase already used it in its splats'
    /// weights).
    void build(std::vector<LightSubpathBatch>& batches, const Scene& scene, float radius, float eta);
    MergeContext context() const { return {m_vertices, m_begin, m_photons, m_grid, m_eta}; }
    std::size_t photon_count() const { return m_photons.size(); }
    const PhotonGrid& grid() const { return m_grid; }

private:
    std::vector<BdptVertex> m_vertices;
    std::vector<std::uint32_t> m_begin;
    std::vector<MergeContext::Photon> m_photons;
    PhotonGrid m_grid;
    float m_eta = 0.f;
};

/// First merging radius when none is given. Five pixel footprints at the median distance of
/// what the camera sees (rays through a 16×16 grid of pixels): the expected number of photons
/// per merge then does not depend on the resolution (N ∝ pixels, the disk ∝ 1/pixels); but at
/// most 1 % of the scene's bounding radius (tiny images would blur coarsely). Where
/// photons are dense that is more than merging needs and slow, so a pilot light phase (up to
/// 65536 light subpaths of their own stream) counts the photons within that radius around the
/// same camera hits; if the median count, scaled to a pass, exceeds kPhotonsPerMerge (16) the
/// radius shrinks to expect that many.
/// With nothing in view: 0.003 × the scene's bounding radius.
float default_merge_radius(const BdptContext& ctx, const RenderSettings& settings);

/// Radius of pass k (0-based) for a first radius r0: r0·(k + 1)^(−1/8).
float merge_radius(float r0, int pass);

/// Wavelengths shared by every subpath of pass k: the hero from a golden-ratio sequence over
/// passes, rotated by a seed-dependent offset (each pass's hero is uniform in u, so the
/// estimate stays unbiased; successive passes cover the spectrum evenly).
SampledWavelengths pass_wavelengths(std::uint64_t seed, int pass);

}  // namespace spt

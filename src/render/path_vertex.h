// The per-vertex steps of the path kernel that its three schedules share: the tile loop
// (integrator.cpp), the wavefront stages (wavefront.cpp) and the path through participating
// media (volumetric_path.cpp). Each is the physics of one phase of a bounce; the schedules
// differ only in where the path's state lives between phases and in how shadow rays are
// traced.
#pragma once
#include <algorithm>
#include <optional>

#include "core/sample_dimensions.h"
#include "core/sobol_sampler.h"
#include "model/bsdfs/bsdf.h"
#include "render/direct_light.h"
#include "render/integrator.h"

namespace spt {

/// What the MIS weight of emission found by the next bounce needs: whether it competes with
/// light sampling (after a non-delta bounce; from the camera or after a delta bounce no light
/// sample could have found it), the BSDF density of the direction and the vertex it left from.
struct EmissionMis {
    bool on = false;
    float prev_pdf = 0.f;
    LightSampleContext prev_ctx;

    /// The weight of emission from light `index` that BSDF sampling found along `wi` (at
    /// `hit`, or escaped when hit is null) against sampling that light directly.
    [[gnu::always_inline]] float weight(const Scene& scene, const NeeLightChoice& choices, int index,
                                        const Vec3& wi, const Hit* hit) const {
        return on ? emission_weight(scene, choices, index, prev_ctx, prev_pdf, wi, hit) : 1.f;
    }

    /// After the bounce `bs` from the vertex with light-sampling reference `ctx`.
    [[gnu::always_inline]] void leave(const BsdfSample& bs, LightSampling sampling, const LightSampleContext& ctx) {
        on = !bs.is_delta() && sampling == LightSampling::mis;
        prev_pdf = bs.pdf;
        prev_ctx = ctx;
        // Light sampling alone: emission that BSDF sampling finds after a non-delta bounce is
        // left to the light samples (weight 0), except from lights they never choose.
        if (sampling == LightSampling::light && !bs.is_delta()) {
            on = true;
            prev_pdf = 0.f;
        }
    }
};

/// The direction the path continues in from a surface vertex at bounce `depth`: the BSDF
/// sampled with its three numbers (lobe, then direction).
template <class Sampler>
[[gnu::always_inline]] inline std::optional<BsdfSample> sample_bounce(const Bsdf& bsdf, const Hit& hit, const Vec3& wo,
                                                                       SampledWavelengths& lambda, int depth,
                                                                       Sampler& rng) {
    seek_dimension(rng, dims::bounce(depth, dims::kBsdfLobe));
    const float u_lobe = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
    return bsdf_sample(bsdf, wo, hit.ns, lambda, u_lobe, u1, u2, TransportMode::radiance);
}

/// Russian roulette after bounce `depth`: the path survives with probability ~ its
/// throughput (`throughput()`, what the film will see, with eta_scale so that the radiance
/// scaling of refraction does not count), at most 0.95 so that lossless paths (mirrors,
/// albedo 1) still end; beta is divided by it. False when the path ends.
template <class Sampler, class Throughput>
[[gnu::always_inline]] inline bool survives_roulette(const IntegratorSettings& settings, int depth,
                                                     const Throughput& throughput, SampledSpectrum& beta,
                                                     Sampler& rng) {
    if (!settings.roulette || depth + 1 < settings.roulette_depth) return true;
    const float survive = std::min(0.95f, throughput());
    seek_dimension(rng, dims::bounce(depth, dims::kRoulette));
    if (!(rng.uniform() < survive)) return false;
    beta /= survive;
    return true;
}

}  // namespace spt

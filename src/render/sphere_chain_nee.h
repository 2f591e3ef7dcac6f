// Specular next-event estimation through and off spheres, as the path kernel asks for it:
// a light sample at a vertex (the refraction chain of render/caustic_nee.h or the reflection
// chain of render/reflection_nee.h, one per vertex), and the MIS weight of emission that BSDF
// sampling found at the end of such a chain, for which the strategy follows where the path
// stands on a chain x → in → out → emitter or x → reflect → emitter. Its tables are
// SphereChains (render/sphere_chains.h), prepared with the scene.
//
// A new next-event strategy plugs into the kernel (render/integrator.cpp) the same way: a
// per-path object that samples at a vertex, follows the BSDF samples, and overrides the
// light sampler's MIS weight for the emission it competes for.
#pragma once
#include "core/sample_dimensions.h"
#include "core/sobol_sampler.h"
#include "render/reflection_nee.h"

namespace spt {

struct SphereChainNee {
    CausticChainState chain;
    /// This vertex could sample a chain: BSDF sampling from it competes with the strategy.
    bool sampled_here = false;
    /// The wavelengths' state at this vertex before it sampled its direction.
    bool terminated_here = false;

    /// The strategy's light sample at vertex `hit` (depth `depth`), added to L with
    /// throughput beta. Only where BSDF sampling could reach the same path before max_depth
    /// (the two refractions are bounces depth + 1 and depth + 2, the reflection depth + 1).
    template <class Sampler>
    [[gnu::always_inline]] void sample(const Scene& scene, const IntegratorSettings& settings, bool non_delta,
                                       int depth, const Bsdf& bsdf, const Hit& hit, const Vec3& wo,
                                       const SampledWavelengths& lambda, float time, Sampler& rng,
                                       const SampledSpectrum& beta, SampledSpectrum& L, PathStats& stats) {
        const bool unbounded = settings.max_depth == IntegratorSettings::kUnbounded;
        sampled_here = non_delta && (unbounded || depth + 1 < settings.max_depth);
        if (sampled_here) {
            // One chain per vertex: refraction with probability refraction_share, else
            // reflection (its first number picks the family, then the sphere).
            seek_dimension(rng, dims::kCausticNee);
            const float us = rng.uniform(), ul = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
            const float share = scene.sphere_chains.refraction_share;
            if (us < share) {
                if (unbounded || depth + 2 < settings.max_depth)
                    L += beta * sample_caustic_nee(scene, bsdf, hit, wo, lambda, time, us / share, ul, u1, u2,
                                                   settings.caustic_nee_bug, stats);
            } else {
                L += beta * sample_reflection_nee(scene, bsdf, hit, wo, lambda, time, (us - share) / (1.f - share),
                                                  ul, u1, u2, settings.caustic_nee_bug, stats);
            }
        }
        terminated_here = lambda.secondary_terminated();
    }

    /// The MIS weight of emission from `light` found at `hit`: the strategy's own when the
    /// path arrived along a chain it samples, else `w` (the light sampler's).
    [[gnu::always_inline]] float emission_weight(const Scene& scene, const Hit& hit, int light,
                                                 const SampledWavelengths& lambda, CausticNeeBug bug, float w) const {
        if (chain.stage == CausticChainState::out) return caustic_emission_weight(scene, chain, hit, light, bug);
        if (chain.stage == CausticChainState::reflected)
            return reflection_emission_weight(scene, chain, hit, light, lambda, bug);
        return w;
    }

    /// Follows the BSDF sample `bs` taken at `hit`. (A chain the depth leaves no room for
    /// cannot reach its emitter.)
    [[gnu::always_inline]] void follow(const Scene& scene, const BsdfSample& bs, const Hit& hit, const Vec3& wo) {
        const bool refracted = bs.is_delta() && bs.flags.has(BsdfFlags::transmission);
        const bool reflected = bs.is_delta() && !bs.flags.has(BsdfFlags::transmission);
        if (!bs.is_delta() && sampled_here) {
            chain.stage = CausticChainState::left_x;
            chain.x = hit.p, chain.wx = bs.wi, chain.pdf_x = bs.pdf;
            chain.terminated_at_x = terminated_here;
        } else if (chain.stage == CausticChainState::left_x && reflected && dot(wo, hit.n) > 0.f &&
                   (chain.sphere = CausticChainState::reflecting_sphere_at(scene, hit)) >= 0) {
            chain.stage = CausticChainState::reflected;
        } else if (chain.stage == CausticChainState::left_x && refracted && dot(wo, hit.n) > 0.f &&
                   (chain.sphere = CausticChainState::caustic_sphere_at(scene, hit)) >= 0) {
            chain.stage = CausticChainState::inside;
        } else if (chain.stage == CausticChainState::inside && refracted && dot(wo, hit.n) < 0.f &&
                   CausticChainState::caustic_sphere_at(scene, hit) == chain.sphere) {
            chain.stage = CausticChainState::out;
        } else {
            chain.stage = CausticChainState::none;
        }
    }
};

}  // namespace spt

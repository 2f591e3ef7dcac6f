// The tables of specular next-event estimation through and off spheres (render/caustic_nee.h,
// render/reflection_nee.h, their choice between each other in render/sphere_chain_nee.h):
// which spheres each chain uses, the chain solver's node tables, which lights the chains
// sample and how often each chain is chosen. They belong to the strategy; the scene keeps
// one instance, prepared by Scene::finalize's strategy step (prepare below).
#pragma once
#include <memory>
#include <vector>

#include "model/lights/light_distribution.h"
#include "spectral/spectrum.h"

namespace spt {

struct Scene;
struct SphereChainNodes;  // geometry/sphere_caustics.h

/// A smooth, non-dispersive glass sphere that specular next-event estimation sees through
/// (render/caustic_nee.h): its material is clear glass (LobeMixBsdf with only kt and a
/// constant index, or a smooth DielectricBsdf without a film and with a constant index), it
/// does not emit and does not move.
struct CausticSphere {
    int sphere = -1;  ///< index in Scene::spheres
    float eta = 1.f;  ///< index inside relative to outside, > 1
    /// What each refraction multiplies the path by besides Fresnel (kt; 1 for a dielectric).
    Spectrum kt;
    std::shared_ptr<const SphereChainNodes> nodes;  ///< the chain solver's table for eta
};

/// A smooth sphere with a delta reflection lobe that specular next-event estimation reflects
/// light off (render/reflection_nee.h): its material is a LobeMixBsdf with a mirror lobe (ks)
/// or a transmission lobe of constant index (kt: Fresnel reflection), or a smooth
/// DielectricBsdf without a film and with a constant index; it is not textured, does not
/// emit and does not move. Reflectance along the chain: ks + kt·F(cos θ, eta); the BSDF
/// picks that reflection with probability (k̄s + k̄t·F)/(k̄d + k̄s + k̄t), k̄ the mean over the
/// live wavelengths (a DielectricBsdf is kd = ks = 0, kt = 1).
struct ReflectingSphere {
    int sphere = -1;  ///< index in Scene::spheres
    float eta = 1.f;  ///< index of the Fresnel lobe (unused when kt is zero)
    Spectrum kd, ks, kt;
    bool has_kd = false, has_kt = false;
};

struct SphereChains {
    /// The glass spheres the refraction chain sees through.
    std::vector<CausticSphere> caustic_spheres;
    /// The spheres the reflection chain reflects off (D → R → L), and its solver's table.
    std::vector<ReflectingSphere> reflecting_spheres;
    std::shared_ptr<const SphereChainNodes> reflection_nodes;
    /// The probability that a vertex samples the refraction chain rather than the reflection
    /// chain (1 without reflecting spheres, 0 without glass ones).
    float refraction_share = 1.f;
    /// The lights both chains sample by area (emitting spheres and quads without an emission
    /// texture), chosen by power.
    LightDistribution light_choice;

    /// True when the scene has spheres and lights for either chain.
    bool active() const { return !caustic_spheres.empty() || !reflecting_spheres.empty(); }

    /// The tables for `scene` (its materials, spheres and lights final): the one place that
    /// decides which spheres qualify. Empty in scenes with media (the volumetric path tracer
    /// does not use the strategy) and in scenes without a light the chains can sample.
    static SphereChains prepare(const Scene& scene);
};

}  // namespace spt

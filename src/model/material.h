// Surface material: a name (for messages) and a BSDF of the closed set (model/bsdfs/bsdf.h).
// A fluorescent material adds a re-radiation part (model/fluorescence.h).
// Emission is not a material property: an emitter is attached to the shape (Hit::light).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "model/bsdfs/bsdf.h"
#include "model/fluorescence.h"
#include "model/textures/texture_binding.h"

namespace spt {

/// The BSDF reads the surface's tangent at each hit (an anisotropic conductor).
inline bool needs_tangent(const Bsdf& bsdf) {
    const ConductorBsdf* c = std::get_if<ConductorBsdf>(&bsdf);
    return c && c->anisotropic();
}

struct Material {
    std::string name;
    Bsdf bsdf;
    BsdfFlags flags;  ///< bsdf_flags(bsdf), kept by Scene::add_material / finalize
    /// Some parameter is bound to a texture (`textures`), or the BSDF needs the surface's
    /// tangent (needs_tangent): the integrators then take the BSDF from Scene::textured_bsdf
    /// at each hit. One byte in the padding after `flags`.
    bool textured = false;

    /// Has a lobe at all (a pure emitter or a black surface ends paths).
    bool reflects() const { return !flags.is_black(); }
    bool has_non_delta() const { return flags.has(BsdfFlags::non_delta); }

    /// The bound parameters; `bsdf` holds each one's upper envelope over its texture (every
    /// bin's largest value), so the flags and the load-time checks (kd + ks + kt ≤ 1) hold
    /// at every point of the surface.
    std::vector<TextureBinding> textures;
    /// The re-radiation part of a fluorescent material (model/fluorescence.h); `bsdf` is its
    /// reflectance part. Null for every other material.
    std::shared_ptr<const Fluorescence> fluorescence;
};

}  // namespace spt

// Surface material: a name (for messages) and a BSDF of the closed set (model/bsdfs/bsdf.h).
// Emission is not a material property: an emitter is attached to the shape (Hit::light).
#pragma once
#include <string>

#include "model/bsdfs/bsdf.h"

namespace spt {

struct Material {
    std::string name;
    Bsdf bsdf;
    BsdfFlags flags;  ///< bsdf_flags(bsdf), kept by Scene::add_material / finalize

    /// Has a lobe at all (a pure emitter or a black surface ends paths).
    bool reflects() const { return !flags.is_black(); }
    bool has_non_delta() const { return flags.has(BsdfFlags::non_delta); }
};

}  // namespace spt

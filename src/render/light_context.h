// The reference point next-event estimation samples lights from.
#pragma once
#include "geometry/ray.h"
#include "model/lights/light_sample.h"
#include "model/material.h"

namespace spt {

/// The light-sampling reference at a hit: shading normal on wo's side, and whether light
/// from behind matters (a BSDF that transmits).
inline LightSampleContext light_context(const Hit& hit, const Material& mat, const Vec3& wo) {
    return {hit.p, hit.p_err, hit.n, face_forward(hit.ns, wo), mat.flags.has(BsdfFlags::transmission)};
}

}  // namespace spt

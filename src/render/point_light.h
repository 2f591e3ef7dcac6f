// Isotropic point light: radiant intensity I(λ) (W·sr⁻¹·nm⁻¹ up to scale); irradiance at
// distance r on a surface tilted by θ is I·cos θ / r².
#pragma once
#include "core/vec3.h"
#include "spectral/spectrum.h"

namespace spt {

struct PointLight {
    Vec3 position;
    Spectrum intensity;
};

}  // namespace spt

// Surface material: emission, and a reflectance made of three lobes, each a spectrum:
//   kd  Lambertian diffuse,
//   ks  perfect mirror (no Fresnel: a grey coat, as on the Cornell plastic sphere),
//   kt  smooth dielectric interface of index eta: Fresnel-weighted mirror reflection and
//       refraction, total internal reflection included (kt = 1 is clear glass).
// kd + ks + kt ≤ 1 at every wavelength (checked when the scene is built).
#pragma once
#include <string>

#include "spectral/spectrum.h"

namespace spt {

struct Material {
    std::string name;
    Spectrum kd, ks, kt;
    Spectrum eta;       ///< index of refraction inside relative to outside (used when kt > 0)
    Spectrum emission;  ///< radiance emitted from both sides

    bool has_diffuse() const { return !kd.is_zero(); }
    bool has_mirror() const { return !ks.is_zero(); }
    bool has_transmission() const { return !kt.is_zero(); }
    bool reflects() const { return has_diffuse() || has_mirror() || has_transmission(); }
    bool is_emissive() const { return !emission.is_zero(); }
    /// Index that varies with wavelength: refraction splits the hero wavelength set.
    bool is_dispersive() const { return has_transmission() && !eta.is_constant(); }
};

}  // namespace spt

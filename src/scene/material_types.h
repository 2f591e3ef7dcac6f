// Scene-file materials of the microfacet-era types (see scenes/README.md, "Materials"):
//   conductor   metal: "metal": "Au" | "eta" + "k" spectra; "roughness" (or "roughness_u" +
//               "roughness_v": anisotropic along the surface's dp/du); "film"
//   dielectric  glass interface: "ior" spectrum; "roughness"; "film"
//   plastic     diffuse base under a clear coat: "kd", "ior" (constant), "roughness"
//   thin_sheet  soap bubble: "thickness_nm", "ior"
// and the checks of their parameters for materials made in code.
#pragma once
#include <functional>
#include <string>

#include "model/bsdfs/bsdf.h"
#include "scene/spectrum_parser.h"

namespace spt {

/// Whether `type` names one of the types parsed here.
bool is_microfacet_material_type(const std::string& type);

/// Reads the float parameter `v` (at `key` of the material: "roughness", "thickness_nm",
/// "film thickness_nm") within [lo, hi] (lo excluded when lo_open); `what` names it in
/// messages. The loader's accepts {"texture": NAME} too: it records the binding under `key`
/// and returns the texture's largest value (the parameter's envelope, Material::textures).
using FloatParameter = std::function<float(const JsonValue& v, const std::string& key, const std::string& what,
                                           double lo, double hi, bool lo_open)>;

/// Reads the reflectance spectrum `v` at `key` of the material ("kd"). The loader's accepts
/// {"texture": NAME} too: it records the binding and returns the texture's envelope.
using ReflectanceParameter = std::function<Spectrum(const JsonValue& v, const char* key)>;

/// The BSDF of material `def` (an object with "type" = one of the types above; `what` names
/// it in messages), its float parameters read through `number` and its reflectances through
/// `reflectance`. Keys "emission" and "type" are allowed and left to the caller. Throws
/// LocatedError.
Bsdf parse_microfacet_material(const SpectrumParser& spectra, const JsonValue& def, const std::string& type,
                               const std::string& what, const FloatParameter& number,
                               const ReflectanceParameter& reflectance);

/// Checks the parameters of the types above (ranges at every wavelength); throws SceneError.
void validate_surface_model(const Bsdf& bsdf, const std::string& who);

}  // namespace spt

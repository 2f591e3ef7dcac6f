// The material types of scene descriptions (scenes/README.md, "Materials"), one row each in
// material_types(), each made from its parameters by its create function in
// material_types.cpp (keys, ranges, defaults and messages in one place):
//   diffuse     Lambertian: "kd"
//   lobes       diffuse + mirror + smooth transmission: "kd", "ks", "kt", "ior" (the default type)
//   conductor   metal: "metal": "Au" | "eta" + "k" spectra; "roughness" (or "roughness_u" +
//               "roughness_v": anisotropic along the surface's dp/du); "film"
//   dielectric  glass interface: "ior" spectrum; "roughness"; "film"
//   plastic     diffuse base under a clear coat: "kd", "ior" (constant), "roughness"
//   thin_sheet  soap bubble: "thickness_nm", "ior"
//   fluorescent a fluorescent dye layer over a surface: "dye" (a name or {"excitation",
//               "emission", "quantum_yield"}), "density", "quantum_yield"; "surface" (a
//               material of another type) or "base" (a diffuse surface's kd)
// and the checks of their parameters for materials made in code.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "model/bsdfs/bsdf.h"
#include "model/fluorescence.h"
#include "scene/spectrum_parser.h"

namespace spt {


/// Reads the float parameter `v` (at `key` of the material: "roughness", "thickness_nm",
/// "film thickness_nm") within [lo, hi] (lo excluded when lo_open); `what` names it in
/// messages. The loader's accepts {"texture": NAME} too: it records the binding under `key`
/// and returns the texture's largest value (the parameter's envelope, Material::textures).
using FloatParameter = std::function<float(const ParamValue& v, const std::string& key, const std::string& what,
                                           double lo, double hi, bool lo_open)>;

/// Reads the reflectance spectrum `v` at `key` of the material ("kd"). The loader's accepts
/// {"texture": NAME} too: it records the binding and returns the texture's envelope.
using ReflectanceParameter = std::function<Spectrum(const ParamValue& v, const char* key)>;

/// What a material's create function reads: its parameters `def` (the caller reads "type" and
/// "emission"; a key that neither reads is unknown), its name in messages (`what`: "material
/// \"m\""), the spectrum reader, and the readers of the parameters that may name a texture.
struct MaterialParams {
    const SpectrumParser& spectra;
    const ParamValue& def;
    const std::string& what;
    const FloatParameter& number;
    const ReflectanceParameter& reflectance;
    /// Where a fluorescent type puts its re-radiation part (Material::fluorescence); left
    /// untouched by the other types.
    std::shared_ptr<const Fluorescence>* fluorescence = nullptr;
};

/// A material type: its name in scene descriptions and the function that makes its BSDF from
/// its parameters (throws LocatedError).
struct MaterialType {
    const char* name;
    Bsdf (*create)(const MaterialParams& params);
};

/// Every material type, one row each, in the order messages list them.
const std::vector<MaterialType>& material_types();
/// The type called `name`, or nullptr.
const MaterialType* find_material_type(const std::string& name);

/// Checks the parameters of the types above (ranges at every wavelength); throws SceneError.
void validate_surface_model(const Bsdf& bsdf, const std::string& who);

}  // namespace spt

// Named fluorescent dyes and UV-A lamps: analytic band fits of published spectra, read from the
// embedded spectra/fluorescent_dyes.csv and spectra/uv_lamps.csv (each names its sources there).
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "spectral/spectrum_source.h"

namespace spt {

struct DyeInfo {
    std::string name;                   ///< "fluorescein", "rhodamine6g", "quinine", "stilbene"
    SpectrumSource excitation;          ///< relative absorption, peak 1
    SpectrumSource emission;            ///< relative photon spectrum per nm, peak 1
    double quantum_yield = 0;           ///< photons emitted per photon absorbed
};

/// The dye of this name (case ignored), or nullopt.
std::optional<DyeInfo> find_dye(std::string_view name);
/// The names find_dye knows, in a fixed order.
std::vector<std::string> dye_names();

/// The UV lamp of this name (case ignored: "led365", "blacklight"), relative spectral radiance
/// with peak 1, or nullopt.
std::optional<SpectrumSource> find_uv_lamp(std::string_view name);
std::vector<std::string> uv_lamp_names();

}  // namespace spt

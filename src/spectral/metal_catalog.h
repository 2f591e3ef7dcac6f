// Named metals: measured complex index η + ik of gold, silver, copper and aluminium, read from
// the embedded spectra/metal_*.csv (each names its source and range there).
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "spectral/spectrum_source.h"

namespace spt {

struct MetalInfo {
    std::string symbol;      ///< "Au", "Ag", "Cu", "Al"
    SpectrumSource eta, k;   ///< piecewise linear through the measured points
    std::string source;      ///< the table's first comment line
};

/// The metal with this chemical symbol (case ignored), or nullopt.
std::optional<MetalInfo> find_metal(std::string_view symbol);

/// The symbols find_metal knows, in a fixed order.
std::vector<std::string> metal_names();

}  // namespace spt

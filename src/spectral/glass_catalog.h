// Named dispersive materials (glasses, fused silica, diamond, water): index of refraction as a
// spectrum from Sellmeier or Cauchy coefficients, read from spectra/glasses.csv with its sources.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "spectral/spectrum_source.h"

namespace spt {

/// Fraunhofer lines of the Abbe number V_d (nm): helium d, hydrogen F and C.
inline constexpr double kLineD = 587.5618, kLineF = 486.1327, kLineC = 656.2725;

struct GlassInfo {
    std::string name;
    SpectrumSource ior;  ///< n(λ), exact (analytic, or a 0.5 nm table for four-term Sellmeier)
    double nd = 0, vd = 0;  ///< published n at the d line and Abbe number V_d
    std::string source;    ///< where the coefficients come from
};

/// Parses the glasses CSV format (see spectra/glasses.csv); `origin` names the text in error
/// messages. Throws std::runtime_error on malformed rows, unknown models or an index ≤ 1 at d.
std::vector<GlassInfo> parse_glass_catalog(std::string_view text, const std::string& origin);

/// The built-in catalogue, parsed once from the embedded spectra/glasses.csv.
const std::vector<GlassInfo>& glass_catalog();

/// Catalogue entry by name, ignoring case; nullopt when unknown.
std::optional<GlassInfo> find_glass(std::string_view name);

/// Names of the catalogue entries, in file order.
std::vector<std::string> glass_names();

/// Abbe number V_d = (n_d − 1)/(n_F − n_C) of an index spectrum.
double abbe_number(const SpectrumSource& ior);

}  // namespace spt

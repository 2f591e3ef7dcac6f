#include "spectral/dye_catalog.h"

#include "spectral/catalog_lookup.h"

namespace spt {

namespace {

/// Quantum yields of the dyes, as the CSV's header states them with their sources.
double quantum_yield(const std::string& name) {
    if (name == "fluorescein") return 0.925;
    if (name == "rhodamine6g") return 0.95;
    if (name == "quinine") return 0.546;
    return 0.80;  // stilbene: an assumed typical value (the CSV says so)
}

}  // namespace

std::vector<std::string> dye_names() { return {"fluorescein", "rhodamine6g", "quinine", "stilbene"}; }

std::optional<DyeInfo> find_dye(std::string_view name) {
    for (const std::string& n : dye_names()) {
        if (!same_ignoring_case(n, name)) continue;
        const SpectralTable& t = embedded_spectral_table("fluorescent_dyes.csv");
        return DyeInfo{n, column_spectrum(t, n + "_excitation"), column_spectrum(t, n + "_emission"), quantum_yield(n)};
    }
    return std::nullopt;
}

std::vector<std::string> uv_lamp_names() { return {"led365", "blacklight"}; }

std::optional<SpectrumSource> find_uv_lamp(std::string_view name) {
    for (const std::string& n : uv_lamp_names())
        if (same_ignoring_case(n, name)) return column_spectrum(embedded_spectral_table("uv_lamps.csv"), n);
    return std::nullopt;
}

}  // namespace spt

#include "spectral/dye_catalog.h"

#include <cctype>

#include "spectral/spectral_table.h"

namespace spt {

namespace {

SpectrumSource column_source(const SpectralTable& t, const std::string& column) {
    const std::vector<double>& values = t.column(column);
    std::vector<std::pair<double, double>> points;
    for (std::size_t i = 0; i < values.size(); ++i) points.emplace_back(t.wavelengths_nm[i], values[i]);
    return SpectrumSource::piecewise_linear(std::move(points));
}

bool same_ignoring_case(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
    return true;
}

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
        return DyeInfo{n, column_source(t, n + "_excitation"), column_source(t, n + "_emission"), quantum_yield(n)};
    }
    return std::nullopt;
}

std::vector<std::string> uv_lamp_names() { return {"led365", "blacklight"}; }

std::optional<SpectrumSource> find_uv_lamp(std::string_view name) {
    for (const std::string& n : uv_lamp_names())
        if (same_ignoring_case(n, name)) return column_source(embedded_spectral_table("uv_lamps.csv"), n);
    return std::nullopt;
}

}  // namespace spt

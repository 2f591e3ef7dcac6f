#include "spectral/metal_catalog.h"

#include <cctype>

#include "spectral/spectral_table.h"

namespace spt {

namespace {

SpectrumSource column_source(const SpectralTable& t, const char* column) {
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

}  // namespace

std::vector<std::string> metal_names() { return {"Au", "Ag", "Cu", "Al"}; }

std::optional<MetalInfo> find_metal(std::string_view symbol) {
    for (const std::string& name : metal_names()) {
        if (!same_ignoring_case(name, symbol)) continue;
        std::string file = "metal_" + name + ".csv";
        for (char& c : file) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        const SpectralTable& t = embedded_spectral_table(file);
        return MetalInfo{name, column_source(t, "eta"), column_source(t, "k"),
                         t.comments.empty() ? std::string() : t.comments.front()};
    }
    return std::nullopt;
}

}  // namespace spt

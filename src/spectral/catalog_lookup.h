// What the named-spectrum catalogs (metals, dyes, UV lamps, illuminants, ColorChecker patches)
// share: a table column read as a spectrum, and names matched without regard to case.
#pragma once
#include <cctype>
#include <string_view>
#include <utility>
#include <vector>

#include "spectral/spectral_table.h"
#include "spectral/spectrum_source.h"

namespace spt {

/// The column `name` of `t` times `scale`, linear between the table's wavelengths (throws
/// std::runtime_error when the column is absent).
inline SpectrumSource column_spectrum(const SpectralTable& t, std::string_view name, double scale = 1.0) {
    const std::vector<double>& values = t.column(name);
    std::vector<std::pair<double, double>> points;
    for (std::size_t i = 0; i < values.size(); ++i) points.emplace_back(t.wavelengths_nm[i], values[i] * scale);
    return SpectrumSource::piecewise_linear(std::move(points));
}

/// a == b, ASCII letters compared without case ("au" names gold).
inline bool same_ignoring_case(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
    return true;
}

}  // namespace spt

// Reader for the CSV data tables in spectra/ ('#' comment lines, a header, numeric rows).
#pragma once
#include <string>
#include <string_view>
#include <vector>

namespace spt {

struct SpectralTable {
    std::vector<std::string> comments;      ///< '#' lines without the '#', the first names the source
    std::vector<std::string> column_names;  ///< first is "wavelength_nm"
    std::vector<double> wavelengths_nm;
    std::vector<std::vector<double>> columns;  ///< one per column after the wavelength
    int header_line = 0;                       ///< line of the header in the text (messages)
    std::vector<int> line_numbers;             ///< line of each row in the text (messages)

    /// Values of the named column; throws std::runtime_error when absent.
    const std::vector<double>& column(std::string_view name) const;
};

/// Parses CSV text; `origin` names the file in error messages (throws std::runtime_error).
SpectralTable parse_spectral_table(std::string_view text, const std::string& origin);

/// A table compiled into the program, by file name in spectra/ (e.g. "cie_1931_2deg.csv").
const SpectralTable& embedded_spectral_table(const std::string& file_name);

}  // namespace spt

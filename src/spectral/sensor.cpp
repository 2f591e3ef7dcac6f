// Sensor tables: checked, then resampled onto the observer's 1-nm grid.
#include "spectral/sensor.h"

#include <cstdio>
#include <limits>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "spectral/spectral_table.h"

namespace spt {

namespace {

/// Byte column (from 1) of field `field` (from 0) of line `line` (from 1) of a CSV text.
int field_column(std::string_view text, int line, int field) {
    std::size_t start = 0;
    for (int l = 1; l < line; ++l) start = text.find('\n', start) + 1;
    std::size_t pos = start;
    for (int f = 0; f < field; ++f) pos = text.find(',', pos) + 1;
    return static_cast<int>(pos - start) + 1;
}

std::string format_nm(double lambda) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", lambda);
    return text;
}

}  // namespace

Observer parse_sensor(std::string_view text, const std::string& origin) {
    const SpectralTable table = parse_spectral_table(text, origin);
    auto fail = [&](std::size_t row, int field, const std::string& what) {
        const int line = table.line_numbers[row];
        throw std::runtime_error(origin + ":" + std::to_string(line) + ":" +
                                 std::to_string(field_column(text, line, field)) + ": " + what);
    };
    if (table.column_names != std::vector<std::string>{"wavelength_nm", "r", "g", "b"})
        throw std::runtime_error(origin + ":" + std::to_string(table.header_line) +
                                 ":1: expected the header 'wavelength_nm,r,g,b'");
    const std::vector<double>& l = table.wavelengths_nm;
    if (l.size() < 2) throw std::runtime_error(origin + ": expected at least two rows");
    for (std::size_t row = 0; row < l.size(); ++row) {
        if (!(l[row] >= kLambdaMin && l[row] <= kLambdaMax))  // NaN too
            fail(row, 0, "wavelength " + format_nm(l[row]) +
                             " nm is outside 360-830 nm, the range the film integrates over");
        for (int c = 0; c < 3; ++c) {
            const double v = table.columns[c][row];
            if (v < 0.0)
                fail(row, c + 1,
                     "sensitivity " + table.column_names[c + 1] + " is negative; expected >= 0");
            // The curves are held as floats: a larger value would become +Inf in every image.
            if (!(v <= std::numeric_limits<float>::max()))
                fail(row, c + 1,
                     "sensitivity " + table.column_names[c + 1] + " is " + format_nm(v) +
                         "; expected a finite number of at most " +
                         format_nm(std::numeric_limits<float>::max()) + " (the float range)");
        }
    }
    // Linear between rows, 0 outside them: the same curve colour-science's linear interpolation
    // gives on the data's own range.
    std::vector<Float4> rows;
    std::size_t seg = 0;
    for (int i = 0; i < Observer::kRows; ++i) {
        const double lambda = kLambdaMin + i;
        Float4 r{};
        if (lambda >= l.front() && lambda <= l.back()) {
            while (seg + 2 < l.size() && lambda > l[seg + 1]) ++seg;
            const double t = (lambda - l[seg]) / (l[seg + 1] - l[seg]);
            for (int c = 0; c < 3; ++c)
                r[c] = static_cast<float>((1.0 - t) * table.columns[c][seg] +
                                          t * table.columns[c][seg + 1]);
        }
        rows.push_back(r);
    }
    try {
        return Observer(origin, rows);
    } catch (const std::invalid_argument& e) {
        throw std::runtime_error(e.what());
    }
}

Observer load_sensor(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("--sensor: cannot read '" + path + "'");
    std::ostringstream text;
    text << in.rdbuf();
    return parse_sensor(text.str(), path);
}

}  // namespace spt

// CSV parsing for spectral tables, and a cache of the tables compiled into the program.
#include "spectral/spectral_table.h"

#include <charconv>
#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>

#include "io/embedded_files.h"

namespace spt {

namespace {

std::vector<std::string_view> split(std::string_view line, char sep) {
    std::vector<std::string_view> out;
    std::size_t start = 0;
    while (true) {
        const std::size_t end = line.find(sep, start);
        out.push_back(line.substr(start, end == std::string_view::npos ? end : end - start));
        if (end == std::string_view::npos) break;
        start = end + 1;
    }
    return out;
}

/// "origin:line:column" of a field (columns counted in bytes from 1).
std::string where(const std::string& origin, int line, std::string_view row,
                  std::string_view field) {
    return origin + ":" + std::to_string(line) + ":" +
           std::to_string(field.data() - row.data() + 1);
}

double parse_number(std::string_view s, const std::string& origin, int line, std::string_view row) {
    double v = 0;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(v))
        throw std::runtime_error(where(origin, line, row, s) + ": expected a number, got '" +
                                 std::string(s) + "'");
    return v;
}

}  // namespace

const std::vector<double>& SpectralTable::column(std::string_view name) const {
    for (std::size_t i = 1; i < column_names.size(); ++i)
        if (column_names[i] == name) return columns[i - 1];
    throw std::runtime_error("spectral table has no column '" + std::string(name) + "'");
}

SpectralTable parse_spectral_table(std::string_view text, const std::string& origin) {
    SpectralTable table;
    int line_no = 0;
    for (std::string_view line : split(text, '\n')) {
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        if (line.empty()) continue;
        if (line.front() == '#') {
            table.comments.emplace_back(line.substr(1));
            continue;
        }
        const auto fields = split(line, ',');
        if (table.column_names.empty()) {
            for (auto f : fields) table.column_names.emplace_back(f);
            table.header_line = line_no;
            if (table.column_names.size() < 2 || table.column_names[0] != "wavelength_nm")
                throw std::runtime_error(origin + ":" + std::to_string(line_no) +
                                         ":1: expected a header 'wavelength_nm,<columns>'");
            table.columns.resize(table.column_names.size() - 1);
            continue;
        }
        if (fields.size() != table.column_names.size())
            throw std::runtime_error(origin + ":" + std::to_string(line_no) + ":1: expected " +
                                     std::to_string(table.column_names.size()) + " fields, got " +
                                     std::to_string(fields.size()));
        const double lambda = parse_number(fields[0], origin, line_no, line);
        if (!table.wavelengths_nm.empty() && lambda <= table.wavelengths_nm.back())
            throw std::runtime_error(origin + ":" + std::to_string(line_no) +
                                     ":1: wavelengths must increase");
        table.wavelengths_nm.push_back(lambda);
        table.line_numbers.push_back(line_no);
        for (std::size_t i = 1; i < fields.size(); ++i)
            table.columns[i - 1].push_back(parse_number(fields[i], origin, line_no, line));
    }
    if (table.wavelengths_nm.empty())
        throw std::runtime_error(origin + ": no data rows");
    return table;
}

const SpectralTable& embedded_spectral_table(const std::string& file_name) {
    static std::mutex mutex;
    static std::map<std::string, SpectralTable> cache;
    const std::lock_guard lock(mutex);
    if (auto it = cache.find(file_name); it != cache.end()) return it->second;
    const EmbeddedFile* file = find_embedded("spectra/" + file_name);
    if (!file) throw std::runtime_error("no built-in spectral table '" + file_name + "'");
    return cache.emplace(file_name, parse_spectral_table(file->text, "spectra/" + file_name))
        .first->second;
}

}  // namespace spt

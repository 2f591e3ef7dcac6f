// Parser for spectra/glasses.csv (one material per row, not a wavelength table) and look-ups.
#include "spectral/glass_catalog.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <stdexcept>

#include "io/embedded_files.h"

namespace spt {

namespace {

constexpr std::string_view kHeader = "name,model,k1,k2,k3,k4,k5,k6,k7,k8,nd,vd,source";
constexpr int kFields = 13;  // the last, source, takes the rest of the line (citations hold commas)

/// Index from a four-term Sellmeier formula (λ in µm, C in µm²).
double sellmeier4(const std::array<double, 8>& k, double lambda_nm) {
    const double l2 = (lambda_nm * 1e-3) * (lambda_nm * 1e-3);
    double n2 = 1.0;
    for (int i = 0; i < 3; ++i) n2 += k[i] * l2 / (l2 - k[i + 3]);
    n2 += k[6] * l2 / (l2 - k[7]);
    return std::sqrt(std::max(n2, 0.0));
}

SpectrumSource make_ior(std::string_view model, const std::array<double, 8>& k,
                        const std::string& where) {
    if (model == "cauchy") {
        if (k[3] != 0 || k[4] != 0 || k[5] != 0 || k[6] != 0 || k[7] != 0)
            throw std::runtime_error(where + ": cauchy uses k1..k3 only");
        return SpectrumSource::cauchy(k[0], k[1], k[2]);
    }
    if (model != "sellmeier")
        throw std::runtime_error(where + ": unknown model '" + std::string(model) + "'");
    if (k[6] == 0 && k[7] == 0)
        return SpectrumSource::sellmeier(k[0], k[1], k[2], k[3], k[4], k[5]);
    // SpectrumSource has three Sellmeier terms; a fourth (water) is tabulated every 0.5 nm
    // over 200-1100 nm: linear interpolation stays within 4e-8 of the formula over 360-830 nm,
    // below the float resolution of n.
    std::vector<std::pair<double, double>> table;
    for (int i = 0; i <= 1800; ++i) {
        const double lambda = 200.0 + 0.5 * i;
        table.emplace_back(lambda, sellmeier4(k, lambda));
    }
    return SpectrumSource::piecewise_linear(std::move(table));
}

double parse_number(std::string_view s, const std::string& where) {
    double v = 0;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(v))
        throw std::runtime_error(where + ": expected a number, got '" + std::string(s) + "'");
    return v;
}

bool iequals(std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               const auto lower = [](char c) { return c >= 'A' && c <= 'Z' ? char(c + 32) : c; };
               return lower(x) == lower(y);
           });
}

}  // namespace

std::vector<GlassInfo> parse_glass_catalog(std::string_view text, const std::string& origin) {
    std::vector<GlassInfo> glasses;
    bool header_seen = false;
    int line_no = 0;
    while (!text.empty()) {
        const std::size_t eol = text.find('\n');
        std::string_view line = text.substr(0, eol);
        text.remove_prefix(eol == std::string_view::npos ? text.size() : eol + 1);
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        if (line.empty() || line.front() == '#') continue;
        const std::string where = origin + ":" + std::to_string(line_no);
        if (!header_seen) {
            if (line != kHeader)
                throw std::runtime_error(where + ": expected the header " + std::string(kHeader));
            header_seen = true;
            continue;
        }
        std::vector<std::string_view> f;
        while (static_cast<int>(f.size()) < kFields - 1) {
            const std::size_t comma = line.find(',');
            if (comma == std::string_view::npos) break;
            f.push_back(line.substr(0, comma));
            line.remove_prefix(comma + 1);
        }
        f.push_back(line);
        if (static_cast<int>(f.size()) != kFields || f[0].empty() || f.back().empty())
            throw std::runtime_error(where + ": expected " + std::string(kHeader) +
                                     " with a name and a source");

        GlassInfo g;
        g.name = f[0];
        std::array<double, 8> k{};
        for (int i = 0; i < 8; ++i) k[i] = parse_number(f[2 + i], where);
        g.ior = make_ior(f[1], k, where);
        g.nd = parse_number(f[10], where);
        g.vd = parse_number(f[11], where);
        g.source = f[12];
        // A shifted column or a pole near the visible gives no physical index at the d line.
        const double n_d = g.ior.eval(kLineD);
        if (!(n_d > 1.0 && std::isfinite(n_d)))
            throw std::runtime_error(where + ": index at 587.56 nm is not finite and > 1");
        for (const GlassInfo& other : glasses)
            if (iequals(other.name, g.name))
                throw std::runtime_error(where + ": duplicate name " + g.name);
        glasses.push_back(std::move(g));
    }
    if (glasses.empty()) throw std::runtime_error(origin + ": no glasses");
    return glasses;
}

const std::vector<GlassInfo>& glass_catalog() {
    static const std::vector<GlassInfo> catalog = [] {
        const EmbeddedFile* file = find_embedded("spectra/glasses.csv");
        if (!file) throw std::runtime_error("spectra/glasses.csv is not built in");
        return parse_glass_catalog(file->text, "spectra/glasses.csv");
    }();
    return catalog;
}

std::optional<GlassInfo> find_glass(std::string_view name) {
    for (const GlassInfo& g : glass_catalog())
        if (iequals(g.name, name)) return g;
    return std::nullopt;
}

std::vector<std::string> glass_names() {
    std::vector<std::string> names;
    for (const GlassInfo& g : glass_catalog()) names.push_back(g.name);
    return names;
}

double abbe_number(const SpectrumSource& ior) {
    return (ior.eval(kLineD) - 1.0) / (ior.eval(kLineF) - ior.eval(kLineC));
}

}  // namespace spt

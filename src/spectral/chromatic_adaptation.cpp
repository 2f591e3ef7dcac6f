// Bradford adaptation matrices and the white points of named illuminants and temperatures.
#include "spectral/chromatic_adaptation.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>

#include "spectral/spectral_table.h"

namespace spt {

Matrix3 bradford_adaptation(const Chromaticity& source, const Chromaticity& target) {
    const auto cone = [](const Chromaticity& xy) {
        return spt::apply(kBradford, Xyz{xy[0] / xy[1], 1.0, (1.0 - xy[0] - xy[1]) / xy[1]});
    };
    const std::array<double, 3> s = cone(source), t = cone(target);
    Matrix3 scale{};
    for (int i = 0; i < 3; ++i) scale[i][i] = t[i] / s[i];
    return invert(kBradford) * scale * kBradford;
}

ColorSpace white_balanced(const ColorSpace& space, const Chromaticity& source) {
    ColorSpace adapted = space;
    adapted.from_xyz = space.from_xyz * bradford_adaptation(source, space.white);
    adapted.to_xyz = invert(adapted.from_xyz);
    return adapted;
}

std::optional<Chromaticity> illuminant_xy(const std::string& name) {
    struct Named {
        const char* name;
        Chromaticity xy;
    };
    static constexpr Named kIlluminants[] = {
        {"A", {0.44758, 0.40745}},   {"D50", {0.3457, 0.3585}},   {"D55", {0.33243, 0.34744}},
        {"D65", {0.3127, 0.3290}},   {"D75", {0.29903, 0.31488}}, {"E", {1.0 / 3, 1.0 / 3}},
        {"F2", {0.3721, 0.3751}},    {"FL2", {0.3721, 0.3751}},   {"F11", {0.3805, 0.3769}},
        {"FL11", {0.3805, 0.3769}},
    };
    std::string upper = name;
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    for (const Named& n : kIlluminants)
        if (upper == n.name) return n.xy;
    return std::nullopt;
}

Chromaticity planckian_xy(double kelvin) {
    const SpectralTable& cmf = embedded_spectral_table("cie_1931_2deg.csv");
    const auto &xs = cmf.column("x_bar"), &ys = cmf.column("y_bar"), &zs = cmf.column("z_bar");
    double x = 0, y = 0, z = 0;
    // CIE 15:2004 fixes c2 = 1.4388e-2 m·K for colour temperatures (CODATA's hc/k is
    // 1.438777e-2); c1 and the units cancel in xy.
    constexpr double kC2 = 1.4388e-2;
    for (std::size_t i = 0; i < cmf.wavelengths_nm.size(); ++i) {
        const double lambda = cmf.wavelengths_nm[i] * 1e-9;
        const double b = 1.0 / (std::pow(lambda, 5) * std::expm1(kC2 / (lambda * kelvin)));
        x += b * xs[i], y += b * ys[i], z += b * zs[i];
    }
    return {x / (x + y + z), y / (x + y + z)};
}

Chromaticity daylight_xy(double kelvin) {
    const double t = kelvin, t2 = t * t, t3 = t2 * t;
    const double x = t <= 7000 ? -4.6070e9 / t3 + 2.9678e6 / t2 + 0.09911e3 / t + 0.244063
                               : -2.0064e9 / t3 + 1.9018e6 / t2 + 0.24748e3 / t + 0.237040;
    return {x, -3.0 * x * x + 2.870 * x - 0.275};
}

Chromaticity cct_xy(double kelvin) {
    return kelvin < 4000 ? planckian_xy(kelvin) : daylight_xy(kelvin);
}

std::optional<Chromaticity> parse_white(const std::string& text) {
    if (std::optional<Chromaticity> xy = illuminant_xy(text)) return xy;
    std::string digits = text;
    if (!digits.empty() && (digits.back() == 'K' || digits.back() == 'k')) digits.pop_back();
    double kelvin = 0;
    const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), kelvin);
    if (digits.empty() || ec != std::errc() || ptr != digits.data() + digits.size() ||
        !(kelvin >= kMinWhiteKelvin && kelvin <= kMaxWhiteKelvin))
        return std::nullopt;
    return cct_xy(kelvin);
}

}  // namespace spt

// CIEDE2000 colour difference, implemented from Sharma, Wu and Dalal 2005 (checked against
// their test data in test_rgb_to_spectrum.cpp), independently of the renderer's own code.
#pragma once
#include <array>
#include <cmath>
#include <numbers>

namespace spt {

inline double delta_e_2000(const std::array<double, 3>& lab1, const std::array<double, 3>& lab2) {
    constexpr double pi = std::numbers::pi;
    auto deg = [](double r) { return r * 180.0 / std::numbers::pi; };
    auto rad = [](double d) { return d * std::numbers::pi / 180.0; };
    const double L1 = lab1[0], a1 = lab1[1], b1 = lab1[2];
    const double L2 = lab2[0], a2 = lab2[1], b2 = lab2[2];
    const double C1 = std::hypot(a1, b1), C2 = std::hypot(a2, b2);
    const double Cm = 0.5 * (C1 + C2);
    const double G = 0.5 * (1 - std::sqrt(std::pow(Cm, 7) / (std::pow(Cm, 7) + std::pow(25.0, 7))));
    const double a1p = (1 + G) * a1, a2p = (1 + G) * a2;
    const double C1p = std::hypot(a1p, b1), C2p = std::hypot(a2p, b2);
    auto hue = [&](double b, double ap) {
        if (b == 0 && ap == 0) return 0.0;
        double h = deg(std::atan2(b, ap));
        return h < 0 ? h + 360 : h;
    };
    const double h1p = hue(b1, a1p), h2p = hue(b2, a2p);
    const double dLp = L2 - L1, dCp = C2p - C1p;
    double dhp = 0;
    if (C1p * C2p != 0) {
        dhp = h2p - h1p;
        if (dhp > 180) dhp -= 360;
        else if (dhp < -180) dhp += 360;
    }
    const double dHp = 2 * std::sqrt(C1p * C2p) * std::sin(rad(dhp / 2));
    const double Lpm = 0.5 * (L1 + L2), Cpm = 0.5 * (C1p + C2p);
    double hpm = h1p + h2p;
    if (C1p * C2p != 0) {
        if (std::fabs(h1p - h2p) <= 180) hpm = 0.5 * (h1p + h2p);
        else if (h1p + h2p < 360) hpm = 0.5 * (h1p + h2p + 360);
        else hpm = 0.5 * (h1p + h2p - 360);
    }
    const double T = 1 - 0.17 * std::cos(rad(hpm - 30)) + 0.24 * std::cos(rad(2 * hpm)) +
                     0.32 * std::cos(rad(3 * hpm + 6)) - 0.20 * std::cos(rad(4 * hpm - 63));
    const double dtheta = 30 * std::exp(-std::pow((hpm - 275) / 25, 2));
    const double Rc = 2 * std::sqrt(std::pow(Cpm, 7) / (std::pow(Cpm, 7) + std::pow(25.0, 7)));
    const double Sl = 1 + 0.015 * std::pow(Lpm - 50, 2) / std::sqrt(20 + std::pow(Lpm - 50, 2));
    const double Sc = 1 + 0.045 * Cpm, Sh = 1 + 0.015 * Cpm * T;
    const double Rt = -std::sin(rad(2 * dtheta)) * Rc;
    (void)pi;
    return std::sqrt(std::pow(dLp / Sl, 2) + std::pow(dCp / Sc, 2) + std::pow(dHp / Sh, 2) +
                     Rt * (dCp / Sc) * (dHp / Sh));
}

}  // namespace spt

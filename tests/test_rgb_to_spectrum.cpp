// RGB → spectrum → XYZ → RGB round trip under D65, measured with CIEDE2000 (implemented here
// from Sharma, Wu and Dalal 2005, independently of the fit's own Lab residual).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "spectral/rgb_to_spectrum.h"

namespace spt {
namespace {

double delta_e_2000(const std::array<double, 3>& lab1, const std::array<double, 3>& lab2) {
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

TEST(DeltaE2000, MatchesSharmaTestData) {
    // Pairs 1, 7 and 17 of the Sharma, Wu & Dalal (2005) test data.
    EXPECT_NEAR(delta_e_2000({50.0, 2.6772, -79.7751}, {50.0, 0.0, -82.7485}), 2.0425, 1e-4);
    EXPECT_NEAR(delta_e_2000({50.0, 0.0, 0.0}, {50.0, -1.0, 2.0}), 2.3669, 1e-4);
    EXPECT_NEAR(delta_e_2000({50.0, 2.5, 0.0}, {73.0, 25.0, -18.0}), 27.1492, 1e-4);
}

double round_trip_delta_e(const std::array<double, 3>& rgb) {
    const SpectrumSource s = rgb_to_spectrum(rgb);
    const Xyz xyz = reflectance_xyz_d65(s);
    const std::array<double, 3> back = xyz_d65_to_linear_srgb(xyz);
    return delta_e_2000(xyz_d65_to_lab(linear_srgb_to_xyz_d65(rgb)),
                        xyz_d65_to_lab(linear_srgb_to_xyz_d65(back)));
}

TEST(RgbToSpectrum, RoundTripWithinDeltaE2000OfOneHundredth) {
    std::vector<double> levels = {0.0, 0.001, 0.01, 0.05, 0.2, 0.5, 0.8, 0.95, 0.999, 1.0};
    double worst = 0;
    std::array<double, 3> worst_rgb{};
    for (double r : levels)
        for (double g : levels)
            for (double b : levels) {
                const double de = round_trip_delta_e({r, g, b});
                if (de > worst) worst = de, worst_rgb = {r, g, b};
            }
    EXPECT_LE(worst, 0.01) << "worst RGB (" << worst_rgb[0] << ", " << worst_rgb[1] << ", "
                           << worst_rgb[2] << ")";
}

TEST(RgbToSpectrum, SaturatedPrimariesAndExtremes) {
    const std::array<double, 3> cases[] = {
        {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1}, {1, 0, 1},
        {0.001, 0.001, 0.001}, {0.999, 0.999, 0.999}, {0.001, 0, 0}, {0.999, 1, 0.999},
        {0.001, 0.002, 0.0005}, {0.999, 0.998, 0.9995}};
    for (const auto& rgb : cases) {
        EXPECT_LE(round_trip_delta_e(rgb), 0.01) << rgb[0] << " " << rgb[1] << " " << rgb[2];
        const SpectrumSource s = rgb_to_spectrum(rgb);
        for (double l = 360; l <= 830; l += 1) {
            ASSERT_GE(s.eval(l), 0.0);
            ASSERT_LE(s.eval(l), 1.0);
        }
    }
}

TEST(RgbToSpectrum, GreyIsAConstantSpectrum) {
    const SpectrumSource s = rgb_to_spectrum({0.3, 0.3, 0.3});
    EXPECT_TRUE(s.is_constant());
    EXPECT_DOUBLE_EQ(s.eval(500), 0.3);
}

TEST(RgbToSpectrum, OutOfRangeValuesAreRejected) {
    EXPECT_THROW(rgb_to_spectrum({1.2, 0, 0}), std::invalid_argument);
    EXPECT_THROW(rgb_to_spectrum({-0.1, 0, 0}), std::invalid_argument);
    EXPECT_THROW(rgb_to_spectrum({std::nan(""), 0, 0}), std::invalid_argument);
}

}  // namespace
}  // namespace spt

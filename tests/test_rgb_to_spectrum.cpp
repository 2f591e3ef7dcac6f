// RGB → spectrum → XYZ → RGB round trip under D65, measured with CIEDE2000 (tests/ciede2000.h,
// independent of the fit's own Lab residual).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "ciede2000.h"
#include "spectral/rgb_to_spectrum.h"

namespace spt {
namespace {

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

// Bins for lights with narrow lines (spectral/line_spectra.h): smooth illuminants keep the
// default, line spectra get the bins they need, the measure falls as bins double, and
// build_scene raises the bins only when the user left them to it.
#include <gtest/gtest.h>

#include <string>

#include "scene/scene_loader.h"
#include "spectral/catalog_lookup.h"
#include "spectral/line_spectra.h"

namespace spt {
namespace {

SpectrumSource illuminant(const std::string& file) { return column_spectrum(embedded_spectral_table(file), "value"); }

TEST(LineSpectra, SmoothIlluminantsKeepTheDefaultAndLampsWithLinesGetMore) {
    EXPECT_EQ(bins_for_light(illuminant("cie_d65.csv")), 16);
    EXPECT_EQ(bins_for_light(illuminant("cie_a.csv")), 16);
    EXPECT_EQ(bins_for_light(SpectrumSource::constant(2.0)), 16);
    EXPECT_EQ(bins_for_light(illuminant("cie_f2.csv")), 32);
    EXPECT_EQ(bins_for_light(illuminant("cie_f7.csv")), 32);
    EXPECT_EQ(bins_for_light(illuminant("cie_f11.csv")), 64);
    EXPECT_EQ(bins_for_light(illuminant("cie_led_b3.csv")), 64);
    // The measure is what the bins cost in colour: under F11 it falls from ~11 ΔE76 at 16
    // bins to below daylight's at 64; it is scale-free.
    const SpectrumSource f11 = illuminant("cie_f11.csv");
    EXPECT_GT(binned_colour_error(f11, 16), 5.0);
    EXPECT_GT(binned_colour_error(f11, 16), 2 * binned_colour_error(f11, 32));
    EXPECT_LT(binned_colour_error(f11, 64), 1.5 * binned_colour_error(illuminant("cie_d65.csv"), 16));
    EXPECT_NEAR(binned_colour_error(SpectrumSource::product({f11, SpectrumSource::constant(40.0)}), 16),
                binned_colour_error(f11, 16), 1e-5);
    // A lone line 2 nm wide on a dim continuum: the most bins the choice gives.
    const SpectrumSource line = SpectrumSource::gaussian(546.1, 1.0, 1.0, 0.05);
    EXPECT_EQ(bins_for_light(line), 256);
}

const char* kChartUnderF11 = "colorchecker-f11";

TEST(LineSpectra, ScenesGetTheBinsTheirLightsNeedUnlessTheUserChose) {
    SpectralResolution automatic{SpectralResolution::kDefaultBins, true};
    const Scene f11 = *load_builtin_scene(kChartUnderF11, automatic);
    EXPECT_EQ(f11.spectral_resolution.bins, 64);
    EXPECT_FALSE(f11.spectral_resolution_reason.empty());
    const Scene daylight = *load_builtin_scene("colorchecker", automatic);
    EXPECT_EQ(daylight.spectral_resolution.bins, 16);
    EXPECT_TRUE(daylight.spectral_resolution_reason.empty());
    const Scene chosen = *load_builtin_scene(kChartUnderF11, SpectralResolution{16, false});
    EXPECT_EQ(chosen.spectral_resolution.bins, 16);
    const Scene fluorescent = *load_builtin_scene("fluorescent-chart", SpectralResolution{16, false});
    EXPECT_EQ(fluorescent.spectral_resolution.bins, SpectralResolution::kExact);
}

}  // namespace
}  // namespace spt

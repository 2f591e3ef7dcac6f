// Spectral output: a camera sensor as the film's observer, the film's spectral bands, the
// wide wavelength density they may need, and the spectral EXR layout (Fichet et al. 2021).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "exr_reader.h"
#include "io/image_encoders.h"
#include "io/image_writer.h"
#include "render/film.h"
#include "render/renderer.h"
#include "scene/builtin_scenes.h"
#include "scene/scene_loader.h"
#include "spectral/cie.h"
#include "spectral/sensor.h"
#include "spectral/spectral_table.h"
#include "spectral/wavelength_range.h"
#include "test_scenes.h"

namespace spt {
namespace {

using test::image_mean_y;
using test::ImageMean;
using test::small_settings;

// ---- Sensor ----------------------------------------------------------------------------------

/// The CIE 1931 table of spectra/ written as a sensor file (x̄, ȳ, z̄ as r, g, b).
std::string cie_as_sensor_csv() {
    const SpectralTable& t = embedded_spectral_table("cie_1931_2deg.csv");
    std::string text = "# the CIE 1931 observer as a sensor\nwavelength_nm,r,g,b\n";
    char row[128];
    for (std::size_t i = 0; i < t.wavelengths_nm.size(); ++i) {
        std::snprintf(row, sizeof row, "%.17g,%.17g,%.17g,%.17g\n", t.wavelengths_nm[i],
                      t.column("x_bar")[i], t.column("y_bar")[i], t.column("z_bar")[i]);
        text += row;
    }
    return text;
}

// A sensor whose curves are the CIE functions must give the XYZ film to the last bit, for
// camera samples (path) and light-tracing splats (bdpt): the film and the splats use the
// observer they are given, nothing else.
TEST(Sensor, CieFunctionsAsASensorReproduceTheXyzFilm) {
    const Observer sensor = parse_sensor(cie_as_sensor_csv(), "cie.csv");
    EXPECT_EQ(sensor.fingerprint(), Cie1931::get().fingerprint());
    const Scene scene = *make_builtin_scene("cornell", SpectralResolution{});
    for (IntegratorKind kind : {IntegratorKind::path, IntegratorKind::bdpt}) {
        RenderSettings rs = small_settings(12, 12, 4);
        rs.integrator.kind = kind;
        auto xyz_film = std::make_unique<Film>(rs.width, rs.height);
        auto sensor_film = std::make_unique<Film>(rs.width, rs.height, sensor);
        render(scene, rs, *xyz_film);
        render(scene, rs, *sensor_film);
        EXPECT_EQ(xyz_film->xyz_sums(), sensor_film->xyz_sums()) << integrator_name(kind);
        for (int y = 0; y < rs.height; ++y)
            for (int x = 0; x < rs.width; ++x) {
                const Xyz a = xyz_film->pixel_xyz(x, y), b = sensor_film->pixel_xyz(x, y);
                ASSERT_EQ(a.y, b.y);
            }
    }
}

// Linear between rows, zero outside them, normalised by the integral of g.
TEST(Sensor, CurvesAreLinearBetweenRowsAndZeroOutside) {
    const Observer s = parse_sensor("wavelength_nm,r,g,b\n400,1,2,0\n500,3,2,4\n", "s.csv");
    const Xyz mid = s.cmf(450.f);
    EXPECT_NEAR(mid.x, 2.0, 1e-6);
    EXPECT_NEAR(mid.y, 2.0, 1e-6);
    EXPECT_NEAR(mid.z, 2.0, 1e-6);
    EXPECT_EQ(s.cmf(399.f).y, 0.0);
    EXPECT_EQ(s.cmf(501.f).y, 0.0);
    EXPECT_EQ(s.cmf(400.f).x, 1.0);
    // g = 2 on [400, 500] and ramps to 0 over the 1-nm grid step on each side: 200 + 2·1.
    EXPECT_NEAR(s.y_integral(), 202.0, 1e-9);
}

TEST(Sensor, ErrorsNameFileLineAndColumn) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"# c\nwavelength_nm,r,g\n400,1,1\n500,1,1\n",
         "s.csv:2:1: expected the header 'wavelength_nm,r,g,b'"},
        {"wavelength_nm,r,g,b\n400,1,1,1\n900,1,1,1\n",
         "s.csv:3:1: wavelength 900 nm is outside 360-830 nm"},
        {"wavelength_nm,r,g,b\n400,1,1,1\n500,1,-1,1\n", "s.csv:3:7: sensitivity g is negative"},
        {"wavelength_nm,r,g,b\n400,1,1,1\n500,1,1,x\n", "s.csv:3:9: expected a number, got 'x'"},
        {"wavelength_nm,r,g,b\n400,1,1,1\n500,1,1\n", "s.csv:3:1: expected 4 fields, got 3"},
        {"wavelength_nm,r,g,b\n500,1,1,1\n400,1,1,1\n", "s.csv:3:1: wavelengths must increase"},
        {"wavelength_nm,r,g,b\n400,1,1,1\n", "s.csv: expected at least two rows"},
        {"wavelength_nm,r,g,b\n400,1,0,1\n500,1,0,1\n",
         "the second response (y or g) integrates to zero"},
        // Beyond the float range the curves would hold +Inf (and every image with them).
        {"wavelength_nm,r,g,b\n400,1,1,1\n500,1,1e39,1\n",
         "s.csv:3:7: sensitivity g is 1e+39; expected a finite number of at most 3.40282e+38"},
        {"wavelength_nm,r,g,b\n400,1e300,1,1\n500,1,1,1\n", "s.csv:2:5: sensitivity r is 1e+300"},
        {"wavelength_nm,r,g,b\n400,1,1,1\n500,1,1,1e400\n", "s.csv:3:9: expected a number, got '1e400'"},
        {"wavelength_nm,r,g,b\n400,1,1,1\n500,1,1,inf\n", "s.csv:3:9: expected a number, got 'inf'"},
        {"wavelength_nm,r,g,b\n400,1,1,1\nnan,1,1,1\n", "s.csv:3:1: expected a number, got 'nan'"},
    };
    // The largest float is accepted.
    EXPECT_NO_THROW(parse_sensor("wavelength_nm,r,g,b\n400,1,1,1\n500,1,3.4028234e38,1\n", "s.csv"));
    for (const auto& [text, message] : cases) {
        try {
            parse_sensor(text, "s.csv");
            ADD_FAILURE() << "accepted: " << text;
        } catch (const std::runtime_error& e) {
            EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
        }
    }
}

// ---- Bands -----------------------------------------------------------------------------------

// One sample, worked by hand: each lane adds L/(pdf·K·Δ) to its band; lanes outside the range
// or with pdf 0 add nothing.
TEST(SpectralBands, SampleAddsRadianceOverPdfLanesAndWidth) {
    Film film(1, 1);
    film.enable_bands({400, 480, 4});  // Δ = 20 nm
    SampledWavelengths w;
    w.lambda = {405.f, 425.f, 470.f, 700.f};
    w.pdf = {0.01f, 0.02f, 0.005f, 0.003f};
    SampledSpectrum L;
    L.v = Float4{1.f, 2.f, 3.f, 4.f};
    film.add_sample(0, 0, L, w);
    std::vector<float> bands = film.develop_bands();
    ASSERT_EQ(bands.size(), 4u);
    EXPECT_FLOAT_EQ(bands[0], 1.f / (0.01f * 4 * 20));
    EXPECT_FLOAT_EQ(bands[1], 2.f / (0.02f * 4 * 20));
    EXPECT_EQ(bands[2], 0.f);
    EXPECT_FLOAT_EQ(bands[3], 3.f / (0.005f * 4 * 20));
    // A dispersive refraction leaves the hero alone, pdf/K: it counts K times as much.
    w.terminate_secondary();
    film.add_sample(0, 0, L, w);
    bands = film.develop_bands();  // the mean of the two samples
    EXPECT_FLOAT_EQ(bands[0], 0.5f * (1.f / (0.01f * 4 * 20) + 1.f / 0.01f / 20));
    EXPECT_FLOAT_EQ(bands[1], 0.5f * 2.f / (0.02f * 4 * 20));
}

TEST(SpectralBands, BandOfCoversTheRangeAndNothingElse) {
    const SpectralBands b{300, 1100, 16};
    EXPECT_EQ(b.band_of(300), 0);
    EXPECT_EQ(b.band_of(349.99), 0);
    EXPECT_EQ(b.band_of(350), 1);
    EXPECT_EQ(b.band_of(1100), 15);
    EXPECT_EQ(b.band_of(299.9), -1);
    EXPECT_EQ(b.band_of(1100.1), -1);
    EXPECT_EQ(b.band_of(std::nan("")), -1);
    EXPECT_DOUBLE_EQ(b.center_nm(0), 325);
}

// The wide density is normalised, and its samples follow it: the fraction of 2^18 stratified
// hero sets in each 50-nm interval matches the integral of the pdf there (binomial error).
TEST(WideWavelengthSampling, PdfIsNormalisedAndSamplesFollowIt) {
    const WideWavelengthSampling wide = WideWavelengthSampling::covering(300.f, 1100.f);
    EXPECT_EQ(wide.min_nm, 300.f);
    EXPECT_EQ(wide.max_nm, 1100.f);
    double total = 0;
    std::vector<double> expected(16, 0.0);
    for (double l = 300.0005; l < 1100; l += 0.001) {
        const double p = wide.pdf(static_cast<float>(l)) * 0.001;
        total += p;
        expected[static_cast<std::size_t>((l - 300) / 50)] += p;
    }
    EXPECT_NEAR(total, 1.0, 1e-4);
    std::vector<double> counts(16, 0.0);
    const int n = 1 << 18;
    for (int i = 0; i < n; ++i) {
        const SampledWavelengths w = wide.sample((i + 0.5f) / n);
        for (int k = 0; k < kLambdaCount; ++k) {
            ASSERT_GE(w.lambda[k], 300.f);
            ASSERT_LE(w.lambda[k], 1100.f);
            ASSERT_FLOAT_EQ(w.pdf[k], wide.pdf(w.lambda[k]));
            const auto interval = static_cast<std::size_t>(std::min(15.0, (w.lambda[k] - 300.0) / 50));
            counts[interval] += 1.0 / (4.0 * n);
        }
    }
    for (int b = 0; b < 16; ++b)
        EXPECT_NEAR(counts[b], expected[b], 5 * std::sqrt(expected[b] / n) + 1e-5)
            << "interval " << b;
}

/// A scene whose every pixel sees a 3000 K blackbody sky (exact spectra: Planck's law at any λ).
Scene blackbody_sky() {
    const std::string text = R"({"camera": {"position": [0, 0, 0], "look_at": [0, 0, -1]},
        "shapes": [], "background": {"type": "blackbody", "temperature_k": 3000}})";
    return load_scene_text(text, "sky.json", "sky", SpectralResolution{SpectralResolution::kExact},
                           [](const std::string&, std::string&, std::string&, std::string&) {
                               return false;
                           });
}

// The film's bands, rendered with the wide density over 300-1100 nm, estimate each band's mean
// of the sky's spectrum, and the XYZ film stays unbiased (it divides by the same mixture pdf).
// Planted bugs caught: the visible pdf instead of the mixture's (bands beyond 830 nm, pdf 0 or
// wrong), a missing 1/Δ or 1/K, a shifted band index.
TEST(SpectralBands, WideRenderEstimatesTheBandMeansOfAKnownSpectrum) {
    const Scene scene = blackbody_sky();
    const Spectrum& sky = std::get<EnvironmentLight>(scene.lights.at(static_cast<std::size_t>(scene.infinite_light_indices.at(0)))).Le;
    RenderSettings rs = small_settings(8, 8, 256);
    rs.wide_wavelengths = WideWavelengthSampling::covering(300.f, 1100.f);
    const SpectralBands bands{300, 1100, 16};
    auto film = std::make_unique<Film>(rs.width, rs.height);
    film->enable_bands(bands);
    render(scene, rs, *film);
    const std::vector<float> values = film->develop_bands();
    const int pixels = rs.width * rs.height;
    for (int b = 0; b < bands.count; ++b) {
        double expected = 0;
        const double lo = bands.min_nm + b * bands.width_nm();
        for (int i = 0; i < 5000; ++i)
            expected += sky.eval(static_cast<float>(lo + (i + 0.5) * bands.width_nm() / 5000));
        expected /= 5000;
        double sum = 0, sum2 = 0;
        for (int p = 0; p < pixels; ++p) {
            const double v = values[static_cast<std::size_t>(p) * bands.count + b];
            sum += v, sum2 += v * v;
        }
        const double mean = sum / pixels;
        const double error = std::sqrt((sum2 / pixels - mean * mean) / (pixels - 1));
        EXPECT_NEAR(mean, expected, 5 * error + 1e-6 * expected)
            << "band " << b << " at " << bands.center_nm(b);
        EXPECT_GT(error, 0.0);
    }
    // Y of the sky: ∫ L ȳ / ∫ ȳ on the CIE table's grid.
    double y = 0;
    for (int l = 360; l <= 830; ++l)
        y += sky.eval(static_cast<float>(l)) * Cie1931::get().cmf(static_cast<float>(l)).y;
    y /= Cie1931::get().y_integral();
    const ImageMean mean_y = image_mean_y(*film);
    EXPECT_NEAR(mean_y.mean, y, 5 * mean_y.standard_error + 1e-3 * y);
}

// Without --spectral-bands the film holds no band sums and the render is the one it always was.
TEST(SpectralBands, FilmWithoutBandsHasNone) {
    Film film(2, 2);
    EXPECT_FALSE(film.has_bands());
    EXPECT_TRUE(film.develop_bands().empty());
}

// ---- Spectral EXR ----------------------------------------------------------------------------

TEST(SpectralExr, ChannelNameFollowsFichet2021) {
    EXPECT_EQ(spectral_channel_name(550), "S0.550,000000nm");
    EXPECT_EQ(spectral_channel_name(555.5), "S0.555,500000nm");
    EXPECT_EQ(spectral_channel_name(1000), "S0.1000,000000nm");
}

// Channels sorted by byte order (S0.1000 before S0.400), each band's pixels where they belong,
// the layout's attributes and the render metadata typed as given.
TEST(SpectralExr, ChannelsAttributesAndPixelsReadBack) {
    Image image{3, 2, std::vector<float>(18)};
    for (std::size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = static_cast<float>(i);
    SpectralImage spectral{{300, 1100, 4}, std::vector<float>(3 * 2 * 4)};
    for (std::size_t i = 0; i < spectral.values.size(); ++i)
        spectral.values[i] = 100.f + static_cast<float>(i);
    ImageWriteOptions options;
    options.spectral = &spectral;
    options.exr_attributes = {ExrAttribute::text("scene", "cornell"),
                              ExrAttribute::integer("spp", 64),
                              ExrAttribute::real("renderTimeSeconds", 1.25)};
    const std::string s = encode_image(image, ImageFormat::Exr, options);

    std::size_t at = 0;
    const auto attributes = exr_test::parse_exr_header(s, at);
    EXPECT_EQ(exr_test::chlist_names(attributes.at("channels").value),
              (std::vector<std::string>{"B", "G", "R", "S0.1000,000000nm", "S0.400,000000nm",
                                        "S0.600,000000nm", "S0.800,000000nm"}));
    EXPECT_EQ(attributes.at("spectralLayoutVersion").type, "string");
    EXPECT_EQ(attributes.at("spectralLayoutVersion").value, "1.0");
    EXPECT_EQ(attributes.at("emissiveUnits").value, "W.m^-2.sr^-1");
    EXPECT_EQ(attributes.at("scene").value, "cornell");
    EXPECT_EQ(attributes.at("spp").type, "int");
    EXPECT_EQ(exr_test::le32(attributes.at("spp").value, 0), 64u);
    EXPECT_EQ(attributes.at("renderTimeSeconds").type, "double");
    EXPECT_EQ(exr_test::le_double(attributes.at("renderTimeSeconds").value, 0), 1.25);

    const auto channels = exr_test::read_exr_channels(s, 3, 2);
    const char* names[4] = {"S0.400,000000nm", "S0.600,000000nm", "S0.800,000000nm",
                            "S0.1000,000000nm"};
    for (int p = 0; p < 6; ++p) {
        EXPECT_EQ(channels.at("R")[p], image.rgb[3 * p]);
        EXPECT_EQ(channels.at("B")[p], image.rgb[3 * p + 2]);
        for (int b = 0; b < 4; ++b)
            EXPECT_EQ(channels.at(names[b])[p], spectral.values[4 * p + b]) << names[b];
    }
}

TEST(SpectralExr, RawRgbHasNoChromaticities) {
    const Image image{1, 1, {1.f, 2.f, 3.f}};
    ImageWriteOptions options;
    options.exr_chromaticities = false;
    std::size_t at = 0;
    const std::string raw = encode_image(image, ImageFormat::Exr, options);
    const std::string srgb = encode_image(image, ImageFormat::Exr, {});
    EXPECT_EQ(exr_test::parse_exr_header(raw, at).count("chromaticities"), 0u);
    EXPECT_EQ(exr_test::parse_exr_header(srgb, at).count("chromaticities"), 1u);
}

}  // namespace
}  // namespace spt

// Tone curves (src/io/tone_map.h): the PBR Neutral curves' shape (monotone under exposure,
// below 1 everywhere, continuous at toe and knee, hue kept, the stated white inputs, the
// linear range of the Khronos specification) and the clip curve's definition. The clip curve's
// PNG bytes are checked against hand-computed codes in test_image_io.cpp. Also the automatic
// exposure that precedes the curve (src/io/auto_exposure.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "io/auto_exposure.h"
#include "io/tone_map.h"

namespace spt {
namespace {

using Rgb = std::array<double, 3>;

constexpr ToneMap kShoulders[] = {ToneMap::neutral, ToneMap::pbr_neutral};
double f90_of(ToneMap m) { return m == ToneMap::pbr_neutral ? 0.04 : 0.0; }

// Colours of several hues and saturations, and grey; the sweeps scale each one.
const std::vector<Rgb> kColours = {{1, 1, 1},      {1, 0, 0},     {0, 1, 0}, {0, 0, 1},
                                   {1, 0.5, 0.25}, {0.2, 0.3, 1}, {1, 1, 0}, {0.9, 0.8, 0.7},
                                   {0.05, 1, 0.6}, {0.3, 0.3, 0.31}};

Rgb scaled(const Rgb& c, double s) { return {c[0] * s, c[1] * s, c[2] * s}; }

TEST(ToneMap, NamesRoundTrip) {
    for (ToneMap m : {ToneMap::clip, ToneMap::neutral, ToneMap::pbr_neutral})
        EXPECT_EQ(tone_map_from_name(tone_map_name(m)), m);
    EXPECT_EQ(tone_map_name(ToneMap::pbr_neutral), std::string("pbr-neutral"));
    EXPECT_EQ(tone_map_from_name("filmic"), std::nullopt);
}

TEST(ToneMap, ShouldersAreMonotoneUnderExposureAndWithinZeroOne) {
    // Dense log sweep over 2^-30 .. 2^30, 64 steps per stop: every channel non-decreasing.
    for (ToneMap m : kShoulders) {
        for (const Rgb& c : kColours) {
            Rgb previous = tone_map(m, scaled(c, std::exp2(-30.0)));
            for (int k = -30 * 64 + 1; k <= 30 * 64; ++k) {
                const Rgb out = tone_map(m, scaled(c, std::exp2(k / 64.0)));
                for (int i = 0; i < 3; ++i) {
                    ASSERT_GE(out[i], previous[i]) << tone_map_name(m) << " channel " << i
                                                   << " at 2^" << k / 64.0;
                    ASSERT_GE(out[i], 0.0);
                    ASSERT_LE(out[i], 1.0);
                }
                previous = out;
            }
        }
    }
}

TEST(ToneMap, ShouldersMapBlackToBlackAndStayBelowOne) {
    for (ToneMap m : kShoulders) {
        const double f90 = f90_of(m);
        EXPECT_EQ(tone_map(m, {0, 0, 0}), (Rgb{0, 0, 0}));
        // A grey's peak approaches 1 from below: p_n = 1 − (0.2 + F90)²/(p − 0.6 + 2 F90),
        // p = v − F90.
        for (double v : {1.0, 4.0, 13.0, 100.0, 1e6}) {
            const Rgb out = tone_map(m, {v, v, v});
            const double d = 0.2 + f90;
            EXPECT_LT(out[0], 1.0) << v;
            EXPECT_NEAR(out[0], 1.0 - d * d / (v - f90 + d - (0.8 - f90)), 1e-12) << v;
            EXPECT_EQ(out[0], out[1]);
            EXPECT_EQ(out[1], out[2]);
        }
        // Huge, infinite and NaN inputs stay in range (NaN and negatives count as 0).
        const double inf = std::numeric_limits<double>::infinity();
        const double nan = std::numeric_limits<double>::quiet_NaN();
        EXPECT_EQ(tone_map(m, {inf, inf, inf}), (Rgb{1, 1, 1}));
        EXPECT_EQ(tone_map(m, {nan, -1, 0}), (Rgb{0, 0, 0}));
        for (double v : tone_map(m, {1e300, 0, 0})) EXPECT_LE(v, 1.0);
    }
}

/// 8-bit sRGB code of a grey input through the curve.
long grey_code(ToneMap m, double v) {
    const double d = tone_map(m, {v, v, v})[0];
    return std::lround(255 * (1.055 * std::pow(d, 1 / 2.4) - 0.055));
}

TEST(ToneMap, GreysReachWhiteAtTheStatedInputs) {
    // p_n(v) = OETF⁻¹(254.5/255) is where the code first rounds to 255.
    const double s = 254.5 / 255.0, white = std::pow((s + 0.055) / 1.055, 2.4);
    // The values stated in tone_map.h, --help and README: 9.57 and 13.5.
    const std::pair<ToneMap, double> stated[] = {{ToneMap::neutral, 9.57},
                                                 {ToneMap::pbr_neutral, 13.5}};
    for (const auto& [m, value] : stated) {
        const double f90 = f90_of(m), d = 0.2 + f90;
        const double white_input = f90 + (0.8 - f90) - d + d * d / (1.0 - white);
        EXPECT_NEAR(white_input, value, 0.05) << tone_map_name(m);
        EXPECT_EQ(grey_code(m, white_input * 0.999), 254) << tone_map_name(m);
        EXPECT_EQ(grey_code(m, white_input * 1.001), 255) << tone_map_name(m);
    }
}

TEST(ToneMap, LinearRangeOfEachShoulder) {
    // neutral: the identity up to 0.8; pbr-neutral (Khronos): c − 0.04 for channels in
    // [0.08, 0.8], and a grey below 0.08 maps to v²/0.16.
    for (const Rgb& c : {Rgb{0.08, 0.5, 0.8}, Rgb{0.3, 0.3, 0.3}, Rgb{0.79, 0.1, 0.4}}) {
        EXPECT_EQ(tone_map(ToneMap::neutral, c), c);
        const Rgb out = tone_map(ToneMap::pbr_neutral, c);
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(out[i], c[i] - 0.04, 1e-15) << i;
    }
    EXPECT_EQ(tone_map(ToneMap::neutral, {0.001, 0.02, 0}), (Rgb{0.001, 0.02, 0}));
    EXPECT_NEAR(tone_map(ToneMap::pbr_neutral, {0.02, 0.02, 0.02})[0], 0.02 * 0.02 / 0.16, 1e-15);
    EXPECT_LT(tone_map(ToneMap::neutral, {0.81, 0.81, 0.81})[0], 0.81);  // the shoulder begins
}

/// The exposure at which the colour's peak after the toe offset reaches K_s (the knee of the
/// shoulder), by bisection on peak·s − f(min·s), which grows with s.
double knee_scale(const Rgb& c, double f90) {
    const double peak = std::max({c[0], c[1], c[2]}), low = std::min({c[0], c[1], c[2]});
    const auto offset = [&](double x) {
        return f90 > 0 && x <= 2 * f90 ? x - x * x / (4 * f90) : f90;
    };
    double lo = 0, hi = 1e3;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (peak * mid - offset(low * mid) < 0.8 - f90 ? lo : hi) = mid;
    }
    return lo;
}

TEST(ToneMap, ShouldersAreContinuousAtToeAndKnee) {
    const double eps = 1e-9;
    for (ToneMap m : kShoulders) {
        const double f90 = f90_of(m);
        for (const Rgb& c : kColours) {
            const double low = std::min({c[0], c[1], c[2]});
            std::vector<double> edges = {knee_scale(c, f90)};
            if (low > 0 && f90 > 0) edges.push_back(2 * f90 / low);  // the toe ends
            for (double edge : edges) {
                const Rgb below = tone_map(m, scaled(c, edge * (1 - eps)));
                const Rgb above = tone_map(m, scaled(c, edge * (1 + eps)));
                for (int i = 0; i < 3; ++i) EXPECT_NEAR(below[i], above[i], 1e-7) << edge;
            }
        }
        EXPECT_NEAR(knee_scale({1, 1, 1}, f90), 0.8, 1e-12);  // a grey's knee is at 0.8
    }
}

TEST(ToneMap, ShouldersKeepHue) {
    // Output minus its mean stays parallel to input minus its mean, in the same direction.
    for (ToneMap m : kShoulders) {
        for (const Rgb& c : kColours) {
            for (double s : {0.5, 2.0, 10.0}) {
                const Rgb in = scaled(c, s), out = tone_map(m, in);
                const double mi = (in[0] + in[1] + in[2]) / 3, mo = (out[0] + out[1] + out[2]) / 3;
                const Rgb a{in[0] - mi, in[1] - mi, in[2] - mi};
                const Rgb b{out[0] - mo, out[1] - mo, out[2] - mo};
                const Rgb cross{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                                a[0] * b[1] - a[1] * b[0]};
                for (double v : cross) EXPECT_NEAR(v, 0.0, 1e-12);
                for (int i = 0; i < 3; ++i) EXPECT_GE(a[i] * b[i], -1e-15);
            }
        }
    }
}

TEST(ToneMap, ClipIsMinOfOnePerChannel) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(tone_map(ToneMap::clip, {0.25, 1.0, 7.0}), (Rgb{0.25, 1.0, 1.0}));
    EXPECT_EQ(tone_map(ToneMap::clip, {-0.5, nan, 0.0}), (Rgb{0, 0, 0}));
}

/// An image whose pixels are greys of the given luminances (R = G = B = Y in sRGB).
Image grey_image(const std::vector<float>& luminance) {
    Image image{static_cast<int>(luminance.size()), 1, {}};
    for (float y : luminance) image.rgb.insert(image.rgb.end(), {y, y, y});
    return image;
}

TEST(AutoExposure, BringsTheMedianOfNonBlackPixelsToMiddleGrey) {
    const ColorSpace& srgb = srgb_color_space();
    // Median of {0.09, 0.36, 2.0} is 0.36: one stop down to 0.18; the black pixels are left
    // out (counting them would make the median 0.09 and the answer +1).
    EXPECT_NEAR(auto_exposure_stops(grey_image({0, 0.36f, 0, 2.0f, 0.09f, 0}), srgb), -1.0, 1e-6);
    // An even count: the mean of the middle two, (0.045 + 0.135)/2 = 0.09, is one stop below.
    EXPECT_NEAR(auto_exposure_stops(grey_image({0.135f, 0.01f, 5.0f, 0.045f}), srgb), 1.0, 1e-6);
    // Luminance weights are the space's Y row: pure blue of 1 has Y = 0.0722.
    const Image blue{1, 1, {0, 0, 1}};
    EXPECT_NEAR(auto_exposure_stops(blue, srgb), std::log2(0.18 / srgb.to_xyz[1][2]), 1e-12);
    // Nothing to measure, and the --exposure range as the limit.
    EXPECT_EQ(auto_exposure_stops(grey_image({0, 0}), srgb), 0.0);
    EXPECT_EQ(auto_exposure_stops(grey_image({1e-30f}), srgb), 20.0);
}

}  // namespace
}  // namespace spt

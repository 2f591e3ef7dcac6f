// The precomputed RGB → sigmoid coefficient table (spectral/rgb_sigmoid_table.h) against the
// colour it must reproduce: the spectrum of every looked-up colour, lit by D65 and summed at
// 1 nm, measured in CIEDE2000 (tests/ciede2000.h) and CIELAB ΔE*ab against the target colour.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <thread>
#include <vector>

#include "ciede2000.h"
#include "spectral/rgb_sigmoid_table.h"
#include "spectral/rgb_to_spectrum.h"

namespace spt {
namespace {

std::array<double, 3> to_double(const std::array<float, 3>& v) { return {v[0], v[1], v[2]}; }

Xyz table_xyz(const SigmoidCoefficients& c) {
    return reflectance_xyz_d65(SpectrumSource::rgb_sigmoid(c.c0, c.c1, c.c2));
}

struct Errors {
    double de2000 = 0, de_ab = 0;
};

Errors errors(const std::array<float, 3>& rgb) {
    const auto target = xyz_d65_to_lab(linear_srgb_to_xyz_d65(to_double(rgb)));
    const auto got = xyz_d65_to_lab(table_xyz(rgb_sigmoid_coefficients(rgb)));
    const double ab = std::hypot(got[0] - target[0], got[1] - target[1], got[2] - target[2]);
    return {delta_e_2000(target, got), ab};
}

struct Summary {
    double max2000 = 0, sum2000 = 0, max_ab = 0, sum_ab = 0;
    std::array<float, 3> worst{};
    int count = 0;
    void add(const std::array<float, 3>& rgb) {
        const Errors e = errors(rgb);
        if (!(e.de2000 <= max2000)) max2000 = e.de2000, worst = rgb;
        max_ab = std::max(max_ab, e.de_ab);
        sum2000 += e.de2000, sum_ab += e.de_ab, ++count;
    }
    void print(const char* what) const {
        std::printf("%s: %d colours, CIEDE2000 max %.3g mean %.3g, ΔE*ab max %.3g mean %.3g, worst (%g, %g, %g)\n",
                    what, count, max2000, sum2000 / count, max_ab, sum_ab / count, worst[0], worst[1], worst[2]);
    }
};

// A trilinear table at this resolution stays well under the just-noticeable difference; a
// planted off-by-one in the lookup's x index gives ΔE2000 above 3 on this grid (checked by hand).
constexpr double kMaxDeltaE2000 = 0.5;
constexpr double kMeanDeltaE2000 = 0.08;

TEST(RgbSigmoidTable, DenseGridReproducesTheColourUnderD65) {
    Summary s;
    constexpr int n = 24;
    for (int r = 0; r <= n; ++r)
        for (int g = 0; g <= n; ++g)
            for (int b = 0; b <= n; ++b) s.add({float(r) / n, float(g) / n, float(b) / n});
    s.print("grid 25³");
    EXPECT_LE(s.max2000, kMaxDeltaE2000) << s.worst[0] << " " << s.worst[1] << " " << s.worst[2];
    EXPECT_LE(s.sum2000 / s.count, kMeanDeltaE2000);
}

TEST(RgbSigmoidTable, RandomColoursReproduceTheColourUnderD65) {
    Summary s;
    std::mt19937 rng(34);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (int i = 0; i < 20000; ++i) {
        // Half uniform, half with a cubed component (dark and saturated colours).
        std::array<float, 3> rgb = {u(rng), u(rng), u(rng)};
        if (i % 2) rgb[i % 3] = rgb[i % 3] * rgb[i % 3] * rgb[i % 3];
        s.add(rgb);
    }
    s.print("random");
    EXPECT_LE(s.max2000, kMaxDeltaE2000) << s.worst[0] << " " << s.worst[1] << " " << s.worst[2];
    EXPECT_LE(s.sum2000 / s.count, kMeanDeltaE2000);
}

TEST(RgbSigmoidTable, IlluminantsReproduceTheirColour) {
    // scale · s · D65 (luminance 1) has the XYZ of rgb exactly when s, as a reflectance under
    // D65, has the XYZ of rgb / scale: only the plane z = ½ of the table is read.
    Summary s;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    std::uniform_real_distribution<float> log_scale(-6.f, 6.f);
    for (int i = 0; i < 5000; ++i) {
        const float k = std::exp(log_scale(rng));
        const std::array<float, 3> rgb = {k * u(rng), k * u(rng), k * u(rng)};
        const RgbIlluminant e = rgb_illuminant(rgb);
        ASSERT_EQ(e.scale, 2.f * std::max({rgb[0], rgb[1], rgb[2]}));
        const std::array<float, 3> shape_rgb = {rgb[0] / e.scale, rgb[1] / e.scale, rgb[2] / e.scale};
        s.add(shape_rgb);
        const SigmoidCoefficients direct = rgb_sigmoid_coefficients(shape_rgb);
        EXPECT_EQ(e.shape.c0, direct.c0);
        EXPECT_EQ(e.shape.c2, direct.c2);
    }
    s.print("illuminants");
    EXPECT_LE(s.max2000, kMaxDeltaE2000);
}

TEST(RgbSigmoidTable, GreysAreConstantSpectra) {
    for (float g : {0.f, 1e-30f, 1e-7f, 0.001f, 0.18f, 0.25f, 0.5f, 0.7f, 0.999f, 0.9999999f, 1.f}) {
        const SigmoidCoefficients c = rgb_sigmoid_coefficients({g, g, g});
        EXPECT_EQ(c.c0, 0.f);
        EXPECT_EQ(c.c1, 0.f);
        for (float l = 360.f; l <= 830.f; l += 10.f) EXPECT_NEAR(c.eval(l), g, 1e-6) << g;
        EXPECT_NEAR(SpectrumSource::rgb_sigmoid(c.c0, c.c1, c.c2).eval(500.0), g, 1e-6) << g;
    }
    EXPECT_EQ(rgb_sigmoid_coefficients({0, 0, 0}).eval(550.f), 0.f);
    EXPECT_EQ(rgb_sigmoid_coefficients({1, 1, 1}).eval(550.f), 1.f);
}

TEST(RgbSigmoidTable, WhiteIlluminantIsUnitLuminanceD65) {
    const RgbIlluminant e = rgb_illuminant({1, 1, 1});
    EXPECT_EQ(e.scale, 2.f);
    for (float l = 360.f; l <= 830.f; l += 1.f) ASSERT_EQ(e.scale * e.shape.eval(l), 1.f) << l;
    const RgbIlluminant bright = rgb_illuminant({40, 40, 40});
    EXPECT_EQ(bright.scale * bright.shape.eval(555.f), 40.f);
    const RgbIlluminant black = rgb_illuminant({0, 0, 0});
    EXPECT_EQ(black.scale, 0.f);
}

TEST(RgbSigmoidTable, PrimariesCornersAndTinyValues) {
    const std::array<float, 3> corners[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1},
                                            {1, 0, 1}, {1, 0.5f, 0}, {0.5f, 0, 0}, {0, 0, 0.5f}};
    for (const auto& rgb : corners) {
        const Errors e = errors(rgb);
        EXPECT_LE(e.de2000, kMaxDeltaE2000) << rgb[0] << " " << rgb[1] << " " << rgb[2];
    }
    // Dark colours, down to subnormal floats: finite coefficients, a spectrum in [0, 1] and
    // the colour within the bound (it is nearly black: ΔE2000 stays small by itself).
    const std::array<float, 3> tiny[] = {{1e-30f, 0, 0}, {0, 3e-20f, 1e-20f}, {1e-7f, 2e-7f, 0}, {2e-5f, 1e-5f, 3e-6f},
                                         {1e-40f, 0, 0}, {1e-3f, 5e-4f, 0}, {0, 1e-45f, 1e-45f}, {1e-4f, 0, 1e-4f}};
    for (const auto& rgb : tiny) {
        const SigmoidCoefficients c = rgb_sigmoid_coefficients(rgb);
        ASSERT_TRUE(std::isfinite(c.c0) && std::isfinite(c.c1) && std::isfinite(c.c2));
        for (float l = 360.f; l <= 830.f; l += 5.f) {
            ASSERT_GE(c.eval(l), 0.f);
            ASSERT_LE(c.eval(l), 1.f);
        }
        EXPECT_LE(errors(rgb).de2000, kMaxDeltaE2000) << rgb[0] << " " << rgb[1] << " " << rgb[2];
    }
}

TEST(RgbSigmoidTable, LookupsFromSeveralThreadsAgree) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    std::vector<std::array<float, 3>> colours(20000);
    for (auto& c : colours) c = {u(rng), u(rng), u(rng)};
    std::vector<SigmoidCoefficients> reference;
    for (const auto& c : colours) reference.push_back(rgb_sigmoid_coefficients(c));
    std::vector<int> mismatches(4, 0);
    {
        std::vector<std::jthread> threads;
        for (int t = 0; t < 4; ++t)
            threads.emplace_back([&, t] {
                for (std::size_t i = 0; i < colours.size(); ++i) {
                    const std::size_t k = (i * (t + 1) * 7919) % colours.size();  // each thread its own order
                    const SigmoidCoefficients c = rgb_sigmoid_coefficients(colours[k]);
                    mismatches[t] += c.c0 != reference[k].c0 || c.c1 != reference[k].c1 || c.c2 != reference[k].c2;
                }
            });
    }
    for (int m : mismatches) EXPECT_EQ(m, 0);
}

}  // namespace
}  // namespace spt

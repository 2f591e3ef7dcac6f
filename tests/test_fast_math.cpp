// The branch-free logarithm and sine/cosine of the sampling code against <cmath>, over the
// whole range their callers use and beyond.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>

#include "core/fast_math.h"
#include "core/rng.h"
#include "spectral/sampled.h"

namespace {

TEST(FastMath, LogMatchesStdLogOverEveryOctave) {
    // 2^-40 … 2^40 (every exponent), dense inside the wavelength sampler's [0.0149, 12.97].
    double worst = 0;
    spt::Rng rng(1, 2, 3);
    for (int k = 0; k < 200000; ++k) {
        const float x = k < 100000 ? std::ldexp(1.f + rng.uniform(), static_cast<int>(rng.uniform() * 80) - 40)
                                   : 0.0149f + 12.96f * rng.uniform();
        const double exact = std::log(static_cast<double>(x));
        const double err = std::fabs(spt::log_positive(x) - exact) / std::max(1.0, std::fabs(exact));
        worst = std::max(worst, err);
    }
    EXPECT_LT(worst, 4e-7);  // a few float ulps of max(1, |log x|)
    EXPECT_EQ(spt::log_positive(1.f), 0.f);
    EXPECT_NEAR(spt::log_positive(std::sqrt(2.f)), std::log(std::sqrt(2.0)), 1e-7);
    // Four lanes give the same bits as one at a time.
    const spt::Float4 x = {0.02f, 0.7f, 1.4142135f, 12.5f};
    const spt::Float4 l = spt::log_positive(x);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(l[i], spt::log_positive(x[i]));
}

TEST(FastMath, SinCosMatchStdOnTheQuarterCircle) {
    double worst = 0;
    for (int k = -100000; k <= 100000; ++k) {
        const float s = static_cast<float>(k) / 100000.f;
        float sn, cs;
        spt::sincos_quarter_pi(s, sn, cs);
        const double theta = 0.78539816339744831 * s;
        worst = std::max({worst, std::fabs(sn - std::sin(theta)), std::fabs(cs - std::cos(theta))});
    }
    EXPECT_LT(worst, 2e-7);
}

TEST(FastMath, Atan2MatchesStdOnTheUpperHalfPlane) {
    // Random points of the upper half plane at every scale, and near the reduction's seams
    // (y = |x|, y = tan(π/8)·|x|, x = 0, y = 0), against std::atan2 in double.
    double worst = 0;
    spt::Rng rng(4, 5, 6);
    for (int k = 0; k < 400000; ++k) {
        const double r = std::ldexp(1.0 + rng.uniform(), static_cast<int>(rng.uniform() * 40) - 20);
        double angle = rng.uniform() * 3.141592653589793;
        if (k % 4 == 1) angle = (rng.uniform() < 0.5 ? 0.39269908169872414 : 0.7853981633974483) + 1e-6 * (rng.uniform() - 0.5);
        if (k % 4 == 2) angle = 3.141592653589793 - angle;
        const double y = r * std::sin(angle), x = r * std::cos(angle);
        if (y < 0) continue;
        worst = std::max(worst, std::fabs(spt::atan2_nonnegative(y, x) - std::atan2(y, x)));
    }
    EXPECT_LT(worst, 1e-10);  // the series' bound 7e-11 and double rounding
    EXPECT_EQ(spt::atan2_nonnegative(0.0, 1.0), 0.0);
    EXPECT_EQ(spt::atan2_nonnegative(0.0, 0.0), 0.0);
    EXPECT_NEAR(spt::atan2_nonnegative(0.0, -2.0), 3.141592653589793, 1e-15);
    EXPECT_NEAR(spt::atan2_nonnegative(3.0, 0.0), 1.5707963267948966, 1e-15);
    EXPECT_NEAR(spt::atan2_nonnegative(1.0, 1.0), 0.7853981633974483, 1e-15);
    // Planted bug: four terms of the series miss the bound by orders of magnitude.
    const double u = 0.41421356237309503, u2 = u * u;
    EXPECT_GT(std::fabs(u * (1 - u2 * (1.0 / 3 - u2 * (1.0 / 5 - u2 / 7))) - std::atan(u)), 1e-5);
}

TEST(FastMath, SignedAtan2MatchesTheLibraryInEveryQuadrant) {
    // atan2_signed (the environment maps' look-ups) against std::atan2 in double, all four
    // quadrants, and std::atan2's signed zeros: y = ±0 on either side of x.
    double worst = 0;
    spt::Rng rng(10, 11, 12);
    for (int k = 0; k < 200000; ++k) {
        const double r = std::ldexp(1.0 + rng.uniform(), static_cast<int>(rng.uniform() * 40) - 20);
        const double angle = (2.0 * rng.uniform() - 1.0) * 3.141592653589793;
        const double y = r * std::sin(angle), x = r * std::cos(angle);
        worst = std::max(worst, std::fabs(spt::atan2_signed(y, x) - std::atan2(y, x)));
    }
    EXPECT_LT(worst, 1e-10);
    for (const double y : {0.0, -0.0})
        for (const double x : {2.0, -2.0, 0.0}) {
            const double expected = std::atan2(y, x), got = spt::atan2_signed(y, x);
            EXPECT_NEAR(got, expected, 1e-15) << y << ", " << x;
            EXPECT_EQ(std::signbit(got), std::signbit(expected)) << y << ", " << x;
        }
    // Planted bug: the sign dropped (atan2_nonnegative of |y|) is told apart below the x axis.
    EXPECT_GT(std::fabs(spt::atan2_nonnegative(0.5, -1.0) - std::atan2(-0.5, -1.0)), 1.0);
}

TEST(FastMath, LanesGiveTheScalarBits) {
    // atan2_nonnegative and sincos_quarter_pi in lanes (the plane light's polygon and tries)
    // compute, lane by lane, the scalar functions' bits, on both sides of every select of the
    // atan2 reduction (y ≷ |x|, the tan(π/8) shift, x < 0, zeros).
    spt::Rng rng(7, 8, 9);
    int checked = 0;
    for (int k = 0; k < 100000; ++k) {
        spt::Double4 y, x, out;
        for (int j = 0; j < 4; ++j) {
            const double r = std::ldexp(1.0 + rng.uniform(), static_cast<int>(rng.uniform() * 20) - 10);
            const double angle = rng.uniform() * 3.141592653589793;
            y[j] = (k + j) % 13 == 0 ? 0.0 : r * std::sin(angle), x[j] = (k + j) % 17 == 0 ? 0.0 : r * std::cos(angle);
            if (y[j] < 0) y[j] = 0;
        }
        spt::atan2_nonnegative(y, x, out);
        for (int j = 0; j < 4; ++j, ++checked)
            ASSERT_EQ(std::bit_cast<std::uint64_t>(out[j]), std::bit_cast<std::uint64_t>(spt::atan2_nonnegative(y[j], x[j])))
                << y[j] << ", " << x[j];
        const spt::Float4 s = {2.f * rng.uniform() - 1.f, 2.f * rng.uniform() - 1.f, -1.f, 1.f};
        spt::Float4 sn, cs;
        spt::sincos_quarter_pi(s, sn, cs);
        for (int j = 0; j < 4; ++j) {
            float sn1, cs1;
            spt::sincos_quarter_pi(s[j], sn1, cs1);
            ASSERT_EQ(std::bit_cast<std::uint32_t>(sn[j]), std::bit_cast<std::uint32_t>(sn1));
            ASSERT_EQ(std::bit_cast<std::uint32_t>(cs[j]), std::bit_cast<std::uint32_t>(cs1));
        }
    }
    EXPECT_EQ(checked, 400000);
    // Planted bug: one ulp off in a lane is told apart (the comparison is of bits).
    const double a = spt::atan2_nonnegative(1.0, 3.0);
    EXPECT_NE(std::bit_cast<std::uint64_t>(std::nextafter(a, 1.0)), std::bit_cast<std::uint64_t>(a));
}

TEST(FastMath, WavelengthSamplerInvertsItsCdf) {
    // λ(u) must be the inverse of the closed-form CDF of visible_wavelength_pdf:
    // F(λ) = (tanh(0.0072·(λ − 538)) − tanh(0.0072·(360 − 538))) / 1.82750197.
    const double t0 = std::tanh(0.0072 * (360.0 - 538.0));
    double worst = 0;
    for (int k = 0; k < 10000; ++k) {
        const float u = (static_cast<float>(k) + 0.5f) / 10000.f;
        float lambda, pdf;
        spt::sample_visible_wavelength(u, lambda, pdf);
        const double F = (std::tanh(0.0072 * (lambda - 538.0)) - t0) / 1.82750197;
        worst = std::max(worst, std::fabs(F - u));
        EXPECT_NEAR(pdf, spt::visible_wavelength_pdf(lambda), 2e-6 * pdf) << u;
    }
    EXPECT_LT(worst, 2e-6);
}

}  // namespace

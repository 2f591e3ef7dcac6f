// Piecewise-constant distributions (core/piecewise_constant.h): chi-square of 1-D and 2-D
// samples against the function they are built from (cells and sub-cells, so a wrong cell and a
// wrong position within a cell both show), with planted-bug negative controls; pdf against
// sample, normalisation, zero cells, u near 1, the double-precision sums, the all-zero and
// invalid inputs, and an 8192 × 4096 map with one bright texel. Fixed seeds; goodness-of-fit
// tests reject at p < 1e-3.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

#include "chi2.h"
#include "core/piecewise_constant.h"
#include "uniform.h"

namespace {

constexpr double kAlpha = 1e-3;
constexpr double kPiD = 3.14159265358979323846;
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

using spt::PiecewiseConstant1D;
using spt::PiecewiseConstant2D;
using spt_test::Uniform;

int floor_cell(float x, int n) { return static_cast<int>(static_cast<double>(x) * n); }

/// Smooth and strictly positive (≥ 0.1).
std::vector<float> smooth_function(int n) {
    std::vector<float> f(n);
    for (int i = 0; i < n; ++i) {
        const double x = (i + 0.5) / n;
        f[i] = float(1.2 + 0.8 * std::sin(2 * kPiD * x) + 0.3 * std::cos(6 * kPiD * x));
    }
    return f;
}

/// A narrow peak over a dim floor, with every 7th cell exactly zero.
std::vector<float> peaked_function(int n) {
    std::vector<float> f(n);
    for (int i = 0; i < n; ++i) {
        const double x = (i + 0.5) / n;
        f[i] = i % 7 == 3 ? 0.f : float(std::exp(-std::pow((x - 0.3) / 0.02, 2)) * 1000.0 + 1.0);
    }
    return f;
}

/// Expected counts of N samples in `sub` equal bins per cell, for sampling proportional to f.
std::vector<double> expected_counts(const std::vector<float>& f, int sub, double n_samples) {
    double sum = 0;
    for (float v : f) sum += v;
    std::vector<double> e;
    for (float v : f)
        for (int k = 0; k < sub; ++k) e.push_back(n_samples * v / sum / sub);
    return e;
}

// ---------------------------------------------------------------- 1-D

struct Sampled1D {
    std::vector<double> counts;
    int pdf_mismatches = 0, cell_mismatches = 0, outside = 0;
};

/// N samples histogrammed in `sub` bins per cell; each sample's pdf and cell checked against
/// pdf(x) and floor(x·n). `warp` may move x (the planted bugs).
template <typename Warp>
Sampled1D sample_1d(const PiecewiseConstant1D& d, int sub, int n_samples, std::uint64_t seed, Warp warp) {
    const int n = d.size();
    Sampled1D s;
    s.counts.assign(std::size_t(n) * sub, 0.0);
    Uniform rng(seed);
    for (int k = 0; k < n_samples; ++k) {
        float pdf = -1.f;
        int cell = -1;
        float x = d.sample(rng.next_float(), &pdf, &cell);
        if (!(x >= 0.f && x < 1.f)) { ++s.outside; continue; }
        if (pdf != d.pdf(x)) ++s.pdf_mismatches;
        if (cell != floor_cell(x, n)) ++s.cell_mismatches;
        x = warp(x, n);
        s.counts[std::min(std::size_t(double(x) * n * sub), s.counts.size() - 1)] += 1.0;
    }
    return s;
}

const auto kNoWarp = [](float x, int) { return x; };

TEST(PiecewiseConstant1D, ChiSquareSmoothAndPeaked) {
    for (const auto& f : {smooth_function(64), peaked_function(100)}) {
        const PiecewiseConstant1D d(f);
        constexpr int kN = 400000, kSub = 4;
        const Sampled1D s = sample_1d(d, kSub, kN, 7, kNoWarp);
        EXPECT_EQ(s.outside, 0);
        EXPECT_EQ(s.pdf_mismatches, 0);
        EXPECT_EQ(s.cell_mismatches, 0);
        const spt_test::Chi2Result r = spt_test::chi2_test(s.counts, expected_counts(f, kSub, kN));
        EXPECT_GE(r.p_value, kAlpha) << "X2=" << r.statistic << " dof=" << r.dof;
        EXPECT_EQ(r.observed_in_empty, 0.0) << "samples in cells of f = 0";
    }
}

TEST(PiecewiseConstant1D, ChiSquareRejectsPlantedBugs) {
    const std::vector<float> f = peaked_function(100);
    const PiecewiseConstant1D d(f);
    constexpr int kN = 400000, kSub = 4;
    // Off by one cell (a wrong bound in the CDF search): the function shifted one cell right.
    std::vector<float> shifted(f.size());
    for (std::size_t i = 1; i < f.size(); ++i) shifted[i] = f[i - 1];
    shifted[0] = f.back();
    const Sampled1D s = sample_1d(d, kSub, kN, 7, kNoWarp);
    const spt_test::Chi2Result off_by_one = spt_test::chi2_test(s.counts, expected_counts(shifted, kSub, kN));
    EXPECT_TRUE(off_by_one.p_value < kAlpha || off_by_one.observed_in_empty > 0);
    // A wrong position within the cell (offset t squared): caught by the sub-cell bins.
    const auto squared_offset = [](float x, int n) {
        const double c = std::floor(double(x) * n), t = double(x) * n - c;
        return float((c + t * t) / n);
    };
    const Sampled1D bad = sample_1d(d, kSub, kN, 7, squared_offset);
    EXPECT_LT(spt_test::chi2_test(bad.counts, expected_counts(f, kSub, kN)).p_value, kAlpha);
}

TEST(PiecewiseConstant1D, PdfMatchesFunctionAndIntegratesToOne) {
    for (const auto& f : {smooth_function(64), peaked_function(100), std::vector<float>{0, 0, 3, 0}}) {
        const PiecewiseConstant1D d(f);
        const int n = d.size();
        double sum = 0, integral = 0;
        for (float v : f) sum += v;
        EXPECT_NEAR(d.integral(), sum / n, 1e-6 * sum / n);
        for (int i = 0; i < n; ++i) {
            const float p = d.pdf((i + 0.5f) / n);
            EXPECT_NEAR(p, f[i] / (sum / n), 1e-5 * (1 + p)) << i;
            if (f[i] == 0.f) {
                EXPECT_EQ(p, 0.f) << i;
            }
            integral += double(p) / n;
        }
        EXPECT_NEAR(integral, 1.0, 1e-6);
        // x = 1 (a direction on the square's edge) reads the last cell; outside [0,1] is 0.
        EXPECT_EQ(d.pdf(1.f), d.pdf(kOneMinusEpsilon));
        EXPECT_EQ(d.pdf(-1e-7f), 0.f);
        EXPECT_EQ(d.pdf(1.0000001f), 0.f);
        EXPECT_EQ(d.pdf(std::numeric_limits<float>::quiet_NaN()), 0.f);
    }
}

TEST(PiecewiseConstant1D, ZeroCellsAreNeverSampledEvenAtCdfBoundaries) {
    // cdf = 0, ¼, ¼, ½, ½, ¾, ¾, 1, 1: every boundary u lands in a cell of weight 1.
    const std::vector<float> f = {1, 0, 1, 0, 1, 0, 1, 0};
    const PiecewiseConstant1D d(f);
    std::vector<float> us = {0.f, kOneMinusEpsilon, 1.f};
    for (int k = 0; k <= 8; ++k) {
        const float u = k / 8.f;
        us.insert(us.end(), {u, std::nextafter(u, 0.f), std::nextafter(u, 1.f)});
    }
    Uniform rng(3);
    for (int k = 0; k < 100000; ++k) us.push_back(rng.next_float());
    for (float u : us) {
        float pdf = 0;
        int cell = -1;
        const float x = d.sample(u, &pdf, &cell);
        ASSERT_TRUE(x >= 0.f && x < 1.f) << u;
        EXPECT_EQ(f[cell], 1.f) << "u=" << u << " cell " << cell;
        EXPECT_EQ(floor_cell(x, 8), cell) << u;
        EXPECT_EQ(pdf, 2.f) << u;
    }
}

TEST(PiecewiseConstant1D, UNearOneStaysBelowOneInItsCell) {
    // Up to 2^24 cells, where a cell is one float wide near 1; last cells zero or not.
    for (int n : {1, 3, 7, 1000, 8192, 1 << 20, 1 << 24}) {
        for (bool trailing_zeros : {false, true}) {
            std::vector<float> f(n, 1.f);
            if (trailing_zeros && n > 2) f[n - 1] = f[n - 2] = 0.f;
            const PiecewiseConstant1D d(std::move(f));
            for (float u : {kOneMinusEpsilon, 1.f, 2.f, std::numeric_limits<float>::quiet_NaN(), -1.f, 0.f,
                            std::nextafter(kOneMinusEpsilon, 0.f)}) {
                float pdf = 0;
                int cell = -1;
                const float x = d.sample(u, &pdf, &cell);
                EXPECT_TRUE(x >= 0.f && x < 1.f) << n << " u=" << u << " x=" << x;
                EXPECT_EQ(floor_cell(x, n), cell) << n << " u=" << u;
                EXPECT_GT(pdf, 0.f);
                EXPECT_EQ(pdf, d.pdf(x));
                if (trailing_zeros && n > 2) {
                    EXPECT_LT(cell, n - 2) << n << " u=" << u;
                }
            }
        }
    }
}

TEST(PiecewiseConstant1D, SampleWithNullPointers) {
    const PiecewiseConstant1D d({1, 2, 3});
    EXPECT_EQ(d.sample(0.9f, nullptr, nullptr), d.sample(0.9f, nullptr, nullptr));
    EXPECT_EQ(d.size(), 3);
}

TEST(PiecewiseConstant1D, SumsInDoubleKeepSmallCellsAfterABigOne) {
    // One cell of 2^24 and 2^22 − 1 cells of 1: a float running sum stops growing after the
    // first cell (2^24 + 1 rounds to 2^24), and the small cells would get probability 0
    // instead of (2^22 − 1)/(2^24 + 2^22 − 1) ≈ 0.2.
    constexpr int n = 1 << 22;
    std::vector<float> f(n, 1.f);
    f[0] = 16777216.f;
    const double expected = (n - 1.0) / (16777216.0 + n - 1.0);
    {  // planted bug: the same CDF summed in float
        float running = 0.f;
        for (float v : f) running += v;
        EXPECT_EQ(running, 16777216.f) << "the control no longer demonstrates the stall";
    }
    const PiecewiseConstant1D d(f);
    double small = 0;
    for (int i = 1; i < n; ++i) small += double(d.pdf((i + 0.5f) / n)) / n;
    EXPECT_NEAR(small, expected, 1e-6);
    EXPECT_NEAR(d.integral(), (16777216.0 + n - 1) / n, 1e-6 * 5);
    Uniform rng(11);
    constexpr int kN = 100000;
    int hits = 0;
    for (int k = 0; k < kN; ++k) {
        int cell = 0;
        d.sample(rng.next_float(), nullptr, &cell);
        hits += cell >= 1;
    }
    const double sigma = std::sqrt(kN * expected * (1 - expected));
    EXPECT_NEAR(hits, kN * expected, 4.5 * sigma);
}

TEST(PiecewiseConstant1D, AllZeroSamplesUniformly) {
    const PiecewiseConstant1D d(std::vector<float>(5, 0.f));
    EXPECT_EQ(d.integral(), 0.f);
    for (float u : {0.f, 0.1f, 0.5f, 0.99f, kOneMinusEpsilon}) {
        float pdf = 0;
        const float x = d.sample(u, &pdf, nullptr);
        EXPECT_NEAR(x, u, 1e-6f);
        EXPECT_LT(x, 1.f);
        EXPECT_NEAR(pdf, 1.f, 1e-6f);
        EXPECT_EQ(pdf, d.pdf(x));
    }
}

TEST(PiecewiseConstant1D, RejectsInvalidInput) {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    EXPECT_THROW(PiecewiseConstant1D(std::vector<float>{}), std::invalid_argument);
    EXPECT_THROW(PiecewiseConstant1D({1.f, -1e-30f}), std::invalid_argument);
    EXPECT_THROW(PiecewiseConstant1D({1.f, nan}), std::invalid_argument);
    EXPECT_THROW(PiecewiseConstant1D({inf, 1.f}), std::invalid_argument);
    EXPECT_THROW(PiecewiseConstant1D(std::vector<float>((1 << 24) + 1, 1.f)), std::invalid_argument);
    try {
        PiecewiseConstant1D({1.f, 2.f, -3.f});
        ADD_FAILURE() << "no throw";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("f[2]"), std::string::npos) << e.what();
    }
    EXPECT_NO_THROW(PiecewiseConstant1D({0.f, -0.f, 1e-45f}));  // −0 and denormals are ≥ 0
}

// ---------------------------------------------------------------- 2-D

std::vector<float> smooth_2d(int nu, int nv) {
    std::vector<float> f(std::size_t(nu) * nv);
    for (int v = 0; v < nv; ++v)
        for (int u = 0; u < nu; ++u) {
            const double x = (u + 0.5) / nu, y = (v + 0.5) / nv;
            f[std::size_t(v) * nu + u] = float((1.2 + std::sin(2 * kPiD * x)) * (1.1 + std::cos(3 * kPiD * y)));
        }
    return f;
}

/// A bright spot over a dim floor, one all-zero row and scattered zero cells.
std::vector<float> peaked_2d(int nu, int nv) {
    std::vector<float> f(std::size_t(nu) * nv);
    for (int v = 0; v < nv; ++v)
        for (int u = 0; u < nu; ++u) {
            const double x = (u + 0.5) / nu - 0.7, y = (v + 0.5) / nv - 0.35;
            const bool zero = v == 5 || (u * 7 + v * 3) % 11 == 0;
            f[std::size_t(v) * nu + u] = zero ? 0.f : float(500.0 * std::exp(-(x * x + y * y) / 0.003) + 0.5);
        }
    return f;
}

/// Expected counts in 2 × 2 sub-bins per cell, bin index ((2v + j)·2nu + 2u + i).
std::vector<double> expected_2d(const std::vector<float>& f, int nu, int nv, double n_samples) {
    double sum = 0;
    for (float v : f) sum += v;
    std::vector<double> e(std::size_t(4) * nu * nv);
    for (int by = 0; by < 2 * nv; ++by)
        for (int bx = 0; bx < 2 * nu; ++bx)
            e[std::size_t(by) * 2 * nu + bx] = n_samples * f[std::size_t(by / 2) * nu + bx / 2] / sum / 4;
    return e;
}

TEST(PiecewiseConstant2D, ChiSquareSmoothAndPeakedWithPlantedBug) {
    constexpr int nu = 24, nv = 16, kN = 600000;
    for (bool peaked : {false, true}) {
        const std::vector<float> f = peaked ? peaked_2d(nu, nv) : smooth_2d(nu, nv);
        const PiecewiseConstant2D d(f, nu, nv);
        std::vector<double> counts(std::size_t(4) * nu * nv, 0.0), transposed_rows(counts.size(), 0.0);
        int mismatches = 0;
        Uniform rng(peaked ? 5 : 6);
        for (int k = 0; k < kN; ++k) {
            float pdf = -1.f;
            const auto [x, y] = d.sample(rng.next_float(), rng.next_float(), &pdf);
            ASSERT_TRUE(x >= 0.f && x < 1.f && y >= 0.f && y < 1.f);
            if (pdf != d.pdf(x, y) || !(pdf > 0.f)) ++mismatches;
            const int bx = int(double(x) * 2 * nu), by = int(double(y) * 2 * nv);
            counts[std::size_t(by) * 2 * nu + bx] += 1;
            // Planted bug: the rows read bottom-up (v ↦ nv − 1 − v), as a flipped image would be.
            transposed_rows[std::size_t(2 * nv - 1 - by) * 2 * nu + bx] += 1;
        }
        EXPECT_EQ(mismatches, 0);
        const std::vector<double> expected = expected_2d(f, nu, nv, kN);
        const spt_test::Chi2Result r = spt_test::chi2_test(counts, expected);
        EXPECT_GE(r.p_value, kAlpha) << "peaked=" << peaked << " X2=" << r.statistic << " dof=" << r.dof;
        EXPECT_EQ(r.observed_in_empty, 0.0);
        const spt_test::Chi2Result bad = spt_test::chi2_test(transposed_rows, expected);
        EXPECT_TRUE(bad.p_value < kAlpha || bad.observed_in_empty > 0) << "peaked=" << peaked;
    }
}

TEST(PiecewiseConstant2D, PdfMatchesFunctionAndIntegratesToOne) {
    constexpr int nu = 24, nv = 16;
    for (bool peaked : {false, true}) {
        const std::vector<float> f = peaked ? peaked_2d(nu, nv) : smooth_2d(nu, nv);
        const PiecewiseConstant2D d(f, nu, nv);
        double sum = 0, integral = 0;
        for (float v : f) sum += v;
        const double mean = sum / (nu * nv);
        EXPECT_NEAR(d.integral(), mean, 1e-6 * mean);
        for (int v = 0; v < nv; ++v)
            for (int u = 0; u < nu; ++u) {
                const float p = d.pdf((u + 0.5f) / nu, (v + 0.5f) / nv);
                const float fv = f[std::size_t(v) * nu + u];
                EXPECT_NEAR(p, fv / mean, 1e-5 * (1 + p));
                if (fv == 0.f) {
                    EXPECT_EQ(p, 0.f);
                }
                integral += double(p) / (nu * nv);
            }
        EXPECT_NEAR(integral, 1.0, 1e-6);
        EXPECT_EQ(d.pdf(1.f, 1.f), d.pdf(kOneMinusEpsilon, kOneMinusEpsilon));
        EXPECT_EQ(d.pdf(0.5f, -0.25f), 0.f);
        EXPECT_EQ(d.pdf(1.5f, 0.5f), 0.f);
    }
}

TEST(PiecewiseConstant2D, EdgeUsZeroRowsAndAllZero) {
    constexpr int nu = 24, nv = 16;
    const std::vector<float> f = peaked_2d(nu, nv);
    const PiecewiseConstant2D d(f, nu, nv);
    for (float u0 : {0.f, kOneMinusEpsilon, 1.f, 0.5f})
        for (float u1 : {0.f, kOneMinusEpsilon, 1.f, 5.f / 16.f, 6.f / 16.f}) {
            float pdf = 0;
            const auto [x, y] = d.sample(u0, u1, &pdf);
            EXPECT_TRUE(x >= 0.f && x < 1.f && y >= 0.f && y < 1.f);
            EXPECT_GT(f[std::size_t(floor_cell(y, nv)) * nu + floor_cell(x, nu)], 0.f) << u0 << " " << u1;
            EXPECT_EQ(pdf, d.pdf(x, y));
        }
    const PiecewiseConstant2D zero(std::vector<float>(12, 0.f), 4, 3);
    EXPECT_EQ(zero.integral(), 0.f);
    float pdf = 0;
    const auto [x, y] = zero.sample(0.3f, 0.6f, &pdf);
    EXPECT_NEAR(x, 0.3f, 1e-6f);
    EXPECT_NEAR(y, 0.6f, 1e-6f);
    EXPECT_NEAR(pdf, 1.f, 1e-6f);
}

TEST(PiecewiseConstant2D, RejectsInvalidInput) {
    EXPECT_THROW(PiecewiseConstant2D({1, 2, 3}, 2, 2), std::invalid_argument);
    EXPECT_THROW(PiecewiseConstant2D(std::vector<float>{}, 0, 0), std::invalid_argument);
    EXPECT_THROW(PiecewiseConstant2D({1, 2, 3, -4}, 2, 2), std::invalid_argument);
    EXPECT_THROW(PiecewiseConstant2D({1, 2, std::numeric_limits<float>::quiet_NaN(), 4}, 2, 2),
                 std::invalid_argument);
    try {
        PiecewiseConstant2D({1, 2, 3, 4, 5, -6}, 3, 2);
        ADD_FAILURE() << "no throw";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("f[5]"), std::string::npos) << e.what();
    }
}

TEST(PiecewiseConstant2D, HugeMapWithOneBrightTexel) {
    // 8192 × 4096 texels of 1 and one of 2^25 − 1, which then carries exactly half the total.
    constexpr int nu = 8192, nv = 4096, bu = 5000, bv = 1234;
    constexpr double cells = double(nu) * nv, bright = cells - 1;
    std::vector<float> f(std::size_t(nu) * nv, 1.f);
    f[std::size_t(bv) * nu + bu] = float(bright);
    const PiecewiseConstant2D d(f, nu, nv);
    f = {};
    // Memory: one float CDF value per texel plus one per row and the marginal.
    EXPECT_LE(d.memory_bytes(), sizeof(float) * (std::size_t(nu + 1) * nv + nv + 1));
    EXPECT_NEAR(d.integral(), 2.0 * bright / cells, 1e-6);
    const double p_bright = bright / (2 * bright);  // 0.5
    EXPECT_NEAR(d.pdf((bu + 0.5f) / nu, (bv + 0.5f) / nv), p_bright * cells, 1e-5 * p_bright * cells);
    // A texel in another row: density (1/total)·cells = 1/2, to the CDF's float resolution.
    EXPECT_NEAR(d.pdf((17 + 0.5f) / nu, (3000 + 0.5f) / nv), 0.5, 1e-3);
    Uniform rng(13);
    constexpr int kN = 40000;
    int hits = 0, mismatches = 0;
    for (int k = 0; k < kN; ++k) {
        float pdf = 0;
        const auto [x, y] = d.sample(rng.next_float(), rng.next_float(), &pdf);
        hits += floor_cell(x, nu) == bu && floor_cell(y, nv) == bv;
        if (pdf != d.pdf(x, y)) ++mismatches;
    }
    EXPECT_EQ(mismatches, 0);
    EXPECT_NEAR(hits, kN * p_bright, 4.5 * std::sqrt(kN * 0.25));
    // The density integrates to 1 over all 33 M texels.
    double integral = 0;
    for (int v = 0; v < nv; ++v) {
        double row = 0;
        for (int u = 0; u < nu; ++u) row += d.pdf((u + 0.5f) / nu, (v + 0.5f) / nv);
        integral += row / cells;
    }
    EXPECT_NEAR(integral, 1.0, 1e-5);
}

}  // namespace

// Spectral building blocks against analytic values: sources, binning, wavelength sampling, CIE
// tables and colour-space matrices. Reference values are from SPECTRAL.md and ROBUSTNESS.md
// (§4, §21), recomputed in double precision where noted.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "chi2.h"
#include "spectral/cie.h"
#include "spectral/color_space.h"
#include "spectral/sampled.h"
#include "spectral/spectral_table.h"
#include "spectral/spectrum.h"
#include "spectral/spectrum_source.h"
#include "uniform.h"

#ifndef SPT_SOURCE_DIR
#error "SPT_SOURCE_DIR must name the source tree (a public compile definition of spt_core)"
#endif

namespace {

using spt::SpectrumSource;

/// Deterministic uniform numbers, independent of the renderer's own generator.
using spt_test::Uniform;

// Analytic CDF of the visible-wavelength density 0.0039398042/cosh²(0.0072(λ−538)) on
// [360, 830]: (tanh(a(λ−538)) + tanh(178a)) / (tanh(178a) + tanh(292a)).
double visible_cdf(double lambda) {
    constexpr double a = 0.0072;
    return (std::tanh(a * (lambda - 538.0)) + std::tanh(a * 178.0)) /
           (std::tanh(a * 178.0) + std::tanh(a * 292.0));
}

/// Simpson's rule with n (even) intervals.
template <typename F>
double simpson(F f, double a, double b, int n) {
    const double h = (b - a) / n;
    double s = f(a) + f(b);
    for (int i = 1; i < n; ++i) s += f(a + i * h) * (i % 2 ? 4.0 : 2.0);
    return s * h / 3.0;
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

}  // namespace

// ---------------------------------------------------------------- analytic sources

TEST(SpectrumSource, GaussianValues) {
    const SpectrumSource s = SpectrumSource::gaussian(540.0, 40.0, 0.55, 0.05);
    EXPECT_DOUBLE_EQ(s.eval(540.0), 0.60);                        // peak: offset + scale
    EXPECT_NEAR(s.eval(580.0), 0.05 + 0.55 * std::exp(-1.0), 1e-15);  // one width away
    EXPECT_NEAR(s.eval(460.0), 0.05 + 0.55 * std::exp(-4.0), 1e-15);  // two widths, symmetric
    EXPECT_NEAR(s.eval(460.0), s.eval(620.0), 1e-15);
    EXPECT_FALSE(s.is_constant());
}

TEST(SpectrumSource, SigmoidValues) {
    const SpectrumSource s = SpectrumSource::sigmoid(600.0, 12.0, 0.65, 0.05);
    EXPECT_DOUBLE_EQ(s.eval(600.0), 0.05 + 0.65 / 2.0);  // midpoint of the step
    // 1/(1+e^{−x}) = 3/4 at x = ln 3, 1/4 at x = −ln 3.
    EXPECT_NEAR(s.eval(600.0 + 12.0 * std::log(3.0)), 0.05 + 0.65 * 0.75, 1e-15);
    EXPECT_NEAR(s.eval(600.0 - 12.0 * std::log(3.0)), 0.05 + 0.65 * 0.25, 1e-15);
    EXPECT_NEAR(s.eval(1000.0), 0.70, 1e-12);  // saturates at offset + scale
    EXPECT_NEAR(s.eval(200.0), 0.05, 1e-12);   // and at offset
}

TEST(SpectrumSource, BlackbodyEqualsScaleAtNormalisationWavelength) {
    for (double kelvin : {2856.0, 5000.0, 6500.0, 10000.0}) {
        const SpectrumSource s = SpectrumSource::blackbody(kelvin, 4.0);
        EXPECT_DOUBLE_EQ(s.eval(560.0), 4.0) << kelvin << " K";
        EXPECT_DOUBLE_EQ(s.eval(450.0), 4.0 * spt::planck(450.0, kelvin) / spt::planck(560.0, kelvin));
    }
    const SpectrumSource other = SpectrumSource::blackbody(6500.0, 2.0, 500.0);
    EXPECT_DOUBLE_EQ(other.eval(500.0), 2.0);
}

TEST(SpectrumSource, PlanckMatchesHandComputedRadiance) {
    // B(λ,T) = 2hc²/λ⁵ / (exp(hc/(λkT)) − 1) with the exact SI constants
    // h = 6.62607015e-34, c = 299792458, k = 1.380649e-23. At λ = 560 nm, T = 6500 K:
    // hc/(λkT) = 3.95268..., 2hc² = 1.19104297e-16, so B = 4.23427906734645e13 W·sr⁻¹·m⁻³
    // (computed with 30-digit arithmetic, mpmath). Double evaluation: relative error ~1e-15.
    EXPECT_NEAR(spt::planck(560.0, 6500.0) / 4.23427906734645e13, 1.0, 1e-12);
    // Ratio B(450)/B(560) at 6500 K = 1.12207380231405 (same computation): a bluish white.
    EXPECT_NEAR(spt::planck(450.0, 6500.0) / spt::planck(560.0, 6500.0), 1.12207380231405, 1e-12);
    // Wien's displacement law: the peak of B at 5000 K is at b/T = 2.897771955e-3/5000 m.
    const double peak = 2.897771955e-3 / 5000.0 * 1e9;  // 579.554 nm
    EXPECT_GT(spt::planck(peak, 5000.0), spt::planck(peak - 0.5, 5000.0));
    EXPECT_GT(spt::planck(peak, 5000.0), spt::planck(peak + 0.5, 5000.0));
}

TEST(SpectrumSource, PiecewiseLinearInterpolatesAndHoldsEnds) {
    const SpectrumSource s = SpectrumSource::piecewise_linear({{400.0, 0.2}, {500.0, 0.8}, {600.0, 0.5}});
    EXPECT_DOUBLE_EQ(s.eval(400.0), 0.2);
    EXPECT_DOUBLE_EQ(s.eval(500.0), 0.8);
    EXPECT_DOUBLE_EQ(s.eval(600.0), 0.5);
    EXPECT_NEAR(s.eval(450.0), 0.5, 1e-15);
    EXPECT_NEAR(s.eval(425.0), 0.35, 1e-15);
    EXPECT_NEAR(s.eval(550.0), 0.65, 1e-15);
    EXPECT_NEAR(s.eval(590.0), 0.53, 1e-15);
    EXPECT_DOUBLE_EQ(s.eval(300.0), 0.2);  // held below the first point
    EXPECT_DOUBLE_EQ(s.eval(830.0), 0.5);  // held above the last
    EXPECT_FALSE(s.is_constant());
}

TEST(SpectrumSource, CauchyBk7AtSodiumLine) {
    // n = A + B/λ², λ in µm: 1.5046 + 0.0042/0.5876² = 1.516764 (SPECTRAL.md §2.6).
    const SpectrumSource s = SpectrumSource::cauchy(1.5046, 0.00420);
    EXPECT_NEAR(s.eval(587.6), 1.51676, 1e-5);
    EXPECT_NEAR(s.eval(830.0), 1.51070, 1e-5);  // ROBUSTNESS §4
    EXPECT_FALSE(s.is_constant());
    EXPECT_TRUE(SpectrumSource::cauchy(1.5, 0.0).is_constant());
}

TEST(SpectrumSource, SellmeierBk7Indices) {
    // Schott BK7 (λ in µm). References are rounded to 5 decimals (error ≤ 5e-6).
    const SpectrumSource bk7 = SpectrumSource::sellmeier(1.03961212, 0.231792344, 1.01046945,
                                                         0.00600069867, 0.0200179144, 103.560653);
    EXPECT_NEAR(bk7.eval(360.0), 1.53719, 1e-5);
    EXPECT_NEAR(bk7.eval(400.0), 1.53085, 1e-5);
    EXPECT_NEAR(bk7.eval(550.0), 1.51852, 1e-5);
    EXPECT_NEAR(bk7.eval(587.6), 1.51680, 1e-5);
    EXPECT_NEAR(bk7.eval(700.0), 1.51306, 1e-5);
    EXPECT_NEAR(bk7.eval(830.0), 1.51020, 1e-5);
    EXPECT_FALSE(bk7.is_constant());
}

// ---------------------------------------------------------------- binned spectra

TEST(Spectrum, BinsReproduceSpectraInTheLookUpsOwnSpan) {
    // A table through values at the 16 bin centres, held flat beyond the end centres, is in the
    // span of the look-up's basis: its least-squares projection must reproduce it.
    std::vector<std::pair<double, double>> points;
    for (int i = 0; i < 16; ++i) points.push_back({392.5 + 25.0 * i, 0.2 + 0.5 * ((i * 7) % 5) / 4.0});
    const SpectrumSource src = SpectrumSource::piecewise_linear(points);
    const spt::Spectrum s(src, {16});
    // Up to the midpoint quadrature of the projection (64 points per bin).
    for (int i = 0; i < 16; ++i) EXPECT_NEAR(s.bins()[i], points[i].second, 2e-4) << "bin " << i;
}

TEST(Spectrum, BinsAreTheLeastSquaresProjection) {
    // Normal equations: the residual source − look-up is orthogonal to every basis function
    // (hats between centres, end ones flat), checked by an independent fine integration. A
    // smooth source, so that the clamp to the source's range never acts.
    const SpectrumSource src = SpectrumSource::gaussian(580.0, 150.0, 0.5, 0.2);
    for (int bins : {4, 16, 100}) {
        const spt::Spectrum s(src, {bins});
        const double width = 400.0 / bins;
        std::vector<double> dot(bins, 0.0), norm(bins, 0.0);
        constexpr int kSteps = 200000;
        for (int k = 0; k < kSteps; ++k) {
            const double l = 380.0 + (k + 0.5) * 400.0 / kSteps;
            const double residual = src.eval(l) - s.eval(static_cast<float>(l));
            const double x = std::clamp((l - 380.0) / width - 0.5, 0.0, bins - 1.0);
            const int i = std::min(static_cast<int>(x), bins - 2);
            const double t = x - i;
            dot[i] += (1 - t) * residual, dot[i + 1] += t * residual;
            norm[i] += (1 - t) * std::fabs(src.eval(l)), norm[i + 1] += t * std::fabs(src.eval(l));
        }
        for (int i = 0; i < bins; ++i)
            EXPECT_LT(std::fabs(dot[i]), 2e-3 * norm[i]) << "basis " << i << " of " << bins;
    }
}

TEST(Spectrum, SingleBinIsConstantAtItsMean) {
    // One 400-nm bin: the projection onto a constant is the mean over 380–780 nm.
    const SpectrumSource src = SpectrumSource::gaussian(460.0, 35.0, 0.75, 0.05);
    const spt::Spectrum s(src, {1});
    double mean = 0;  // midpoint rule, as the projection onto a single constant
    for (int k = 0; k < 64; ++k) mean += src.eval(380.0 + (k + 0.5) * 400.0 / 64) / 64;
    const float v = static_cast<float>(mean);
    for (float l : {300.f, 360.f, 380.f, 450.f, 580.f, 700.f, 780.f, 830.f}) EXPECT_EQ(s.eval(l), v) << l;
    EXPECT_EQ(s.max_value(), v);
    EXPECT_EQ(s.min_value(), v);
}

TEST(Spectrum, LinearBetweenCentresAndHeldOutside) {
    const SpectrumSource src = SpectrumSource::sigmoid(600.0, 12.0, 0.65, 0.05);
    const spt::Spectrum s(src, {16});  // 25 nm bins, centres 392.5, 417.5, ..., 767.5
    const auto& b = s.bins();
    for (int i = 0; i + 1 < 16; ++i) {
        const float c0 = 392.5f + 25.f * static_cast<float>(i);
        for (float t : {0.25f, 0.5f, 0.75f}) {
            const float expected = (1.f - t) * b[i] + t * b[i + 1];
            // λ = c0 + 25t is exact in float; (λ−380)/25 − 0.5 rounds by ≤ 2 ulp of ≤ 16.
            EXPECT_NEAR(s.eval(c0 + 25.f * t), expected, 4e-6f * std::fabs(b[i + 1] - b[i]) + 1e-7f)
                << "between centres " << i << " and " << i + 1 << " at t=" << t;
        }
    }
    // Held beyond the first and last centre, including outside [380, 780].
    for (float l : {360.f, 379.f, 380.f, 385.f, 392.5f}) EXPECT_EQ(s.eval(l), b.front()) << l;
    for (float l : {767.5f, 770.f, 780.f, 800.f, 830.f}) EXPECT_EQ(s.eval(l), b.back()) << l;
    EXPECT_EQ(std::vector<float>(b.begin(), b.end()), spt::project_onto_bins(src, 16));
}

TEST(Spectrum, ExactModeEvaluatesSource) {
    const SpectrumSource src = SpectrumSource::blackbody(6500.0, 4.0);
    const spt::Spectrum s(src, {spt::SpectralResolution::kExact});
    EXPECT_TRUE(s.bins().empty());
    for (float l = 360.f; l <= 830.f; l += 3.7f)
        EXPECT_EQ(s.eval(l), static_cast<float>(src.eval(l))) << l;
    // The range scan covers the sampled range: the blackbody at 6500 K decreases above 446 nm,
    // so min is at 830 nm and max near the 446 nm peak.
    EXPECT_NEAR(s.min_value(), src.eval(830.0), 1e-6 * src.eval(830.0));
    EXPECT_GE(s.max_value(), static_cast<float>(src.eval(446.0)) * (1 - 1e-6f));
}

TEST(Spectrum, ConstantDetection) {
    const spt::SpectralResolution res{16};
    const spt::Spectrum c(SpectrumSource::constant(0.75), res);
    EXPECT_TRUE(c.is_constant());
    EXPECT_TRUE(c.bins().empty());
    for (float l : {300.f, 380.f, 555.f, 830.f, 900.f}) EXPECT_EQ(c.eval(l), 0.75f);
    EXPECT_FALSE(c.is_zero());
    EXPECT_TRUE(spt::Spectrum(SpectrumSource::constant(0.0), res).is_zero());
    EXPECT_TRUE(spt::Spectrum().is_zero());
    // Sources that are flat despite their kind.
    EXPECT_TRUE(spt::Spectrum(SpectrumSource::gaussian(500, 30, 0.0, 0.3), res).is_constant());
    EXPECT_EQ(spt::Spectrum(SpectrumSource::gaussian(500, 30, 0.0, 0.3), res).eval(500.f), 0.3f);
    EXPECT_TRUE(spt::Spectrum(SpectrumSource::piecewise_linear({{400, 0.4}, {700, 0.4}}), res).is_constant());
    EXPECT_TRUE(spt::Spectrum(SpectrumSource::cauchy(1.5, 0.0), res).is_constant());
    // And sources that are not.
    EXPECT_FALSE(spt::Spectrum(SpectrumSource::gaussian(500, 30, 0.1, 0.3), res).is_constant());
    EXPECT_FALSE(spt::Spectrum(SpectrumSource::piecewise_linear({{400, 0.4}, {700, 0.5}}), res).is_constant());
    EXPECT_FALSE(spt::Spectrum(SpectrumSource::blackbody(6500), res).is_constant());
}

// ---------------------------------------------------------------- wavelength sampling

TEST(WavelengthSampling, PdfIntegratesToOneOnVisibleRange) {
    // Simpson with 4700 intervals (0.1 nm): the integrand is smooth, so the rule's error is
    // ~h⁴·max|f''''|/180 < 1e-12; the float pdf contributes a few 1e-7 relative.
    const double integral = simpson([](double l) { return double(spt::visible_wavelength_pdf(float(l))); },
                                    360.0, 830.0, 4700);
    EXPECT_NEAR(integral, 1.0, 1e-4);
    EXPECT_GT(spt::visible_wavelength_pdf(360.f), 0.f);
    EXPECT_GT(spt::visible_wavelength_pdf(830.f), 0.f);
    for (float l : {0.f, 300.f, 359.9f, 830.1f, 1000.f, -5.f})
        EXPECT_EQ(spt::visible_wavelength_pdf(l), 0.f) << l;
    // Peak at 538 nm: 0.0039398042 = 1/253.8197.
    EXPECT_NEAR(spt::visible_wavelength_pdf(538.f), 0.0039398042f, 1e-9f);
}

TEST(WavelengthSampling, MatchesMitsubaReferenceValues) {
    // Mitsuba 3 test_spectra.py test05 (3 decimals, so ±5e-4); float evaluation adds ≤ 2e-4 nm
    // (|dλ/du| ≤ 465 at these u times a few float ulps) and ≤ 2e-4 to 1/p.
    struct Case { float u; double lambda, inv_pdf; };
    for (const Case& c : {Case{0.1f, 424.343, 465.291}, Case{0.5f, 545.903, 254.643},
                          Case{0.8f, 635.381, 400.432}}) {
        const float lambda = spt::sample_visible_wavelength(c.u);
        EXPECT_NEAR(lambda, c.lambda, 1e-3) << "u=" << c.u;
        EXPECT_NEAR(1.0 / spt::visible_wavelength_pdf(lambda), c.inv_pdf, 1e-3) << "u=" << c.u;
    }
    // The extremes stay inside the range.
    EXPECT_GE(spt::sample_visible_wavelength(0.f), 360.f);
    EXPECT_LE(spt::sample_visible_wavelength(1.f - 0x1p-24f), 830.f);
    EXPECT_NEAR(spt::sample_visible_wavelength(0.f), 360.f, 1e-2f);
    EXPECT_NEAR(spt::sample_visible_wavelength(1.f - 0x1p-24f), 830.f, 1e-2f);
}

TEST(WavelengthSampling, ChiSquareAgainstPdf) {
    // 1e6 samples in 100 equal bins over [360, 830]; expected counts integrate
    // visible_wavelength_pdf over each bin (Simpson, 64 intervals). Reject at p < 1e-3.
    constexpr int kBins = 100, kSamples = 1'000'000;
    constexpr double kWidth = 470.0 / kBins;
    std::vector<double> observed(kBins, 0.0), expected(kBins, 0.0);
    for (int i = 0; i < kBins; ++i)
        expected[i] = kSamples * simpson([](double l) { return double(spt::visible_wavelength_pdf(float(l))); },
                                         360.0 + i * kWidth, 360.0 + (i + 1) * kWidth, 64);
    Uniform rng(20240601);
    int outside = 0;
    for (int n = 0; n < kSamples; ++n) {
        const float l = spt::sample_visible_wavelength(rng.next_float());
        if (!(l >= 360.f && l <= 830.f)) { ++outside; continue; }
        observed[std::min(kBins - 1, static_cast<int>((l - 360.0) / kWidth))] += 1.0;
    }
    EXPECT_EQ(outside, 0);
    const spt_test::Chi2Result r = spt_test::chi2_test(observed, expected);
    EXPECT_EQ(r.dof, kBins - 1);
    EXPECT_GE(r.p_value, 1e-3) << "X2=" << r.statistic << " dof=" << r.dof;
}

TEST(WavelengthSampling, ChiSquareRejectsUniformPdf) {
    // Negative control: the same samples against a uniform density on [360, 830] must fail.
    constexpr int kBins = 100, kSamples = 1'000'000;
    std::vector<double> observed(kBins, 0.0), expected(kBins, double(kSamples) / kBins);
    Uniform rng(20240601);
    for (int n = 0; n < kSamples; ++n) {
        const float l = spt::sample_visible_wavelength(rng.next_float());
        observed[std::clamp(static_cast<int>((l - 360.0) / 4.7), 0, kBins - 1)] += 1.0;
    }
    EXPECT_LT(spt_test::chi2_test(observed, expected).p_value, 1e-3);
}

TEST(SampledWavelengths, CompanionsAreRotatedStrata) {
    // λ_k = inverse CDF((u + k/4) mod 1), each with its own pdf. Checked through the analytic
    // CDF: |CDF(λ_k) − u_k| ≤ float rounding of u_k (6e-8) + p(λ)·δλ, where the float inverse
    // CDF is off by δλ ≲ 10 ulp of atanh's argument times 138.9·|atanh'| (≤ 1e-7 in CDF units):
    // 1e-6 leaves a margin of 5 (measured: 1.8e-7).
    // The pdf may be computed from the sampling variable y = tanh(0.0072(538 − λ)) as
    // 0.0039398042·(1 − y²): y carries ≤ 3ε absolute rounding, so 1 − y² is off by ≤ 6ε
    // absolute, i.e. 6ε/(1 − y²) relative, with 1 − y² = p/0.0039398042 (≤ 1.1e-5 at 830 nm;
    // measured 1.7e-6), plus 8ε for evaluating cosh in visible_wavelength_pdf.
    std::vector<float> us = {0.f, 0.1f, 0.25f, 0.3f, 0.5f, 0.74999994f, 0.75f, 0.9f, 1.f - 0x1p-24f};
    for (int i = 0; i < 100000; ++i) us.push_back(static_cast<float>(i) / 100000.f);
    for (float u : us) {
        const spt::SampledWavelengths w = spt::SampledWavelengths::sample(u);
        for (int k = 0; k < spt::kLambdaCount; ++k) {
            const double uk = std::fmod(double(u) + k / 4.0, 1.0);
            ASSERT_GE(w.lambda[k], 360.f);
            ASSERT_LE(w.lambda[k], 830.f);
            ASSERT_NEAR(visible_cdf(w.lambda[k]), uk, 1e-6) << "u=" << u << " k=" << k;
            const double p = spt::visible_wavelength_pdf(w.lambda[k]);
            const double one_minus_y2 = p / 0.0039398042;
            ASSERT_NEAR(w.pdf[k], p, p * (6.0 * 0x1p-24 / one_minus_y2 + 8.0 * 0x1p-24))
                << "u=" << u << " k=" << k;
            ASSERT_GT(w.pdf[k], 0.f);
        }
        ASSERT_FALSE(w.secondary_terminated());
    }
}

TEST(SampledWavelengths, TerminateSecondaryZeroesCompanionsAndQuartersHero) {
    spt::SampledWavelengths w = spt::SampledWavelengths::sample(0.37f);
    const auto before = w;
    w.terminate_secondary();
    EXPECT_TRUE(w.secondary_terminated());
    EXPECT_EQ(w.pdf[0], before.pdf[0] / 4.f);  // exact: division by a power of two
    for (int k = 1; k < spt::kLambdaCount; ++k) EXPECT_EQ(w.pdf[k], 0.f);
    EXPECT_EQ(w.lambda, before.lambda);  // wavelengths unchanged
    // Idempotent: a second dispersive event must not divide the hero pdf again.
    w.terminate_secondary();
    EXPECT_EQ(w.pdf[0], before.pdf[0] / 4.f);
    // The film estimate is preserved: (1/4)·L0/(p0/4) = L0/p0, companions contribute 0.
    const spt::SampledSpectrum L(1.f);
    const spt::Xyz xyz = spt::Cie1931::get().to_xyz(L, w);
    const double expected_y = spt::Cie1931::get().cmf(w.lambda[0]).y / before.pdf[0] /
                              spt::Cie1931::get().y_integral();
    EXPECT_NEAR(xyz.y, expected_y, 1e-6 * expected_y);
}

// ---------------------------------------------------------------- CIE 1931

TEST(Cie1931, YIntegralMatchesTable) {
    // Trapezoid ∫ȳ of the 1-nm table = Σȳ − (ȳ(360)+ȳ(830))/2 = 106.856915 (header of the CSV:
    // Σȳ = 106.856917101172). pbrt's CIE_Y_integral is 106.856895.
    const double y = spt::Cie1931::get().y_integral();
    EXPECT_NEAR(y, 106.857, 1e-3 * 106.857);
    EXPECT_NEAR(y, 106.856917101172 - 0.5 * (3.917e-06 + 4.5181e-07), 1e-6);
}

TEST(Cie1931, EmbeddedTableEqualsCsvOnDisk) {
    const std::string path = std::string(SPT_SOURCE_DIR) + "/spectra/cie_1931_2deg.csv";
    const std::string text = read_file(path);
    ASSERT_FALSE(text.empty()) << "cannot read " << path;
    const spt::SpectralTable disk = spt::parse_spectral_table(text, path);
    const spt::SpectralTable& embedded = spt::embedded_spectral_table("cie_1931_2deg.csv");
    ASSERT_EQ(disk.column_names, embedded.column_names);
    ASSERT_EQ(disk.wavelengths_nm.size(), 471u);
    ASSERT_EQ(disk.wavelengths_nm, embedded.wavelengths_nm);
    ASSERT_EQ(disk.columns.size(), 3u);
    for (std::size_t c = 0; c < 3; ++c) {
        ASSERT_EQ(disk.columns[c].size(), embedded.columns[c].size());
        for (std::size_t i = 0; i < disk.columns[c].size(); ++i)
            EXPECT_EQ(disk.columns[c][i], embedded.columns[c][i]) << disk.column_names[c + 1] << " at "
                                                                  << disk.wavelengths_nm[i] << " nm";
    }
    // The look-up returns the table entries exactly at integer wavelengths (t = 0 or 1).
    const auto& xs = disk.column("x_bar");
    const auto& ys = disk.column("y_bar");
    const auto& zs = disk.column("z_bar");
    for (std::size_t i = 0; i < disk.wavelengths_nm.size(); ++i) {
        const float l = static_cast<float>(disk.wavelengths_nm[i]);
        ASSERT_EQ(l, 360.f + static_cast<float>(i));
        const spt::Xyz c = spt::Cie1931::get().cmf(l);
        EXPECT_EQ(c.x, static_cast<float>(xs[i])) << l;
        EXPECT_EQ(c.y, static_cast<float>(ys[i])) << l;
        EXPECT_EQ(c.z, static_cast<float>(zs[i])) << l;
    }
    // Linear between entries, zero outside [360, 830].
    const spt::Xyz mid = spt::Cie1931::get().cmf(555.5f);
    EXPECT_NEAR(mid.y, 0.5 * (float(ys[195]) + float(ys[196])), 1e-7);
    for (float l : {359.f, 359.99f, 830.01f, 900.f}) {
        const spt::Xyz c = spt::Cie1931::get().cmf(l);
        EXPECT_EQ(c.x, 0.0);
        EXPECT_EQ(c.y, 0.0);
        EXPECT_EQ(c.z, 0.0);
    }
}

TEST(Cie1931, ConstantSpectrumGivesEqualEnergyXyz) {
    // E[to_xyz(1)] = ∫cmf/∫ȳ over 360–830 = (1.0000794, 1, 1.0003278) for this table (trapezoid of
    // the float entries); ROBUSTNESS §21 gives (1.00008, 1.00000, 1.00033) for 1-nm sums.
    // Estimate: R = 64 independent replicates, each 1024 strata of u → 4096 wavelengths. The
    // tolerance is 4 standard errors of the replicate mean plus 2e-6 for float32 rounding of
    // the pdf and CMF evaluation (a few ulps relative, systematic).
    const spt::Observer& cie = spt::Cie1931::get();
    constexpr int kReplicates = 64, kStrata = 1024;
    Uniform rng(7);
    double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
    for (int r = 0; r < kReplicates; ++r) {
        double m[3] = {0, 0, 0};
        for (int i = 0; i < kStrata; ++i) {
            const float u = static_cast<float>((i + rng.next_double()) / kStrata);
            const spt::SampledWavelengths w = spt::SampledWavelengths::sample(std::min(u, 1.f - 0x1p-24f));
            const spt::Xyz xyz = cie.to_xyz(spt::SampledSpectrum(1.f), w);
            m[0] += xyz.x, m[1] += xyz.y, m[2] += xyz.z;
        }
        for (int c = 0; c < 3; ++c) {
            m[c] /= kStrata;
            sum[c] += m[c], sum2[c] += m[c] * m[c];
        }
    }
    // Expected value from the table itself (float entries, as the renderer holds them).
    const spt::SpectralTable& t = spt::embedded_spectral_table("cie_1931_2deg.csv");
    double integral[3] = {0, 0, 0};
    for (int c = 0; c < 3; ++c)
        for (std::size_t i = 0; i + 1 < t.wavelengths_nm.size(); ++i)
            integral[c] += 0.5 * (double(float(t.columns[c][i])) + double(float(t.columns[c][i + 1])));
    const double documented[3] = {1.00008, 1.00000, 1.00033};
    for (int c = 0; c < 3; ++c) {
        const double expected = integral[c] / integral[1];
        EXPECT_NEAR(expected, documented[c], 5e-6);  // rounding of the documented values
        const double mean = sum[c] / kReplicates;
        const double var = (sum2[c] - kReplicates * mean * mean) / (kReplicates - 1);
        const double se = std::sqrt(std::max(var, 0.0) / kReplicates);
        EXPECT_NEAR(mean, expected, 4.0 * se + 2e-6) << "component " << c << " se=" << se;
    }
}

// ---------------------------------------------------------------- colour spaces

TEST(ColorSpace, SrgbMatricesMatchIec61966) {
    // SPECTRAL.md §2.4: exact inverse from the IEC primaries and D65 (0.3127, 0.3290), 7 decimals.
    const spt::Matrix3 from_xyz = {{{3.2409699, -1.5373832, -0.4986108},
                                    {-0.9692436, 1.8759675, 0.0415551},
                                    {0.0556301, -0.2039770, 1.0569715}}};
    const spt::Matrix3 to_xyz = {{{0.4123908, 0.3575843, 0.1804808},
                                  {0.2126390, 0.7151687, 0.0721923},
                                  {0.0193308, 0.1191948, 0.9505322}}};
    const spt::ColorSpace& cs = spt::srgb_color_space();
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            EXPECT_NEAR(cs.from_xyz[i][j], from_xyz[i][j], 1e-6) << i << "," << j;
            EXPECT_NEAR(cs.to_xyz[i][j], to_xyz[i][j], 1e-6) << i << "," << j;
        }
}

TEST(ColorSpace, SrgbWhiteIsD65AndMatricesAreInverse) {
    const spt::ColorSpace& cs = spt::srgb_color_space();
    // RGB (1,1,1) → XYZ of xy = (0.3127, 0.3290) with Y = 1.
    const spt::Xyz white{0.3127 / 0.3290, 1.0, (1.0 - 0.3127 - 0.3290) / 0.3290};
    const spt::Xyz one{1.0, 1.0, 1.0};
    const auto w = spt::apply(cs.to_xyz, one);
    EXPECT_NEAR(w[0], white.x, 1e-12);
    EXPECT_NEAR(w[1], white.y, 1e-12);
    EXPECT_NEAR(w[2], white.z, 1e-12);
    const auto rgb = spt::apply(cs.from_xyz, white);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(rgb[i], 1.0, 1e-12);
    // to_xyz · from_xyz = I (double precision, condition number ~ 10).
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double s = 0, s2 = 0;
            for (int k = 0; k < 3; ++k) {
                s += cs.to_xyz[i][k] * cs.from_xyz[k][j];
                s2 += cs.from_xyz[i][k] * cs.to_xyz[k][j];
            }
            EXPECT_NEAR(s, i == j ? 1.0 : 0.0, 1e-12) << i << "," << j;
            EXPECT_NEAR(s2, i == j ? 1.0 : 0.0, 1e-12) << i << "," << j;
        }
    // Primaries: RGB (1,0,0) has chromaticity (0.64, 0.33), etc.
    const double prim[3][2] = {{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}};
    for (int p = 0; p < 3; ++p) {
        const double X = cs.to_xyz[0][p], Y = cs.to_xyz[1][p], Z = cs.to_xyz[2][p];
        EXPECT_NEAR(X / (X + Y + Z), prim[p][0], 1e-12);
        EXPECT_NEAR(Y / (X + Y + Z), prim[p][1], 1e-12);
    }
}

TEST(ColorSpace, SpectralD65MapsToSrgbWhite) {
    // D65 (5-nm table to 780 nm, linear in between) through the CMFs: chromaticity
    // (0.31271, 0.32902) against the rounded white (0.3127, 0.3290). The 4-decimal rounding
    // of the white point and the 780–830 nm gap move RGB by ≲ 5e-4, so allow 1e-3 (pbrt: 1e-2).
    const spt::SpectralTable& d65 = spt::embedded_spectral_table("cie_d65.csv");
    std::vector<std::pair<double, double>> pts;
    for (std::size_t i = 0; i < d65.wavelengths_nm.size(); ++i)
        pts.emplace_back(d65.wavelengths_nm[i], d65.columns[0][i]);
    const SpectrumSource d65_src = SpectrumSource::piecewise_linear(pts);
    spt::Xyz xyz;
    for (int l = 360; l <= 830; ++l) {
        const double v = l <= 780 ? d65_src.eval(l) : 0.0;  // the table stops at 780 nm
        const spt::Xyz c = spt::Cie1931::get().cmf(static_cast<float>(l));
        xyz.x += v * c.x, xyz.y += v * c.y, xyz.z += v * c.z;
    }
    const double sum = xyz.x + xyz.y + xyz.z;
    EXPECT_NEAR(xyz.x / sum, 0.3127, 1e-4);
    EXPECT_NEAR(xyz.y / sum, 0.3290, 1e-4);
    const spt::Xyz norm{xyz.x / xyz.y, 1.0, xyz.z / xyz.y};
    const auto rgb = spt::apply(spt::srgb_color_space().from_xyz, norm);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(rgb[i], 1.0, 1e-3) << "channel " << i;
}

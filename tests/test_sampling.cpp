// Statistical tests of the sampling routines: chi-square goodness of fit of warps against their
// densities (pbrt-v4 bsdfs_test.cpp, Mitsuba chi2.py), planted-bug negative controls, lobe
// selection of the three-lobe material, and energy conservation (ROBUSTNESS.md §6, §7 cases
// 18–20). All tests use fixed seeds; goodness-of-fit tests reject at p < 1e-3.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "chi2.h"
#include "test_scenes.h"
#include "core/sampling.h"
#include "model/bsdfs/bsdf.h"
#include "model/bsdfs/fresnel.h"
#include "model/material.h"
#include "spectral/sampled.h"
#include "spectral/spectrum.h"
#include "uniform.h"

namespace {

constexpr double kPiD = 3.14159265358979323846;
constexpr double kAlpha = 1e-3;  ///< rejection level of every goodness-of-fit test here

using spt_test::Uniform;

template <typename F>
double simpson(F f, double a, double b, int n) {
    const double h = (b - a) / n;
    double s = f(a) + f(b);
    for (int i = 1; i < n; ++i) s += f(a + i * h) * (i % 2 ? 4.0 : 2.0);
    return s * h / 3.0;
}

spt::Spectrum constant(double v) {
    return spt::Spectrum(spt::SpectrumSource::constant(v), spt::SpectralResolution{});
}

/// A kd/ks/kt material as the scene loader builds it: a DiffuseBsdf when only kd is non-zero,
/// a LobeMixBsdf otherwise.
spt::Material make_material(const char* name, spt::Spectrum kd, spt::Spectrum ks, spt::Spectrum kt = constant(0),
                            spt::Spectrum eta = constant(1.5)) {
    spt::Material m;
    m.name = name;
    if (ks.is_zero() && kt.is_zero()) m.bsdf = spt::DiffuseBsdf{std::move(kd)};
    else m.bsdf = spt::LobeMixBsdf{std::move(kd), std::move(ks), std::move(kt), std::move(eta)};
    m.flags = spt::bsdf_flags(m.bsdf);
    return m;
}


/// Uniformly distributed unit vector (double precision, then rounded).
spt::Vec3 random_direction(Uniform& rng) {
    const double z = 1.0 - 2.0 * rng.next_double(), phi = 2.0 * kPiD * rng.next_double();
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return spt::normalize(spt::Vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)));
}

/// θ×φ histogram of directions in the +z hemisphere against a density (solid angle measure),
/// integrated over each cell by Simpson's rule in θ (the densities here do not depend on φ).
struct HemisphereHistogram {
    static constexpr int kTheta = 40, kPhi = 80;
    std::vector<double> counts = std::vector<double>(kTheta * kPhi, 0.0);
    int outside = 0;

    void add(const spt::Vec3& w) {
        if (!(w.z >= 0.f)) { ++outside; return; }
        const double theta = std::acos(std::min(1.0, double(w.z)));
        double phi = std::atan2(double(w.y), double(w.x));
        if (phi < 0.0) phi += 2.0 * kPiD;
        const int i = std::min(kTheta - 1, static_cast<int>(theta / (0.5 * kPiD) * kTheta));
        const int j = std::min(kPhi - 1, static_cast<int>(phi / (2.0 * kPiD) * kPhi));
        counts[i * kPhi + j] += 1.0;
    }

    template <typename Pdf>
    static std::vector<double> expected(Pdf pdf_of_cos, double n_samples) {
        std::vector<double> e(kTheta * kPhi);
        const double dtheta = 0.5 * kPiD / kTheta, dphi = 2.0 * kPiD / kPhi;
        for (int i = 0; i < kTheta; ++i) {
            const double p = simpson([&](double t) { return pdf_of_cos(std::cos(t)) * std::sin(t); },
                                     i * dtheta, (i + 1) * dtheta, 16);
            for (int j = 0; j < kPhi; ++j) e[i * kPhi + j] = n_samples * p * dphi;
        }
        return e;
    }
};

}  // namespace

// ---------------------------------------------------------------- the chi-square helper itself

TEST(Chi2, RegularizedGammaMatchesClosedForms) {
    for (double x : {0.0, 1e-3, 0.5, 1.0, 2.5, 7.0, 30.0, 200.0}) {
        EXPECT_NEAR(spt_test::regularized_gamma_q(1.0, x), std::exp(-x), 1e-14) << x;
        EXPECT_NEAR(spt_test::regularized_gamma_q(0.5, x), std::erfc(std::sqrt(x)), 1e-14) << x;
        EXPECT_NEAR(spt_test::regularized_gamma_q(3.0, x), std::exp(-x) * (1 + x + x * x / 2), 1e-13) << x;
    }
    // Upper 5% points of the chi-square distribution (tables: Abramowitz & Stegun 26.8;
    // NIST/SEMATECH e-Handbook 1.3.6.7.4), given to 3–6 decimals.
    EXPECT_NEAR(spt_test::chi2_survival(3.841459, 1), 0.05, 1e-6);
    EXPECT_NEAR(spt_test::chi2_survival(18.307038, 10), 0.05, 1e-6);
    EXPECT_NEAR(spt_test::chi2_survival(124.342, 100), 0.05, 1e-5);
    EXPECT_NEAR(spt_test::chi2_survival(1074.679, 1000), 0.05, 1e-5);
    // Upper 0.1% point for 99 dof (the wavelength test): 148.230.
    EXPECT_NEAR(spt_test::chi2_survival(148.230, 99), 1e-3, 1e-5);
}

TEST(Chi2, PoolsCellsWithSmallExpectedCounts) {
    // Expected 1, 2, 2.5 are pooled into one cell (5.5, observed 6); 46.5 and 48 stand alone.
    const std::vector<double> observed = {3, 1, 2, 50, 44, 0};
    const std::vector<double> expected = {2, 1, 2.5, 48, 46.5, 0};
    const spt_test::Chi2Result r = spt_test::chi2_test(observed, expected);
    EXPECT_EQ(r.cells, 3);
    EXPECT_EQ(r.dof, 2);
    const double x2 = 2.5 * 2.5 / 46.5 + 2.0 * 2.0 / 48.0 + 0.5 * 0.5 / 5.5;
    EXPECT_NEAR(r.statistic, x2, 1e-12);
    EXPECT_NEAR(r.p_value, std::exp(-x2 / 2), 1e-12);  // chi-square(2) survival is e^{−x/2}
    EXPECT_EQ(r.observed_in_empty, 0.0);
    // Observations where the density is zero are reported.
    const spt_test::Chi2Result bad = spt_test::chi2_test({3, 1, 2, 50, 44, 7}, expected);
    EXPECT_EQ(bad.observed_in_empty, 7.0);
}

// ---------------------------------------------------------------- cosine-weighted hemisphere

TEST(CosineHemisphere, PdfIntegratesToOne) {
    const auto e = HemisphereHistogram::expected([](double c) { return double(spt::cosine_hemisphere_pdf(float(c))); }, 1.0);
    double total = 0.0;
    for (double v : e) total += v;
    EXPECT_NEAR(total, 1.0, 1e-3);
    EXPECT_EQ(spt::cosine_hemisphere_pdf(0.f), 0.f);
    EXPECT_EQ(spt::cosine_hemisphere_pdf(-0.5f), 0.f);
    EXPECT_NEAR(spt::cosine_hemisphere_pdf(1.f), 1.0 / kPiD, 6e-8);  // 2 float ulps at 0.318
}

TEST(CosineHemisphere, ChiSquareAgainstPdf) {
    // 40×80 θ×φ cells, 1e6 samples; expected counts integrate cosine_hemisphere_pdf.
    constexpr int kSamples = 1'000'000;
    HemisphereHistogram h;
    Uniform rng(1);
    for (int n = 0; n < kSamples; ++n) {
        const spt::Vec3 w = spt::sample_cosine_hemisphere(rng.next_float(), rng.next_float());
        ASSERT_NEAR(spt::length(w), 1.0, 1e-5);
        h.add(w);
    }
    EXPECT_EQ(h.outside, 0);
    const auto expected = HemisphereHistogram::expected(
        [](double c) { return double(spt::cosine_hemisphere_pdf(float(c))); }, kSamples);
    const spt_test::Chi2Result r = spt_test::chi2_test(h.counts, expected);
    EXPECT_EQ(r.observed_in_empty, 0.0);
    EXPECT_GT(r.dof, 3000);
    EXPECT_GE(r.p_value, kAlpha) << "X2=" << r.statistic << " dof=" << r.dof;
}

TEST(CosineHemisphere, ChiSquareRejectsUniformPdf) {
    // Planted bug (ROBUSTNESS case 19): cosine samples judged against the uniform density 1/2π.
    constexpr int kSamples = 1'000'000;
    HemisphereHistogram h;
    Uniform rng(1);
    for (int n = 0; n < kSamples; ++n) h.add(spt::sample_cosine_hemisphere(rng.next_float(), rng.next_float()));
    const auto uniform = HemisphereHistogram::expected([](double) { return 0.5 / kPiD; }, kSamples);
    EXPECT_LT(spt_test::chi2_test(h.counts, uniform).p_value, kAlpha);
}

TEST(CosineHemisphere, ChiSquareRejectsWarpWithoutSquareRoot) {
    // Planted bug: lifting the disk with z = 1 − r² instead of √(1 − r²) (then renormalised).
    // The error is subtle near the pole, yet 1e6 samples must reveal it.
    constexpr int kSamples = 1'000'000;
    HemisphereHistogram h;
    Uniform rng(2);
    for (int n = 0; n < kSamples; ++n) {
        const spt::Vec3 w = spt::sample_cosine_hemisphere(rng.next_float(), rng.next_float());
        h.add(spt::normalize(spt::Vec3(w.x, w.y, 1.f - w.x * w.x - w.y * w.y)));
    }
    const auto expected = HemisphereHistogram::expected(
        [](double c) { return double(spt::cosine_hemisphere_pdf(float(c))); }, kSamples);
    EXPECT_LT(spt_test::chi2_test(h.counts, expected).p_value, kAlpha);
}

// ---------------------------------------------------------------- three-lobe material

TEST(PlasticBsdf, LobeChoiceProportionalToAlbedo) {
    // kd = 0.6, ks = 0.2: diffuse with probability 0.6/0.8 = 0.75. Every weight is then
    // kd/0.75 = ks/0.25 = 0.8, the albedo. Binomial z-test at α = 1e-3 (|z| < 3.29).
    const spt::Material m = make_material("plastic", constant(0.6), constant(0.2));
    const spt::Vec3 n(0.f, 0.f, 1.f), wo = spt::normalize(spt::Vec3(0.3f, -0.2f, 0.9f));
    constexpr int kSamples = 200'000;
    Uniform rng(3);
    int diffuse = 0;
    double sum = 0.0;
    for (int i = 0; i < kSamples; ++i) {
        spt::SampledWavelengths lambda = spt::SampledWavelengths::sample(rng.next_float());
        const std::optional<spt::BsdfSample> bs =
            spt::test::sample_radiance(m, wo, n, lambda, rng.next_float(), rng.next_float(), rng.next_float());
        ASSERT_TRUE(bs.has_value());
        if (!bs->is_delta()) {
            ++diffuse;
        } else {
            // The specular lobe is a perfect mirror.
            ASSERT_NEAR(bs->wi.x, -wo.x, 1e-6f);
            ASSERT_NEAR(bs->wi.y, -wo.y, 1e-6f);
            ASSERT_NEAR(bs->wi.z, wo.z, 1e-6f);
        }
        for (int k = 0; k < spt::kLambdaCount; ++k) ASSERT_NEAR(bs->weight[k], 0.8f, 1e-6f);
        sum += bs->weight.average();
    }
    const double p = 0.75, se = std::sqrt(p * (1 - p) / kSamples);
    EXPECT_LT(std::fabs(double(diffuse) / kSamples - p) / se, 3.29) << "diffuse share " << double(diffuse) / kSamples;
    EXPECT_NEAR(sum / kSamples, 0.8, 1e-6);
}

TEST(PlasticBsdf, SpectralWeightsAverageToAlbedo) {
    // Spectrally varying kd (the Cornell BLUE) plus grey ks = 0.15: lobe probabilities use the
    // mean over the four wavelengths, so individual weights differ from the albedo, but their
    // expectation at each wavelength is kd(λ) + ks(λ). Tolerance: 4 standard errors.
    const spt::Material m = make_material(
        "blue plastic", spt::Spectrum(spt::SpectrumSource::gaussian(460, 35, 0.75, 0.05), spt::SpectralResolution{}),
        constant(0.15));
    const spt::Vec3 n = spt::normalize(spt::Vec3(0.2f, 0.5f, -0.8f));
    const spt::Vec3 wo = spt::normalize(spt::Vec3(-0.1f, 0.3f, -0.9f));
    const spt::SampledWavelengths base = spt::SampledWavelengths::sample(0.05f);  // 380, 466, 536, 624 nm
    constexpr int kSamples = 200'000;
    Uniform rng(4);
    double sum[spt::kLambdaCount] = {}, sum2[spt::kLambdaCount] = {};
    for (int i = 0; i < kSamples; ++i) {
        spt::SampledWavelengths lambda = base;
        const std::optional<spt::BsdfSample> bs =
            spt::test::sample_radiance(m, wo, n, lambda, rng.next_float(), rng.next_float(), rng.next_float());
        ASSERT_TRUE(bs.has_value());
        for (int k = 0; k < spt::kLambdaCount; ++k) sum[k] += bs->weight[k], sum2[k] += double(bs->weight[k]) * bs->weight[k];
    }
    for (int k = 0; k < spt::kLambdaCount; ++k) {
        const double albedo = spt::test::lobes_of(m).kd.eval(base.lambda[k]) + spt::test::lobes_of(m).ks.eval(base.lambda[k]);
        const double mean = sum[k] / kSamples;
        const double se = std::sqrt(std::max(0.0, sum2[k] / kSamples - mean * mean) / kSamples);
        EXPECT_GT(se, 0.0);
        EXPECT_NEAR(mean, albedo, 4 * se + 1e-6) << "lambda " << base.lambda[k] << " se " << se;
    }
}

TEST(DiffuseBsdf, SamplesFollowCosineLawOnSideOfWo) {
    // Diffuse samples of a plastic material, tilted normal, wo on either side. cosθ relative to
    // the normal on wo's side has CDF cos²θ: 50 bins with expected N·(c1² − c0²); the azimuth
    // in an independent frame around that normal is uniform: 36 bins. α = 1e-3 for each.
    const spt::Material m = make_material("plastic", constant(0.6), constant(0.2));
    const spt::Material lambert = make_material("lambert", constant(0.7), constant(0.0));
    const spt::Vec3 n = spt::normalize(spt::Vec3(0.3f, -0.5f, 0.8f));
    Uniform rng(5);
    int case_index = 0;
    for (const spt::Material* mat : {&m, &lambert}) {
        for (float side : {1.f, -1.f}) {
            ++case_index;
            const spt::Vec3 n_wo = n * side;
            spt::Vec3 wo = random_direction(rng);
            if (spt::dot(wo, n_wo) < 0.f) wo = -wo;
            // Our own frame around n_wo (not the renderer's Frame), for the azimuth.
            const spt::Vec3 a = std::fabs(n_wo.x) < 0.9f ? spt::Vec3(1, 0, 0) : spt::Vec3(0, 1, 0);
            const spt::Vec3 b1 = spt::normalize(spt::cross(n_wo, a)), b2 = spt::cross(n_wo, b1);
            constexpr int kCos = 50, kPhi = 36, kWanted = 200'000;
            std::vector<double> cos_counts(kCos, 0.0), phi_counts(kPhi, 0.0);
            int accepted = 0, wrong_side = 0;
            while (accepted < kWanted) {
                spt::SampledWavelengths lambda = spt::SampledWavelengths::sample(rng.next_float());
                const std::optional<spt::BsdfSample> bs =
                    spt::test::sample_radiance(*mat, wo, n, lambda, rng.next_float(), rng.next_float(), rng.next_float());
                ASSERT_TRUE(bs.has_value());
                if (bs->is_delta()) continue;
                ++accepted;
                ASSERT_NEAR(spt::length(bs->wi), 1.0, 1e-5);
                const double c = spt::dot(bs->wi, n_wo);
                if (!(c > 0.0)) { ++wrong_side; continue; }
                cos_counts[std::min(kCos - 1, static_cast<int>(c * kCos))] += 1.0;
                double phi = std::atan2(double(spt::dot(bs->wi, b2)), double(spt::dot(bs->wi, b1)));
                if (phi < 0.0) phi += 2.0 * kPiD;
                phi_counts[std::min(kPhi - 1, static_cast<int>(phi / (2.0 * kPiD) * kPhi))] += 1.0;
            }
            EXPECT_EQ(wrong_side, 0) << "case " << case_index;
            std::vector<double> cos_expected(kCos), phi_expected(kPhi, double(kWanted) / kPhi);
            for (int i = 0; i < kCos; ++i)
                cos_expected[i] = kWanted * (double(i + 1) * (i + 1) - double(i) * i) / (double(kCos) * kCos);
            const spt_test::Chi2Result rc = spt_test::chi2_test(cos_counts, cos_expected);
            const spt_test::Chi2Result rp = spt_test::chi2_test(phi_counts, phi_expected);
            EXPECT_GE(rc.p_value, kAlpha) << "cos law, case " << case_index << " X2=" << rc.statistic;
            EXPECT_GE(rp.p_value, kAlpha) << "azimuth, case " << case_index << " X2=" << rp.statistic;
            // Negative control on the same histogram: uniform-in-solid-angle (cosθ uniform).
            const std::vector<double> uniform_cos(kCos, double(kWanted) / kCos);
            EXPECT_LT(spt_test::chi2_test(cos_counts, uniform_cos).p_value, kAlpha);
        }
    }
}

TEST(DiffuseBsdf, NeverReturnsHorizonOrNonFiniteDirections) {
    // ROBUSTNESS case 18: u at the ends of [0, 1) may map to the horizon (pdf 0); such samples
    // are dropped, never returned with an infinite weight.
    const spt::Material lambert = make_material("lambert", constant(0.7), constant(0.0));
    const spt::Vec3 n(0.f, 0.f, 1.f), wo = spt::normalize(spt::Vec3(0.2f, 0.1f, 0.9f));
    const float us[] = {0.f, 0x1p-24f, 0.25f, 0.5f, 0.75f, 1.f - 0x1p-24f};
    for (float u1 : us)
        for (float u2 : us) {
            spt::SampledWavelengths lambda = spt::SampledWavelengths::sample(0.5f);
            const std::optional<spt::BsdfSample> bs = spt::test::sample_radiance(lambert, wo, n, lambda, 0.5f, u1, u2);
            if (!bs) continue;
            EXPECT_TRUE(spt::is_finite(bs->wi)) << u1 << "," << u2;
            EXPECT_GT(spt::dot(bs->wi, n), 0.f) << u1 << "," << u2;
            for (int k = 0; k < spt::kLambdaCount; ++k) EXPECT_TRUE(std::isfinite(bs->weight[k]));
        }
}

TEST(BsdfSample, ExactlyTangentWoGivesNoSample) {
    // ROBUSTNESS case 18: "wo exactly tangent: no sample" (pbrt drops wo.z == 0), for every lobe.
    const spt::Vec3 n(0.f, 0.f, 1.f), wo(1.f, 0.f, 0.f);
    const spt::Material materials[] = {
        make_material("lambert", constant(0.7), constant(0.0)),
        make_material("mirror", constant(0.0), constant(1.0)),
        make_material("glass", constant(0.0), constant(0.0), constant(1.0), constant(1.5)),
    };
    for (const spt::Material& m : materials) {
        for (float u : {0.1f, 0.5f, 0.9f}) {
            spt::SampledWavelengths lambda = spt::SampledWavelengths::sample(0.5f);
            const std::optional<spt::BsdfSample> bs = spt::test::sample_radiance(m, wo, n, lambda, u, u, u);
            EXPECT_FALSE(bs.has_value()) << m.name << " u=" << u << " returned wi=(" << bs->wi.x << ","
                                         << bs->wi.y << "," << bs->wi.z << ")";
        }
    }
}

TEST(BsdfEnergy, MeanWeightEqualsAlbedoAndNeverExceedsOne) {
    // For each material and 10 directions wo (5 per side), 16384 samples at a fixed wavelength
    // set: the mean of weight·eta_scale (flux: the 1/η² radiance factor undone) equals the
    // albedo kd + ks + kt at each wavelength and is ≤ 1 (pbrt BSDFEnergyConservation,
    // ROBUSTNESS case 20). Tolerance: 4 standard errors + float rounding.
    // A dispersive glass keeps only the hero on refraction: hero albedo 1, companions F(λk).
    const spt::SpectralResolution bins{};
    const spt::SpectralResolution exact{spt::SpectralResolution::kExact};
    const spt::SpectrumSource bk7 = spt::SpectrumSource::sellmeier(1.03961212, 0.231792344, 1.01046945,
                                                                   0.00600069867, 0.0200179144, 103.560653);
    const spt::Material materials[] = {
        make_material("lambert 0.9", constant(0.9), constant(0.0)),
        make_material("mirror", constant(0.0), constant(1.0)),
        make_material("plastic", constant(0.6), constant(0.2)),
        make_material("blue plastic", spt::Spectrum(spt::SpectrumSource::gaussian(460, 35, 0.75, 0.05), bins), constant(0.15)),
        make_material("red + mirror", spt::Spectrum(spt::SpectrumSource::sigmoid(600, 12, 0.65, 0.05), bins), constant(0.3)),
        make_material("glass 1.5", constant(0.0), constant(0.0), constant(1.0), constant(1.5)),
        make_material("diffuse + water", constant(0.3), constant(0.0), constant(0.7), constant(1.33)),
        make_material("bk7", constant(0.0), constant(0.0), constant(1.0), spt::Spectrum(bk7, exact)),
    };
    Uniform rng(6);
    constexpr int kSamples = 16384;
    for (const spt::Material& m : materials) {
        for (int d = 0; d < 10; ++d) {
            const spt::Vec3 n = random_direction(rng);
            spt::Vec3 wo = random_direction(rng);
            if ((spt::dot(wo, n) > 0.f) != (d % 2 == 0)) wo = -wo;
            const spt::SampledWavelengths base = spt::SampledWavelengths::sample(rng.next_float());
            double sum[spt::kLambdaCount] = {}, sum2[spt::kLambdaCount] = {};
            for (int i = 0; i < kSamples; ++i) {
                spt::SampledWavelengths lambda = base;
                const std::optional<spt::BsdfSample> bs =
                    spt::test::sample_radiance(m, wo, n, lambda, rng.next_float(), rng.next_float(), rng.next_float());
                if (!bs) continue;  // absorbed / dropped: weight 0
                for (int k = 0; k < spt::kLambdaCount; ++k) {
                    const double w = double(bs->weight[k]) * bs->eta_scale;
                    ASSERT_TRUE(std::isfinite(w)) << m.name;
                    ASSERT_GE(w, 0.0) << m.name;
                    sum[k] += w, sum2[k] += w * w;
                }
            }
            const float cos_o = std::fabs(spt::dot(wo, n));
            for (int k = 0; k < spt::kLambdaCount; ++k) {
                const float l = base.lambda[k];
                const spt::LobeMixBsdf p = spt::test::lobes_of(m);
                double albedo = p.kd.eval(l) + p.ks.eval(l) + p.kt.eval(l);
                if (m.flags.has(spt::BsdfFlags::dispersive) && k > 0) {
                    const float eta = p.eta.eval(l);
                    albedo = spt::fresnel_dielectric(cos_o, spt::dot(wo, n) > 0.f ? eta : 1.f / eta);
                }
                const double mean = sum[k] / kSamples;
                const double se = std::sqrt(std::max(0.0, sum2[k] / kSamples - mean * mean) / kSamples);
                EXPECT_NEAR(mean, albedo, 4 * se + 1e-5) << m.name << " wo#" << d << " lambda " << l;
                EXPECT_LE(mean, 1.0 + 4 * se + 1e-5) << m.name << " wo#" << d << " lambda " << l;
            }
        }
    }
}

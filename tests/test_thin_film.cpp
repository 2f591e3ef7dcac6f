// Thin-film interference (model/bsdfs/thin_film.h) against the closed-form Airy reflectance of
// a non-absorbing film on a dielectric, written independently here with real angles:
//   R_pol = (r01² + r12² + 2·r01·r12·cos 2δ) / (1 + r01²·r12² + 2·r01·r12·cos 2δ),
// at several thicknesses, angles and wavelengths; thickness 0 is the bare substrate (glass and
// a metal); a quarter-wave film of index √n₂ cancels normal reflection; a half-wave film is
// absent; reflectance from either side of a lossless film is the same; the film BSDFs use it.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "core/rng.h"
#include "model/bsdfs/bsdf.h"

namespace {

using namespace spt;

struct Amplitudes {
    double s, p;
};

/// Fresnel amplitude coefficients (Born & Wolf sign convention) between real indices.
Amplitudes fresnel_amplitudes(double n1, double cos1, double n2, double cos2) {
    return {(n1 * cos1 - n2 * cos2) / (n1 * cos1 + n2 * cos2), (n2 * cos1 - n1 * cos2) / (n2 * cos1 + n1 * cos2)};
}

double airy(double r01, double r12, double two_delta) {
    const double c = std::cos(two_delta);
    return (r01 * r01 + r12 * r12 + 2 * r01 * r12 * c) / (1 + r01 * r01 * r12 * r12 + 2 * r01 * r12 * c);
}

/// Closed-form reflectance of film n1 (thickness d) on substrate n2 from n0, no TIR anywhere.
double closed_form(double cos0, double n0, double n1, double n2, double d_nm, double lambda_nm) {
    const double sin0 = std::sqrt(1 - cos0 * cos0);
    const double cos1 = std::sqrt(1 - std::pow(n0 * sin0 / n1, 2)), cos2 = std::sqrt(1 - std::pow(n0 * sin0 / n2, 2));
    const Amplitudes a = fresnel_amplitudes(n0, cos0, n1, cos1), b = fresnel_amplitudes(n1, cos1, n2, cos2);
    const double two_delta = 4 * 3.14159265358979323846 * n1 * d_nm * cos1 / lambda_nm;
    return 0.5 * (airy(a.s, b.s, two_delta) + airy(a.p, b.p, two_delta));
}

TEST(ThinFilm, MatchesTheClosedFormAiryResult) {
    for (double d : {0.0, 50.0, 120.0, 333.0, 800.0, 2000.0})
        for (double cos0 : {1.0, 0.8, 0.5, 0.2})
            for (double l : {400.0, 532.0, 700.0})
                for (auto [n1, n2] : {std::pair{1.33, 1.0}, std::pair{1.38, 1.52}, std::pair{2.2, 1.5}}) {
                    const double expected = closed_form(cos0, 1.0, n1, n2, d, l);
                    EXPECT_NEAR(thin_film_reflectance(float(cos0), 1.f, float(n1), {float(n2), 0.f}, float(d), float(l)),
                                expected, 2e-5 + 1e-4 * expected)
                        << "d " << d << " cos " << cos0 << " λ " << l << " n1 " << n1 << " n2 " << n2;
                }
}

TEST(ThinFilm, ZeroThicknessIsTheBareSubstrate) {
    for (double cos0 : {1.0, 0.6, 0.1}) {
        EXPECT_NEAR(thin_film_reflectance(float(cos0), 1.f, 1.8f, {1.5f, 0.f}, 0.f, 550.f), fresnel_dielectric(float(cos0), 1.5f), 1e-6);
        EXPECT_NEAR(thin_film_reflectance(float(cos0), 1.f, 1.8f, {0.2f, 3.1f}, 0.f, 550.f), fresnel_conductor(float(cos0), 0.2f, 3.1f), 1e-6);
        // From inside glass towards air, TIR included (cos 0.1 from n = 1.5 is beyond critical).
        EXPECT_NEAR(thin_film_reflectance(float(cos0), 1.5f, 1.3f, {1.f, 0.f}, 0.f, 550.f),
                    fresnel_dielectric(float(cos0), 1.f / 1.5f), 1e-6);
        // And a vanishing film tends to it continuously.
        EXPECT_NEAR(thin_film_reflectance(float(cos0), 1.f, 1.8f, {1.5f, 0.f}, 0.01f, 550.f), fresnel_dielectric(float(cos0), 1.5f), 1e-4);
    }
}

TEST(ThinFilm, InlineRootAndReflectanceMatchComplexArithmeticInDouble) {
    // The written-out principal root and the bare interface's |r|² against std::complex<double>:
    // every quadrant, the negative real axis (the root +i·√|x|: total internal reflection),
    // magnitudes over 12 decades; then metals, dielectrics from either side and grazing light.
    using D = std::complex<double>;
    spt::Rng rng(3, 1, 4);
    for (int k = 0; k < 100000; ++k) {
        const double r = std::ldexp(1.0 + rng.uniform(), static_cast<int>(rng.uniform() * 40) - 20);
        const double angle = k % 7 == 0 ? 3.141592653589793 : (2.0 * rng.uniform() - 1.0) * 3.141592653589793;
        const Complex z(static_cast<float>(r * std::cos(angle)), k % 7 == 0 ? 0.f : static_cast<float>(r * std::sin(angle)));
        const Complex got = thin_film_detail::principal_sqrt(z);
        const D expected = std::sqrt(D(z.real(), z.imag()));
        ASSERT_LE(std::abs(D(got.real(), got.imag()) - expected), 3e-7 * std::abs(expected)) << z;
    }
    EXPECT_EQ(thin_film_detail::principal_sqrt(Complex(-4.f, 0.f)), Complex(0.f, 2.f));
    EXPECT_EQ(thin_film_detail::principal_sqrt(Complex(0.f, 0.f)), Complex(0.f, 0.f));
    // root_sign −1: the planted bug (the other root, the growing wave).
    auto reference = [](float cos_i, float n0, float eta, float kappa, double root_sign) {
        const D q0(n0 * cos_i), n2(eta, kappa), n0c(n0 * n0);
        const D q2 = root_sign * std::sqrt(n2 * n2 - D(n0 * n0 * (1.0 - double(cos_i) * cos_i)));
        const D rs = (q0 - q2) / (q0 + q2), rp = (n2 * n2 * q0 - n0c * q2) / (n2 * n2 * q0 + n0c * q2);
        return std::min(1.0, 0.5 * (std::norm(rs) + std::norm(rp)));
    };
    double worst = 0;
    for (int k = 0; k < 100000; ++k) {
        const float cos_i = k % 11 == 0 ? 0.f : rng.uniform(), n0 = k % 2 ? 1.f : 1.5f;
        const float eta = 0.05f + 4.f * rng.uniform(), kappa = k % 3 == 0 ? 0.f : 8.f * rng.uniform();
        worst = std::max(worst, std::fabs(interface_reflectance(cos_i, n0, {eta, kappa}) - reference(cos_i, n0, eta, kappa, 1.0)));
    }
    // The float rounding of sin² θ: near η = 1 at grazing angles the reflectance is steep in
    // it (1.4e-5 there, as std::complex<float> gave).
    EXPECT_LT(worst, 3e-5);
    EXPECT_GT(std::fabs(interface_reflectance(0.7f, 1.f, {0.2f, 3.f}) - reference(0.7f, 1.f, 0.2f, 3.f, -1.0)), 0.01);
}

TEST(ThinFilm, QuarterAndHalfWaveFilms) {
    const double n2 = 1.69, n1 = std::sqrt(n2), l = 550;
    EXPECT_NEAR(thin_film_reflectance(1.f, 1.f, float(n1), {float(n2), 0.f}, float(l / (4 * n1)), float(l)), 0.0, 1e-6);
    EXPECT_NEAR(thin_film_reflectance(1.f, 1.f, 1.45f, {float(n2), 0.f}, float(l / (2 * 1.45)), float(l)),
                fresnel_dielectric(1.f, float(n2)), 1e-6);
}

TEST(ThinFilm, LosslessFilmReflectsAlikeFromBothSides) {
    // Glass (1.5) with an MgF₂-like film (1.38): R from air at θ0 equals R from glass at θ2.
    for (double cos0 : {0.95, 0.6, 0.3}) {
        const double sin2 = std::sqrt(1 - cos0 * cos0) / 1.5, cos2 = std::sqrt(1 - sin2 * sin2);
        const float d = 180.f, l = 480.f;
        EXPECT_NEAR(thin_film_reflectance(float(cos0), 1.f, 1.38f, {1.5f, 0.f}, d, l),
                    thin_film_reflectance(float(cos2), 1.5f, 1.38f, {1.f, 0.f}, d, l), 1e-5);
    }
}

TEST(ThinFilm, FilmBsdfsUseTheAiryReflectance) {
    const Spectrum soap(SpectrumSource::constant(1.33), {});
    const ThinSheetBsdf bubble{{soap, 450.f}};
    SampledWavelengths lambda{};
    lambda.lambda = {420.f, 510.f, 600.f, 690.f};
    lambda.pdf = {1, 1, 1, 1};
    const SampledSpectrum r = bubble.reflectance(0.8f, lambda);
    for (int k = 0; k < kLambdaCount; ++k) EXPECT_NEAR(r[k], closed_form(0.8, 1, 1.33, 1, 450, lambda.lambda[k]), 1e-5);
    // A smooth coated glass reflects R and transmits 1 − R into the refracted direction.
    const DielectricBsdf coated{Spectrum(SpectrumSource::constant(1.5), {}), {}, {Spectrum(SpectrumSource::constant(1.38), {}), 100.f}};
    const Vec3 n{0, 0, 1};
    const Vec3 wo = normalize(Vec3{0.6f, 0.f, 0.8f});
    for (float u : {0.001f, 0.999f}) {
        SampledWavelengths lw = lambda;
        const auto bs = coated.sample(wo, n, lw, u, 0.5f, 0.5f, TransportMode::importance);
        ASSERT_TRUE(bs);
        double p_r = 0;
        for (int k = 0; k < kLambdaCount; ++k) p_r += closed_form(0.8, 1, 1.38, 1.5, 100, lambda.lambda[k]) / 4;
        for (int k = 0; k < kLambdaCount; ++k) {
            const double rk = closed_form(0.8, 1, 1.38, 1.5, 100, lambda.lambda[k]);
            EXPECT_NEAR(bs->weight[k], bs->flags.has(BsdfFlags::reflection) ? rk / p_r : (1 - rk) / (1 - p_r), 1e-4);
        }
    }
}

}  // namespace

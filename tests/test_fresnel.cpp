// Dielectric interface: Fresnel reflectance, Snell refraction and the sample weights of the
// smooth-dielectric lobe, against closed forms and the hard cases of ROBUSTNESS.md §4 and §7
// (cases 9–11, 21). Fresnel is evaluated in float32; tolerances state the rounding budget.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <random>

#include "model/bsdfs/bsdf.h"
#include "model/bsdfs/fresnel.h"
#include "model/material.h"
#include "spectral/sampled.h"
#include "spectral/spectrum.h"
#include "uniform.h"

namespace {

constexpr double kPiD = 3.14159265358979323846;
/// float32 unit roundoff.
constexpr double kEpsF = 0x1p-24;

double radians(double deg) { return deg * kPiD / 180.0; }

/// Double-precision reference: unpolarised Fresnel reflectance, eta = n_t/n_i.
double fresnel_reference(double cos_i, double eta) {
    const double sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0) return 1.0;
    const double cos_t = std::sqrt(1.0 - sin2_t);
    const double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    const double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5 * (rp * rp + rs * rs);
}

/// Float32 budget for F: ~10 ulp of the arithmetic, plus the amplification near the critical
/// angle, where 1 − sin²θt (absolute error ~2ε) is divided by cos²θt before the square root.
double fresnel_tolerance(double cos_i, double eta) {
    const double sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    const double cos_t = std::sqrt(std::max(1.0 - sin2_t, 1e-300));
    return 16.0 * kEpsF * (1.0 + 1.0 / cos_t);
}

float fresnel_deg(double deg, double eta) {
    return spt::fresnel_dielectric(static_cast<float>(std::cos(radians(deg))), static_cast<float>(eta));
}

spt::Material glass(const spt::SpectrumSource& eta) {
    spt::Material m;
    m.name = "glass";
    spt::LobeMixBsdf b;
    b.kt = spt::Spectrum(spt::SpectrumSource::constant(1.0), spt::SpectralResolution{});
    b.eta = spt::Spectrum(eta, spt::SpectralResolution{spt::SpectralResolution::kExact});
    m.bsdf = std::move(b);
    m.flags = spt::bsdf_flags(m.bsdf);
    return m;
}

spt::SpectrumSource bk7() {
    return spt::SpectrumSource::sellmeier(1.03961212, 0.231792344, 1.01046945, 0.00600069867,
                                          0.0200179144, 103.560653);
}

/// Direction at angle theta (degrees) from +z in the xz plane, pointing away from the surface.
spt::Vec3 dir_deg(double deg, bool above = true) {
    const double t = radians(deg);
    return {static_cast<float>(std::sin(t)), 0.f, static_cast<float>(above ? std::cos(t) : -std::cos(t))};
}

using spt_test::Uniform;

}  // namespace

// ---------------------------------------------------------------- Fresnel reflectance

TEST(Fresnel, NormalIncidenceMatchesClosedForm) {
    // ROBUSTNESS §4: 0.020059 (1.33), 0.04 (1.5), 0.172395 (2.42), 0.36 (4).
    struct Case { double n, documented; };
    for (const Case& c : {Case{1.33, 0.020059}, Case{1.5, 0.04}, Case{2.42, 0.172395}, Case{4.0, 0.36}}) {
        const double expected = std::pow((c.n - 1.0) / (c.n + 1.0), 2.0);
        EXPECT_NEAR(expected, c.documented, 5e-7);
        // Entering and leaving give the same reflectance at normal incidence.
        EXPECT_NEAR(spt::fresnel_dielectric(1.f, float(c.n)), expected, 16 * kEpsF) << c.n;
        EXPECT_NEAR(spt::fresnel_dielectric(1.f, float(1.0 / c.n)), expected, 16 * kEpsF) << c.n;
    }
    // η = 1: no interface, no reflection at any angle below grazing.
    for (double deg : {0.0, 30.0, 60.0, 89.0}) EXPECT_NEAR(fresnel_deg(deg, 1.0), 0.0, 1e-7) << deg;
}

TEST(Fresnel, ObliqueValuesFromOutside) {
    // η = 1.5 (ROBUSTNESS §7 case 9): 0.0502399 at 45°, 0.3877044 at 80°, 1 at grazing.
    // References have 7 decimals (±5e-8); float32 evaluation adds ≤ 16 ulp·(1 + 1/cosθt).
    EXPECT_NEAR(fresnel_deg(45.0, 1.5), 0.0502399, 5e-8 + fresnel_tolerance(std::cos(radians(45)), 1.5));
    EXPECT_NEAR(fresnel_deg(80.0, 1.5), 0.3877044, 5e-8 + fresnel_tolerance(std::cos(radians(80)), 1.5));
    EXPECT_EQ(spt::fresnel_dielectric(0.f, 1.5f), 1.f);
    // Monotonic increase towards grazing incidence (η > 1 from outside: no Brewster dip in
    // the unpolarised average below the Brewster angle 56.31°, and rising after it).
    float prev = spt::fresnel_dielectric(1.f, 1.5f);
    for (int deg = 60; deg <= 89; ++deg) {
        const float f = fresnel_deg(deg, 1.5);
        EXPECT_GT(f, prev) << deg;
        prev = f;
    }
}

TEST(Fresnel, FromInsideAndTotalInternalReflection) {
    // η = 1/1.5 (glass to air): 0.3797513 at 41.0°; critical angle asin(1/1.5) = 41.8103149°.
    const double cos41 = std::cos(radians(41.0));
    EXPECT_NEAR(fresnel_deg(41.0, 1.0 / 1.5), 0.3797513, 5e-8 + fresnel_tolerance(cos41, 1.0 / 1.5));
    EXPECT_LT(fresnel_deg(41.81, 1.0 / 1.5), 1.f);
    for (double deg : {41.8104, 41.85, 42.0, 50.0, 70.0, 89.9, 90.0})
        EXPECT_EQ(fresnel_deg(deg, 1.0 / 1.5), 1.f) << deg;
    // η = 1/4 (diamond-like index 4 to air): F(0°) = 0.36, TIR above asin(1/4) = 14.4775122°.
    EXPECT_NEAR(spt::fresnel_dielectric(1.f, 0.25f), 0.36, 16 * kEpsF);
    EXPECT_LT(fresnel_deg(14.477, 0.25), 1.f);
    for (double deg : {14.4776, 14.5, 20.0, 45.0, 80.0}) EXPECT_EQ(fresnel_deg(deg, 0.25), 1.f) << deg;
}

TEST(Fresnel, MatchesDoublePrecisionAcrossAngles) {
    // Every angle 0–89.9° for several indices, both sides, against the double formula with the
    // float32 error budget of fresnel_tolerance (which grows only near the critical angle).
    for (double eta : {1.1, 1.33, 1.5, 2.42, 4.0}) {
        for (double deg = 0.0; deg < 90.0; deg += 0.1) {
            const float ci = static_cast<float>(std::cos(radians(deg)));
            EXPECT_NEAR(spt::fresnel_dielectric(ci, float(eta)), fresnel_reference(ci, float(eta)),
                        fresnel_tolerance(ci, float(eta)))
                << "eta=" << eta << " theta=" << deg;
            const double inv = 1.0 / eta;
            const float inv_f = static_cast<float>(inv);
            const double crit = std::asin(double(inv_f)) * 180.0 / kPiD;
            if (deg > crit - 0.05 && deg < crit + 0.05) continue;  // rounding of the cut-off itself
            EXPECT_NEAR(spt::fresnel_dielectric(ci, inv_f), fresnel_reference(ci, inv_f),
                        fresnel_tolerance(ci, inv_f))
                << "eta=1/" << eta << " theta=" << deg;
        }
    }
}

TEST(Fresnel, ReciprocalAcrossTheInterface) {
    // F(θi, η) = F(θt, 1/η): the same interface seen from the other side (Stokes relations).
    for (double eta : {1.33, 1.5, 2.42}) {
        for (double deg = 0.0; deg <= 85.0; deg += 5.0) {
            const double ci = std::cos(radians(deg));
            const double ct = std::sqrt(1.0 - (1.0 - ci * ci) / (eta * eta));
            const float a = spt::fresnel_dielectric(float(ci), float(eta));
            const float b = spt::fresnel_dielectric(float(ct), float(1.0 / eta));
            EXPECT_NEAR(a, b, fresnel_tolerance(ci, eta) + fresnel_tolerance(ct, 1.0 / eta))
                << "eta=" << eta << " theta=" << deg;
        }
    }
}

// ---------------------------------------------------------------- refraction

TEST(Refract, SnellsLawUnitLengthOppositeSide) {
    // Random wi and normals, η ∈ [1, 2.5] entering and 1/η leaving (ROBUSTNESS case 10).
    Uniform rng(11);
    int refracted = 0, tir = 0;
    for (int i = 0; i < 20000; ++i) {
        // Random unit normal and a random direction on its side.
        const double z = 1.0 - 2.0 * rng.next_double(), phi = 2.0 * kPiD * rng.next_double();
        const double r = std::sqrt(1.0 - z * z);
        const spt::Vec3 n = spt::normalize(spt::Vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)));
        spt::Vec3 w;
        do {
            const double z2 = 1.0 - 2.0 * rng.next_double(), p2 = 2.0 * kPiD * rng.next_double();
            const double r2 = std::sqrt(1.0 - z2 * z2);
            w = spt::normalize(spt::Vec3(float(r2 * std::cos(p2)), float(r2 * std::sin(p2)), float(z2)));
            if (spt::dot(w, n) < 0.f) w = -w;
        } while (!(spt::dot(w, n) > 1e-4f));
        const double eta_in = 1.0 + 1.5 * rng.next_double();
        const float eta = static_cast<float>(i % 2 ? eta_in : 1.0 / eta_in);

        const double cos_i = spt::dot(w, n);
        const double sin_i = std::sqrt(std::max(0.0, 1.0 - cos_i * cos_i));
        const double sin2_t = sin_i * sin_i / (double(eta) * eta);
        const std::optional<spt::Vec3> wt = spt::refract(w, n, eta);
        if (std::fabs(sin2_t - 1.0) < 1e-5) continue;  // within rounding of the TIR cut-off
        if (sin2_t > 1.0) {
            EXPECT_FALSE(wt.has_value()) << "TIR expected, sin2_t=" << sin2_t;
            ++tir;
            continue;
        }
        ASSERT_TRUE(wt.has_value()) << "sin2_t=" << sin2_t;
        ++refracted;
        ASSERT_TRUE(spt::is_finite(*wt));
        EXPECT_NEAR(spt::length(*wt), 1.0, 1e-6);
        const double cos_t = -spt::dot(*wt, n);
        EXPECT_GT(cos_t, 0.0) << "transmitted direction on the incident side";
        // Snell: n_i sinθi = n_t sinθt, i.e. sinθi = η sinθt.
        const double sin_t = spt::length(spt::cross(*wt, n));
        EXPECT_NEAR(sin_i, eta * sin_t, 1e-5);
        // Coplanar with w and n, tangential part reversed: wt_tan = −w_tan/η.
        for (int k = 0; k < 3; ++k) {
            const double w_tan = w[k] - cos_i * n[k];
            const double wt_tan = (*wt)[k] + cos_t * n[k];
            EXPECT_NEAR(wt_tan, -w_tan / eta, 1e-5) << "component " << k;
        }
    }
    EXPECT_GT(refracted, 10000);
    EXPECT_GT(tir, 1000);
}

TEST(Refract, TotalInternalReflectionReturnsNullopt) {
    const spt::Vec3 n(0.f, 0.f, 1.f);
    for (double deg : {41.82, 42.0, 60.0, 89.0, 90.0})
        EXPECT_FALSE(spt::refract(dir_deg(deg), n, float(1.0 / 1.5)).has_value()) << deg;
    for (double deg : {14.48, 30.0, 80.0}) EXPECT_FALSE(spt::refract(dir_deg(deg), n, 0.25f).has_value()) << deg;
    // Just below the critical angle, a grazing refracted direction: sinθt = 1.5·sin 41.8°.
    const std::optional<spt::Vec3> wt = spt::refract(dir_deg(41.8), n, float(1.0 / 1.5));
    ASSERT_TRUE(wt.has_value());
    const double sin_t = 1.5 * std::sin(radians(41.8));
    EXPECT_NEAR(-wt->z, std::sqrt(1.0 - sin_t * sin_t), 2e-4);  // cosθt = 0.00582; ε/cosθt amplification
    // Normal incidence passes straight through, whatever η.
    for (float eta : {0.25f, 0.6667f, 1.f, 1.5f, 4.f}) {
        const std::optional<spt::Vec3> s = spt::refract(n, n, eta);
        ASSERT_TRUE(s.has_value());
        EXPECT_EQ(*s, spt::Vec3(0.f, 0.f, -1.f)) << eta;
    }
}

TEST(Refract, ReflectancePlusTransmittanceIsOne) {
    // Energy: T from the Fresnel amplitude transmission coefficients with the refracted cosθt,
    //   T = (η cosθt/cosθi)·(t_s² + t_p²)/2, t_s = 2cosθi/(cosθi + η cosθt), t_p = 2cosθi/(η cosθi + cosθt),
    // must complement F. Tolerance: float F (≤ fresnel_tolerance) plus cosθt from refract (few ulp).
    const spt::Vec3 n(0.f, 0.f, 1.f);
    for (double eta_in : {1.33, 1.5, 2.42, 4.0}) {
        for (double eta : {eta_in, 1.0 / eta_in}) {
            const double crit = eta < 1.0 ? std::asin(eta) * 180.0 / kPiD : 90.0;
            for (double deg = 0.0; deg < std::min(89.0, crit - 1.0); deg += 1.0) {
                const spt::Vec3 w = dir_deg(deg);
                const std::optional<spt::Vec3> wt = spt::refract(w, n, float(eta));
                ASSERT_TRUE(wt.has_value()) << eta << " " << deg;
                const double ci = w.z, ct = -wt->z;
                const double ts = 2 * ci / (ci + eta * ct), tp = 2 * ci / (eta * ci + ct);
                const double T = eta * ct / ci * 0.5 * (ts * ts + tp * tp);
                const float F = spt::fresnel_dielectric(w.z, float(eta));
                EXPECT_NEAR(F + T, 1.0, 2 * fresnel_tolerance(ci, eta) + 1e-6)
                    << "eta=" << eta << " theta=" << deg;
            }
        }
    }
}

TEST(Refract, Bk7DispersionAngles) {
    // ROBUSTNESS §21: BK7 at 60° incidence refracts to 34.452° at 400 nm and 34.915° at 700 nm
    // (3 decimals: ±5e-4°; float directions add ~1e-5°).
    const spt::SpectrumSource s = bk7();
    const spt::Vec3 n(0.f, 0.f, 1.f);
    for (auto [lambda, expected] : {std::pair{400.0, 34.452}, std::pair{700.0, 34.915}}) {
        const std::optional<spt::Vec3> wt = spt::refract(dir_deg(60.0), n, float(s.eval(lambda)));
        ASSERT_TRUE(wt.has_value());
        EXPECT_NEAR(std::acos(double(-wt->z)) * 180.0 / kPiD, expected, 6e-4) << lambda << " nm";
    }
}

// ---------------------------------------------------------------- dielectric BSDF samples

TEST(DielectricBsdf, NormalIncidenceProbabilitiesAndWeights) {
    // ROBUSTNESS case 11 (radiance mode): reflection with p = F = 0.04 and weight 1; refraction
    // with p = 0.96 and weight 1/η² = 0.444444 entering, η² = 2.25 leaving.
    const spt::Material m = glass(spt::SpectrumSource::constant(1.5));
    const spt::Vec3 n(0.f, 0.f, 1.f);
    constexpr int kSweep = 100000;  // u1 = (i + ½)/N: the reflection count is F·N to ±1
    for (bool entering : {true, false}) {
        const spt::Vec3 wo(0.f, 0.f, entering ? 1.f : -1.f);
        const float expected_t = entering ? 1.f / 2.25f : 2.25f;
        int reflections = 0;
        for (int i = 0; i < kSweep; ++i) {
            spt::SampledWavelengths lambda = spt::SampledWavelengths::sample(0.3f);
            const float u1 = (static_cast<float>(i) + 0.5f) / kSweep;
            const std::optional<spt::BsdfSample> bs = spt::bsdf_sample(m.bsdf, wo, n, lambda, 0.5f, u1, 0.5f, spt::TransportMode::radiance);
            ASSERT_TRUE(bs.has_value()) << "u1=" << u1;
            EXPECT_TRUE(bs->is_delta());
            EXPECT_FALSE(lambda.secondary_terminated()) << "constant IOR must keep the companions";
            if (bs->wi.z * wo.z > 0.f) {  // reflected
                ++reflections;
                EXPECT_EQ(bs->wi, wo);
                for (int k = 0; k < spt::kLambdaCount; ++k) ASSERT_NEAR(bs->weight[k], 1.f, 1e-6f);
            } else {
                EXPECT_EQ(bs->wi, -wo);
                for (int k = 0; k < spt::kLambdaCount; ++k)
                    ASSERT_NEAR(bs->weight[k], expected_t, 1e-6f * expected_t) << "entering=" << entering;
                ASSERT_NEAR(bs->eta_scale, entering ? 2.25f : 1.f / 2.25f, 1e-6f);
            }
        }
        EXPECT_NEAR(double(reflections) / kSweep, 0.04, 1.0 / kSweep + 16 * kEpsF) << "entering=" << entering;
    }
    EXPECT_NEAR(1.f / 2.25f, 0.444444f, 1e-6f);
}

TEST(DielectricBsdf, ReflectionShareAt80Degrees) {
    // 1e6 independent samples: binomial share 0.38770 ± 0.00146 (3σ, σ = √(F(1−F)/N) = 4.87e-4),
    // and the refracted angle θt = 41.03641° (ROBUSTNESS case 9).
    const spt::Material m = glass(spt::SpectrumSource::constant(1.5));
    const spt::Vec3 n(0.f, 0.f, 1.f), wo = dir_deg(80.0);
    const double F = 0.387704354691473;
    constexpr int kSamples = 1'000'000;
    Uniform rng(80);
    int reflections = 0;
    const double cos_t = std::cos(radians(41.03641));
    for (int i = 0; i < kSamples; ++i) {
        spt::SampledWavelengths lambda = spt::SampledWavelengths::sample(rng.next_float());
        const std::optional<spt::BsdfSample> bs =
            spt::bsdf_sample(m.bsdf, wo, n, lambda, rng.next_float(), rng.next_float(), rng.next_float(), spt::TransportMode::radiance);
        ASSERT_TRUE(bs.has_value());
        if (bs->wi.z > 0.f) {
            ++reflections;
        } else if (i % 1000 == 0) {
            EXPECT_NEAR(-bs->wi.z, cos_t, 1e-6);
            EXPECT_NEAR(bs->weight[0], 1.f / 2.25f, 1e-6f);
        }
    }
    const double sigma = std::sqrt(F * (1 - F) / kSamples);
    EXPECT_NEAR(sigma, 0.00146 / 3, 1e-6);
    EXPECT_NEAR(double(reflections) / kSamples, 0.38770, 0.00146);
}

TEST(DielectricBsdf, DispersiveRefractionKeepsOnlyTheHero) {
    // BK7 at 60°: the refraction branch terminates the companions (pdf 0, hero pdf / 4, weight
    // 0) and bends the hero by its own index; the reflection branch keeps all four wavelengths
    // with weights F(λk)/F(λ0) (SPECTRAL.md §2.1).
    const spt::SpectrumSource src = bk7();
    const spt::Material m = glass(src);
    ASSERT_TRUE(m.flags.has(spt::BsdfFlags::dispersive));
    const spt::Vec3 n(0.f, 0.f, 1.f), wo = dir_deg(60.0);
    spt::SampledWavelengths base;
    base.lambda = {400.f, 500.f, 600.f, 700.f};
    base.pdf = {spt::visible_wavelength_pdf(400.f), spt::visible_wavelength_pdf(500.f),
                spt::visible_wavelength_pdf(600.f), spt::visible_wavelength_pdf(700.f)};
    const float cos_o = wo.z;
    const float f0 = spt::fresnel_dielectric(cos_o, float(src.eval(400.0)));

    spt::SampledWavelengths lr = base;
    const std::optional<spt::BsdfSample> r = spt::bsdf_sample(m.bsdf, wo, n, lr, 0.5f, 0.f, 0.5f, spt::TransportMode::radiance);
    ASSERT_TRUE(r.has_value());
    EXPECT_FALSE(lr.secondary_terminated());
    EXPECT_EQ(lr.pdf, base.pdf);
    EXPECT_NEAR(r->wi.x, -wo.x, 1e-7f);
    EXPECT_NEAR(r->wi.z, wo.z, 1e-7f);
    for (int k = 0; k < 4; ++k) {
        const float fk = spt::fresnel_dielectric(cos_o, float(src.eval(base.lambda[k])));
        EXPECT_NEAR(r->weight[k], fk / f0, 1e-6f) << "lambda " << base.lambda[k];
    }

    spt::SampledWavelengths lt = base;
    const std::optional<spt::BsdfSample> t = spt::bsdf_sample(m.bsdf, wo, n, lt, 0.5f, 0.999f, 0.5f, spt::TransportMode::radiance);
    ASSERT_TRUE(t.has_value());
    EXPECT_TRUE(lt.secondary_terminated());
    EXPECT_EQ(lt.pdf[0], base.pdf[0] / 4.f);
    for (int k = 1; k < 4; ++k) {
        EXPECT_EQ(lt.pdf[k], 0.f);
        EXPECT_EQ(t->weight[k], 0.f);
    }
    const double eta0 = src.eval(400.0);
    EXPECT_NEAR(t->weight[0], 1.0 / (eta0 * eta0), 1e-6);
    EXPECT_NEAR(std::acos(double(-t->wi.z)) * 180.0 / kPiD, 34.452, 6e-4);
}

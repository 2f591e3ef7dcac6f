// The contract of model/bsdfs/bsdf.h, checked for every type of the closed set (and the
// lobe mix in its forms: plastic, clear and dispersive glass, all three lobes; conductors,
// dielectrics and coated plastics smooth and rough, with and without thin films, dispersive
// rough glass, plastics with a dispersive coat, the soap-bubble sheet): flags agree
// with what sample() produces; a non-delta sample's pdf is pdf()'s value and its weight is
// eval/pdf; the non-delta directions follow pdf() (chi-square); eval is reciprocal (its
// importance mode the adjoint of its radiance mode); the mean
// weight (the albedo) is at most 1, and exactly 1 for white surfaces (furnace); importance
// transport drops refraction's (η_i/η_t)².
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "chi2.h"
#include "cone_histogram.h"
#include "core/frame.h"
#include "model/bsdfs/bsdf.h"
#include "test_scenes.h"

namespace {

using namespace spt;
constexpr double kPi = std::numbers::pi;

Spectrum constant(double v) { return spt::test::constant_spectrum(v); }
Spectrum exact(const SpectrumSource& s) { return Spectrum(s, {SpectralResolution::kExact}); }

struct Case {
    std::string name;
    Bsdf bsdf;
    bool constant_spectra;  ///< lobe choice at the hero = over the live wavelengths
    /// Relative tolerance of eval against sampling: microfacet types recompute the half
    /// vector from a float direction, smooth ones are exact to rounding.
    double tolerance = 1e-5;
};

std::vector<Case> cases() {
    const SpectrumSource bk7 = SpectrumSource::sellmeier(1.03961212, 0.231792344, 1.01046945, 0.00600069867,
                                                        0.0200179144, 103.560653);
    return {
        {"diffuse", DiffuseBsdf{constant(0.7)}, true},
        {"diffuse spectral", DiffuseBsdf{exact(SpectrumSource::gaussian(460, 35, 0.75, 0.05))}, false},
        {"plastic", LobeMixBsdf{constant(0.6), constant(0.25), {}, {}}, true},
        {"glass", LobeMixBsdf{{}, {}, constant(1.0), constant(1.5)}, true},
        {"dispersive glass", LobeMixBsdf{{}, {}, constant(1.0), exact(bk7)}, true},
        {"three lobes", LobeMixBsdf{constant(0.3), constant(0.2), constant(0.4), constant(1.33)}, true},
        {"smooth gold", ConductorBsdf{constant(0.2), constant(3.0), {}, {}}, true},
        {"rough conductor", ConductorBsdf{constant(0.2), constant(3.0), {0.3f}, {}}, true, 1e-3},
        {"rough conductor with film", ConductorBsdf{constant(1.2), constant(2.0), {0.2f}, {constant(1.38), 350.f}}, false, 1e-3},
        {"smooth dielectric", DielectricBsdf{constant(1.5), {}, {}}, true},
        {"rough dielectric", DielectricBsdf{constant(1.5), {0.3f}, {}}, true, 1e-3},
        {"rough dispersive glass", DielectricBsdf{exact(bk7), {0.2f}, {}}, false, 1e-3},
        {"smooth dielectric with film", DielectricBsdf{constant(1.33), {}, {constant(1.5), 300.f}}, false},
        {"rough dielectric with film", DielectricBsdf{constant(1.5), {0.25f}, {constant(1.38), 200.f}}, false, 1e-3},
        {"smooth coated plastic", make_plastic(constant(0.5), 1.5f, 0.f), true, 1e-3},
        {"rough coated plastic", make_plastic(constant(0.5), 1.5f, 0.2f), true, 1e-3},
        // A coat index varying with λ: one lobe choice for all λ, so eval/pdf per lane.
        {"smooth dispersive-coat plastic", make_plastic(constant(0.5), exact(bk7), 0.f), true, 1e-3},
        {"rough dispersive-coat plastic", make_plastic(exact(SpectrumSource::gaussian(460, 35, 0.75, 0.05)),
                                                       exact(SpectrumSource::cauchy(1.45, 0.1)), 0.2f), true, 1e-3},
        {"soap bubble", ThinSheetBsdf{{constant(1.33), 400.f}}, false},
    };
}

const Vec3 kNormal = normalize(Vec3(0.3f, -0.5f, 0.8f));

Vec3 about(const Vec3& n, double cos_theta, double phi) {
    const double s = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
    return normalize(Frame(n).to_world({float(s * std::cos(phi)), float(s * std::sin(phi)), float(cos_theta)}));
}

/// Outgoing directions on both sides, grazing to normal.
std::vector<Vec3> outgoing() {
    std::vector<Vec3> w;
    for (double c : {0.95, 0.5, 0.1})
        for (double side : {1.0, -1.0}) w.push_back(about(kNormal * float(side), c, 1.3));
    return w;
}

SampledWavelengths wavelengths(float u) { return SampledWavelengths::sample(u); }

TEST(BsdfContract, FlagsPdfAndWeightAgreeWithSampling) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (const Case& c : cases()) {
        const BsdfFlags flags = bsdf_flags(c.bsdf);
        for (const Vec3& wo : outgoing()) {
            int produced = 0;
            for (int i = 0; i < 4000; ++i) {
                SampledWavelengths lambda = wavelengths(u(rng));
                const auto bs = bsdf_sample(c.bsdf, wo, kNormal, lambda, u(rng), u(rng), u(rng), TransportMode::radiance);
                if (!bs) continue;
                ++produced;
                ASSERT_FALSE(flags.is_black()) << c.name;
                if (bs->is_delta()) {
                    ASSERT_TRUE(flags.has(BsdfFlags::delta)) << c.name;
                    ASSERT_EQ(bs->pdf, 0.f) << c.name;
                    continue;
                }
                ASSERT_TRUE(flags.has(BsdfFlags::non_delta)) << c.name;
                const float pdf = bsdf_pdf(c.bsdf, wo, bs->wi, kNormal, lambda.lambda[0]);
                ASSERT_NEAR(bs->pdf, pdf, c.tolerance * 10 * pdf) << c.name;
                if (!c.constant_spectra) continue;
                // weight = eval/density; with constant spectra the density is pdf().
                const SampledSpectrum f = bsdf_eval(c.bsdf, wo, bs->wi, kNormal, lambda, TransportMode::radiance);
                for (int k = 0; k < kLambdaCount; ++k)
                    ASSERT_NEAR(bs->weight[k], f[k] / pdf, 10 * c.tolerance * f[k] / pdf) << c.name;
            }
            EXPECT_GT(produced, 0) << c.name;
        }
    }
}

TEST(BsdfContract, BlackHasNoLobeAndEvaluatesToZero) {
    // A black BSDF (a pure emitter's surface) is never sampled: paths end there.
    const Bsdf black = DiffuseBsdf{};
    EXPECT_TRUE(bsdf_flags(black).is_black());
    const SampledWavelengths lambda = wavelengths(0.5f);
    const Vec3 wo = about(kNormal, 0.7, 0.1), wi = about(kNormal, 0.4, 2.0);
    EXPECT_TRUE(bsdf_eval(black, wo, wi, kNormal, lambda, TransportMode::radiance).is_zero());
}

TEST(BsdfContract, NonDeltaDirectionsFollowPdf) {
    // Cells of equal solid angle over the whole sphere (cos θ about n, φ); delta samples and
    // failures go to one more cell whose expected count is 1 − ∫pdf. The hero's lobe choice
    // is the sampling probability only with constant spectra: those cases are tested.
    constexpr int kN = 200000;
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (const Case& c : cases()) {
        if (!c.constant_spectra) continue;
        const Vec3 wo = about(kNormal, 0.6, 0.4);
        const SampledWavelengths lambda0 = wavelengths(0.3f);
        spt_test::ConeHistogram histogram(kNormal, -1.0, 16, 16);
        const std::vector<double> expected = histogram.expected(
            [&](const Vec3& wi) { return bsdf_pdf(c.bsdf, wo, wi, kNormal, lambda0.lambda[0]); }, kN, 4);
        for (int s = 0; s < kN; ++s) {
            SampledWavelengths lambda = lambda0;
            const auto bs = bsdf_sample(c.bsdf, wo, kNormal, lambda, u(rng), u(rng), u(rng), TransportMode::radiance);
            if (bs && !bs->is_delta()) histogram.add(bs->wi);
            else histogram.add_outside();
        }
        const std::vector<double>& observed = histogram.observed();
        const spt_test::Chi2Result r = spt_test::chi2_test(observed, expected);
        EXPECT_GT(r.p_value, 1e-5) << c.name << ": X² = " << r.statistic << ", dof " << r.dof;
        EXPECT_EQ(r.observed_in_empty, 0) << c.name;
    }
}

TEST(BsdfContract, EvalIsReciprocal) {
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const SampledWavelengths lambda = wavelengths(0.6f);
    for (const Case& c : cases())
        for (int i = 0; i < 500; ++i) {
            const Vec3 a = about(kNormal, 2 * u(rng) - 1, 2 * kPi * u(rng));
            const Vec3 b = about(kNormal, 2 * u(rng) - 1, 2 * kPi * u(rng));
            // f(a, b)|cos b| / |cos b| = f(b, a)|cos a| / |cos a|.
            const double ca = std::fabs(dot(a, kNormal)), cb = std::fabs(dot(b, kNormal));
            if (ca < 1e-3 || cb < 1e-3) continue;
            // Importance mode is the adjoint f*(a, b) = f(b, a): the same as radiance mode
            // where f is symmetric, without refraction's 1/η'² where it is not.
            const SampledSpectrum fab = bsdf_eval(c.bsdf, a, b, kNormal, lambda, TransportMode::importance);
            const SampledSpectrum fba = bsdf_eval(c.bsdf, b, a, kNormal, lambda, TransportMode::radiance);
            for (int k = 0; k < kLambdaCount; ++k)
                ASSERT_NEAR(fab[k] / cb, fba[k] / ca, c.tolerance * (1 + fab[k] / cb)) << c.name;
        }
}

/// Mean weight per wavelength over samples (the directional albedo), in radiance or importance.
SampledSpectrum mean_weight(const Bsdf& bsdf, const Vec3& wo, TransportMode mode, int n, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    SampledSpectrum sum(0.f);
    const SampledWavelengths lambda0 = wavelengths(0.45f);
    for (int i = 0; i < n; ++i) {
        SampledWavelengths lambda = lambda0;
        const auto bs = bsdf_sample(bsdf, wo, kNormal, lambda, u(rng), u(rng), u(rng), mode);
        if (!bs) continue;
        // (A dispersive refraction keeps the hero lane alone: per lane the mean stays the
        // albedo of that wavelength's choice, at most 1.)
        const SampledSpectrum w = bs->weight;
        sum += w;
    }
    return sum / float(n);
}

TEST(BsdfContract, EnergyAtMostOneAndWhiteFurnaceExactlyOne) {
    for (const Case& c : cases())
        for (const Vec3& wo : outgoing()) {
            const SampledSpectrum albedo = mean_weight(c.bsdf, wo, TransportMode::importance, 20000, 11);
            for (int k = 0; k < kLambdaCount; ++k) EXPECT_LE(albedo[k], 1.0 + 0.03) << c.name << " lane " << k;
        }
    // White furnace: a white Lambertian and clear glass (importance: no radiance scaling)
    // return every sample with weight 1.
    for (const Bsdf& white : {Bsdf{DiffuseBsdf{constant(1.0)}}, Bsdf{LobeMixBsdf{{}, {}, constant(1.0), constant(1.5)}}})
        for (const Vec3& wo : outgoing()) {
            const SampledSpectrum a = mean_weight(white, wo, TransportMode::importance, 5000, 13);
            for (int k = 0; k < kLambdaCount; ++k) EXPECT_NEAR(a[k], 1.0, 1e-5);
        }
}

TEST(BsdfContract, RefractionScalesRadianceButNotImportance) {
    const LobeMixBsdf glass{{}, {}, constant(1.0), constant(1.5)};
    const Vec3 wo = about(kNormal, 0.8, 0.2);  // entering from outside
    for (int i = 0; i < 64; ++i) {
        const float u = (i + 0.5f) / 64;
        SampledWavelengths l1 = wavelengths(0.3f), l2 = l1;
        const auto r = glass.sample(wo, kNormal, l1, 0.5f, u, 0.5f, TransportMode::radiance);
        const auto m = glass.sample(wo, kNormal, l2, 0.5f, u, 0.5f, TransportMode::importance);
        ASSERT_TRUE(r && m);
        ASSERT_EQ(r->wi, m->wi);
        if (r->flags.has(BsdfFlags::reflection)) {
            EXPECT_EQ(r->weight[0], m->weight[0]);
        } else {
            EXPECT_NEAR(r->weight[0], m->weight[0] / (1.5f * 1.5f), 1e-6f);  // (η_i/η_t)² = 1/2.25
            EXPECT_NEAR(r->eta_scale, 2.25f, 1e-6f);
        }
    }
}

}  // namespace

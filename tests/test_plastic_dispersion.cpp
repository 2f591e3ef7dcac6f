// The plastic whose coat index varies with wavelength (model/bsdfs/plastic.h):
//   - the coat albedo table over the index (coat_albedo.h, coat_albedo_over_index) is at its rows
//     the constant coat's table bit for bit, and between rows within its stated error (6e-4 in
//     E, 1e-5 in E_avg), smooth and rough, at low, middle and high indices;
//   - eval at each wavelength equals eval of the constant-index plastic of index η(λ), within
//     that error; planted bug: a coat that gives every λ the mean index must be rejected;
//   - the white furnace holds per wavelength under a strongly dispersive coat (each λ's mean
//     weight is 1) while the coat's own share differs between the wavelengths (the test sees
//     the dispersion); the smooth coat's delta weight is F(μ, η(λ))/pc per λ;
//   - the sampled direction and the lobe choice do not depend on λ: no companion is terminated,
//     and sample() agrees with pdf() for any hero (the chi-square is in test_bsdf_contract.cpp);
//   - scene files: every spectrum form of "ior" (catalogue glass, Cauchy), a constant ior is
//     the constant plastic, and the clear errors for a textured roughness with a dispersive
//     coat and an index below 1.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "core/frame.h"
#include "model/bsdfs/bsdf.h"
#include "scene/scene_loader.h"
#include "spectral/glass_catalog.h"

namespace {

using namespace spt;

Spectrum constant(double v) { return Spectrum(SpectrumSource::constant(v), {SpectralResolution::kExact}); }
Spectrum exact(const SpectrumSource& s) { return Spectrum(s, {SpectralResolution::kExact}); }

/// SF11 from the catalogue (η 1.76–1.87 over 360–830 nm) and a far stronger Cauchy coat
/// (η from 2.22 at 360 nm to 1.60 at 830 nm).
Spectrum sf11() { return exact(find_glass("SF11")->ior); }
Spectrum strong_cauchy() { return exact(SpectrumSource::cauchy(1.45, 0.1)); }

const Vec3 kNormal = normalize(Vec3(0.2f, -0.3f, 0.9f));

Vec3 about(const Vec3& n, double cos_theta, double phi) {
    const double s = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
    return normalize(Frame(n).to_world({float(s * std::cos(phi)), float(s * std::sin(phi)), float(cos_theta)}));
}

TEST(CoatAlbedoOverIndex, RowsExactAndBetweenRowsWithinTheStatedError) {
    double worst_e = 0, worst_avg = 0;
    float worst_alpha = 0, worst_eta = 0, worst_mu = 0;
    for (float alpha : {0.f, 0.05f, 0.3f, 1.f})
        for (auto [lo, hi] : {std::pair{1.05f, 1.09f}, std::pair{1.5f, 1.55f}, std::pair{2.9f, 3.f}}) {
            const CoatAlbedoRows& t = coat_albedo_over_index(alpha, lo, hi);
            ASSERT_GE(t.rows.size(), 2u);
            const int intervals = static_cast<int>(t.rows.size()) - 1;
            EXPECT_LE((hi - lo) / intervals, kCoatIndexStep * (1 + 1e-5f));
            for (int r = 0; r <= intervals; ++r) {
                const float eta = static_cast<float>(double(lo) + (double(hi) - lo) * r / intervals);
                const CoatAlbedo row = make_coat_albedo(alpha, eta);
                EXPECT_EQ(t.rows[std::size_t(r)].e, row.e) << alpha << " row " << r;
                EXPECT_EQ(t.rows[std::size_t(r)].average, row.average);
                if (r == intervals) break;
                // Midway to the next row, where linear interpolation is worst.
                const float mid = lo + (hi - lo) * (float(r) + 0.5f) / float(intervals);
                const CoatAlbedo direct = make_coat_albedo(alpha, mid);
                for (int j = 0; j < CoatAlbedo::kPoints; ++j) {
                    const float mu = float(j) / (CoatAlbedo::kPoints - 1);
                    const double e = std::fabs(double(t.at(mid, mu)) - direct.at(mu));
                    if (e > worst_e) worst_e = e, worst_alpha = alpha, worst_eta = mid, worst_mu = mu;
                }
                worst_avg = std::max(worst_avg, std::fabs(double(t.average(mid)) - direct.average));
            }
        }
    std::printf("[coat over index] largest error midway between rows: E %.2e (alpha %g, eta %g, cos %g), "
                "E_avg %.2e\n", worst_e, worst_alpha, worst_eta, worst_mu, worst_avg);
    EXPECT_LE(worst_e, 6e-4);
    EXPECT_LE(worst_avg, 1e-5);
    EXPECT_GT(worst_e, 0.0);  // the rows are not the answer everywhere: the test measures something
    // Shared: one table per (α, range).
    EXPECT_EQ(&coat_albedo_over_index(0.3f, 1.5f, 1.55f), &coat_albedo_over_index(0.3f, 1.5f, 1.55f));
}

/// Largest relative difference, over directions and wavelengths, between the dispersive
/// plastic's eval at λ and the constant plastic of index η(λ) (with the same kd) at λ.
double largest_difference_from_constant_coats(const PlasticBsdf& dispersive, const Spectrum& eta, float alpha) {
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    double worst = 0;
    for (float hero_u : {0.05f, 0.3f, 0.55f, 0.8f}) {
        const SampledWavelengths lambda = SampledWavelengths::sample(hero_u);
        for (int k = 0; k < kLambdaCount; ++k) {
            const PlasticBsdf fixed = make_plastic(dispersive.kd, eta.eval(lambda.lambda[k]), alpha);
            for (int i = 0; i < 40; ++i) {
                const Vec3 wo = about(kNormal, 0.05 + 0.95 * u(rng), 6.3 * u(rng));
                const Vec3 wi = about(kNormal, 0.05 + 0.95 * u(rng), 6.3 * u(rng));
                const double a = dispersive.eval(wo, wi, kNormal, lambda, TransportMode::radiance)[k];
                const double b = fixed.eval(wo, wi, kNormal, lambda, TransportMode::radiance)[k];
                worst = std::max(worst, std::fabs(a - b) / std::max(b, 1e-3));
            }
        }
    }
    return worst;
}

TEST(PlasticDispersion, EvalAtEachWavelengthIsTheConstantCoatOfThatIndex) {
    // The diffuse term reads E from the table (≤ 6e-4 off, far less at most cosines), the
    // coat's lobe F(η(λ)) exactly.
    for (float alpha : {0.f, 0.2f, 0.7f})
        for (const Spectrum& eta : {sf11(), strong_cauchy()}) {
            const PlasticBsdf p = make_plastic(exact(SpectrumSource::gaussian(520, 60, 0.7, 0.1)), eta, alpha);
            ASSERT_NE(p.dispersion, nullptr);
            EXPECT_LE(largest_difference_from_constant_coats(p, eta, alpha), 2e-4) << alpha;
        }
    // Planted bug: every λ given the mean index (a table and clamp of that index alone). The
    // comparison must see it even for SF11, the weaker of the two coats.
    for (float alpha : {0.f, 0.2f}) {
        const Spectrum eta = sf11();
        PlasticBsdf wrong = make_plastic(constant(0.5), eta, alpha);
        const DispersiveCoat mean_only{eta, &coat_albedo_over_index(alpha, wrong.eta, wrong.eta)};
        wrong.dispersion = &mean_only;
        EXPECT_GT(largest_difference_from_constant_coats(wrong, eta, alpha), 5e-3) << alpha;
    }
}

/// Mean sample weight per lane at the fixed wavelengths `lambda0`, and the part of it that
/// came from the coat's lobe (its delta mirror, or rough-coat samples' eval share).
struct FurnaceResult {
    SampledSpectrum total, coat;
};

FurnaceResult furnace(const PlasticBsdf& p, const Vec3& wo, const SampledWavelengths& lambda0, int n,
                      std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    FurnaceResult r{SampledSpectrum(0.f), SampledSpectrum(0.f)};
    for (int i = 0; i < n; ++i) {
        SampledWavelengths lambda = lambda0;
        const auto bs = p.sample(wo, kNormal, lambda, u(rng), u(rng), u(rng), TransportMode::importance);
        if (!bs) continue;
        EXPECT_FALSE(lambda.secondary_terminated());  // reflection only: every λ follows wi
        r.total += bs->weight;
        if (bs->is_delta()) r.coat += bs->weight;
    }
    r.total = r.total / float(n);
    r.coat = r.coat / float(n);
    return r;
}

TEST(PlasticDispersion, WhiteBaseIsAWhiteFurnaceAtEveryWavelength) {
    // Each λ's own coat: ∫f cos = E(μo; η(λ)) + (1 − E_table(μo; η(λ))) = 1 up to the table
    // (as the constant coat, test_microfacet.cpp) and the Monte Carlo noise.
    const Spectrum eta = strong_cauchy();
    for (float alpha : {0.f, 0.2f, 0.7f})
        for (double cos_o : {0.95, 0.5, 0.15}) {
            const PlasticBsdf p = make_plastic(constant(1.0), eta, alpha);
            const Vec3 wo = about(kNormal, cos_o, 0.4);
            for (float hero_u : {0.1f, 0.6f}) {
                const SampledWavelengths lambda = SampledWavelengths::sample(hero_u);
                const FurnaceResult r = furnace(p, wo, lambda, 100000, 41);
                for (int k = 0; k < kLambdaCount; ++k)
                    EXPECT_NEAR(r.total[k], 1.0, 6e-3) << "α " << alpha << " cos " << cos_o << " λ " << lambda.lambda[k];
                if (alpha != 0.f) continue;
                // The smooth coat's share is F(μo, η(λ)) at each λ: it differs between the
                // wavelengths by more than twice the furnace's tolerance.
                float lo = 1, hi = 0;
                for (int k = 0; k < kLambdaCount; ++k) {
                    const float F = fresnel_dielectric(float(cos_o), eta.eval(lambda.lambda[k]));
                    EXPECT_NEAR(r.coat[k], F, 4e-3 + 0.02 * F) << "cos " << cos_o << " λ " << lambda.lambda[k];
                    lo = std::min(lo, r.coat[k]), hi = std::max(hi, r.coat[k]);
                }
                EXPECT_GT(hi - lo, 2 * 6e-3) << "cos " << cos_o;
            }
        }
}

TEST(PlasticDispersion, SmoothCoatDeltaWeightIsEachWavelengthsFresnel) {
    const PlasticBsdf p = make_plastic(constant(0.4), sf11(), 0.f);
    const Vec3 wo = about(kNormal, 0.6, 1.0);
    const float pc = p.coat_probability(0.6f);
    SampledWavelengths lambda = SampledWavelengths::sample(0.37f);
    const SampledWavelengths before = lambda;
    const auto bs = p.sample(wo, kNormal, lambda, 0.5f * pc, 0.3f, 0.7f, TransportMode::radiance);
    ASSERT_TRUE(bs && bs->is_delta());
    for (int k = 0; k < kLambdaCount; ++k) {
        const float F = fresnel_dielectric(0.6f, sf11().eval(lambda.lambda[k]));
        EXPECT_NEAR(bs->weight[k], F / pc, 1e-5f * F / pc) << k;
        EXPECT_EQ(lambda.pdf[k], before.pdf[k]);  // nothing terminated
    }
}

TEST(PlasticDispersion, LobeChoiceAndPdfDoNotDependOnTheWavelengths) {
    // One lobe-choice probability for all λ (the coat at the mean index): pdf() is the same
    // for any hero, and sampling with any wavelengths gives the same direction and pdf.
    for (float alpha : {0.f, 0.2f}) {
        const PlasticBsdf p = make_plastic(constant(0.5), strong_cauchy(), alpha);
        const Vec3 wo = about(kNormal, 0.7, 0.2);
        for (int i = 0; i < 64; ++i) {
            const float u1 = (i + 0.5f) / 64, u2 = 0.61f, u_lobe = std::fmod(0.37f * float(i), 1.f);
            SampledWavelengths blue = SampledWavelengths::sample(0.02f), red = SampledWavelengths::sample(0.9f);
            const auto a = p.sample(wo, kNormal, blue, u_lobe, u1, u2, TransportMode::radiance);
            const auto b = p.sample(wo, kNormal, red, u_lobe, u1, u2, TransportMode::radiance);
            ASSERT_EQ(bool(a), bool(b));
            if (!a) continue;
            EXPECT_EQ(a->wi, b->wi);
            EXPECT_EQ(a->pdf, b->pdf);
            if (a->is_delta()) continue;
            EXPECT_EQ(p.pdf(wo, a->wi, kNormal, blue.lambda[0]), p.pdf(wo, a->wi, kNormal, red.lambda[0]));
        }
    }
}

std::string scene_with(const std::string& material, const std::string& textures = "{}") {
    return R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]},
  "textures": )" + textures + R"(,
  "materials": {"m": )" + material + R"(},
  "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}]})";
}

std::string error_of(const std::string& material, const std::string& textures = "{}") {
    try {
        load_scene_text(scene_with(material, textures), "test.json", "test", {}, {});
    } catch (const LocatedError& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(PlasticDispersion, SceneFilesAcceptEverySpectrumFormOfTheCoatIndex) {
    for (const char* ior : {R"({"type": "glass", "name": "SF11"})", R"({"type": "cauchy", "a": 1.5, "b_um2": 0.004})",
                            R"({"type": "table", "points": [[400, 1.6], [700, 1.5]]})"}) {
        const Scene s = load_scene_text(
            scene_with(std::string(R"({"type": "plastic", "kd": 0.5, "roughness": 0.2, "ior": )") + ior + "}"),
            "test.json", "test", {}, {});
        const PlasticBsdf* p = std::get_if<PlasticBsdf>(&s.materials[0].bsdf);
        ASSERT_TRUE(p) << ior;
        ASSERT_NE(p->dispersion, nullptr) << ior;
        EXPECT_FALSE(s.effects.dispersion) << ior;  // reflection only: no direction splits
    }
    // A constant index is the constant plastic, as before.
    const Scene c = load_scene_text(scene_with(R"({"type": "plastic", "kd": 0.5, "ior": 1.7})"), "test.json", "test", {}, {});
    const PlasticBsdf& p = std::get<PlasticBsdf>(c.materials[0].bsdf);
    EXPECT_EQ(p.dispersion, nullptr);
    EXPECT_EQ(p.eta, 1.7f);

    // A textured roughness with a dispersive coat: an error at the roughness, saying what to do.
    const std::string textured = error_of(
        R"({"type": "plastic", "kd": 0.5, "ior": {"type": "glass", "name": "SF11"}, "roughness": {"texture": "r"}})",
        R"({"r": {"type": "checkerboard", "even": 0.1, "odd": 0.4}})");
    EXPECT_EQ(textured.rfind("test.json:3:", 0), 0u) << textured;
    EXPECT_NE(textured.find("textured roughness and an ior that varies with wavelength"), std::string::npos) << textured;
    EXPECT_NE(textured.find("; expected"), std::string::npos) << textured;
    // The same texture with a constant coat index loads.
    EXPECT_EQ(error_of(R"({"type": "plastic", "kd": 0.5, "ior": 1.5, "roughness": {"texture": "r"}})",
                       R"({"r": {"type": "checkerboard", "even": 0.1, "odd": 0.4}})"),
              "(no error)");
    const std::string below = error_of(R"({"type": "plastic", "kd": 0.5, "ior": {"type": "table", "points": [[400, 0.9], [700, 1.5]]}})");
    EXPECT_EQ(below.rfind("test.json:", 0), 0u) << below;
    EXPECT_NE(below.find("expected"), std::string::npos) << below;
}

}  // namespace

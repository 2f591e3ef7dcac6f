// Fluorescence (model/fluorescence.h): the path tracer's re-emission against closed forms.
//
// The oracle: a fluorescent plane under a uniform environment of radiance E(λ), seen straight
// down. Nothing else is visible from the plane, so its radiance is exactly
//     L(λo) = (1 − a(λo))·R(λo)·E(λo) + ∫ D(λi, λo)·E(λi) dλi
// (D the Donaldson matrix of the header, a the layer's absorptance, R the surface's albedo
// seen straight on: a diffuse kd, or a smooth conductor's Fresnel reflectance at normal
// incidence; the Lambertian re-emission of a uniform hemisphere integrates to 1). trace_path with a fixed hero λo estimates L(λo) on the hero lane, whichever
// branch the vertex takes; each check passes within 5 standard errors and must miss a planted
// error (the energy factor λi/λo dropped) by more than that.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "core/rng.h"
#include "model/fluorescence.h"
#include "render/integrator.h"
#include "scene/scene_loader.h"
#include "integrator_refusal.h"
#include "spectral/dye_catalog.h"

namespace spt {
namespace {

constexpr double kZ = 5.0;

Scene plane_scene(const std::string& material, const std::string& background) {
    const std::string text = R"({"camera": {"position": [0, 1, 0], "look_at": [0, 0, 0], "up": [0, 0, 1]},
      "background": )" + background + R"(,
      "materials": {"patch": )" + material + R"(},
      "shapes": [{"type": "plane", "normal": [0, 1, 0], "point": [0, 0, 0], "material": "patch"}]})";
    return load_scene_text(text, "test.json", "test", SpectralResolution{}, {});
}

const Material& patch(const Scene& scene) {
    for (const Material& m : scene.materials)
        if (m.fluorescence) return m;
    throw std::runtime_error("no fluorescent material");
}

float background(const Scene& scene, float lambda_nm) {
    for (const Light& l : scene.lights)
        if (const EnvironmentLight* e = std::get_if<EnvironmentLight>(&l)) return e->Le.eval(lambda_nm);
    return 0.f;
}

/// ∫ D(λi, λo)·E(λi) dλi by the midpoint rule at 0.05 nm; `energy_factor` false plants the
/// error of forgetting λi/λo.
double reemitted(const Fluorescence& fl, const Scene& scene, float lambda_o, bool energy_factor = true) {
    double sum = 0;
    const double h = 0.05;
    for (double l = kTransportMin + h / 2; l < kTransportMax; l += h) {
        const float li = static_cast<float>(l);
        double d = fl.donaldson(li, lambda_o);
        if (!energy_factor) d *= lambda_o / li;
        sum += d * background(scene, li) * h;
    }
    return sum;
}

struct Estimate {
    double mean = 0, standard_error = 0;
};

/// Means of the four lanes' radiance along the straight-down ray with wavelengths `lanes`.
std::array<Estimate, kLambdaCount> lane_radiance(const Scene& scene, const std::array<float, kLambdaCount>& lanes,
                                                 int n, std::uint64_t seed) {
    IntegratorSettings is;
    is.roulette = false;
    PathStats stats;
    std::array<double, kLambdaCount> s{}, s2{};
    for (int i = 0; i < n; ++i) {
        Rng rng(seed, 0, static_cast<std::uint64_t>(i));
        SampledWavelengths lambda;
        lambda.lambda = lanes;
        lambda.pdf = {1.f, 1.f, 1.f, 1.f};
        const SampledSpectrum L = trace_path(scene, is, {{0, 1, 0}, {0, -1, 0}, kInfinity}, 0.f, lambda, rng, stats);
        EXPECT_EQ(lambda.lambda, lanes) << "the film's wavelengths must come back";
        EXPECT_FALSE(lambda.secondary_terminated()) << "re-emission keeps the companions";
        for (int j = 0; j < kLambdaCount; ++j) s[j] += L[j], s2[j] += double(L[j]) * L[j];
    }
    std::array<Estimate, kLambdaCount> e;
    for (int j = 0; j < kLambdaCount; ++j) {
        const double mean = s[j] / n;
        e[j] = {mean, std::sqrt(std::max(0.0, s2[j] / n - mean * mean) / n)};
    }
    return e;
}

/// R(λ) of the header comment: the surface's albedo seen straight on (diffuse or smooth
/// conductor surfaces).
double straight_albedo(const Bsdf& surface, float lambda_nm) {
    if (const DiffuseBsdf* d = std::get_if<DiffuseBsdf>(&surface)) return d->kd.eval(lambda_nm);
    const ConductorBsdf& c = std::get<ConductorBsdf>(surface);
    EXPECT_EQ(c.ggx.alpha, 0.f) << "a rough conductor's albedo has no closed form here";
    SampledWavelengths lambda;
    lambda.lambda = {lambda_nm, lambda_nm, lambda_nm, lambda_nm};
    return c.reflectance(1.f, lambda)[0];
}

/// Every lane of the path is checked: the hero (λo) and companions 7, 11 and 23 nm away.
/// `surface`: the material's keys for the surface under the layer (default: a diffuse 0.9).
void expect_oracle(const std::string& dye, const std::string& background_spectrum,
                   const std::vector<float>& wavelengths, bool expect_glow, const std::string& surface = "") {
    const Scene scene = plane_scene(R"({"type": "fluorescent", "dye": ")" + dye + R"(", "density": 1.5)" +
                                        (surface.empty() ? "" : ", " + surface) + "}",
                                    background_spectrum);
    ASSERT_TRUE(scene.effects.fluorescence);
    const Material& m = patch(scene);
    const Fluorescence& fl = *m.fluorescence;
    bool glowed = false;
    for (const float hero : wavelengths) {
        const std::array<float, kLambdaCount> lanes = {hero, hero + 7.f, hero - 11.f, hero + 23.f};
        const std::array<Estimate, kLambdaCount> est = lane_radiance(scene, lanes, 20000, 7);
        for (int j = 0; j < kLambdaCount; ++j) {
            const float lo = lanes[j];
            const Estimate& e = est[j];
            const double reflected =
                (1.0 - fl.absorptance(lo)) * straight_albedo(m.bsdf, lo) * background(scene, lo);
            const double fluo = reemitted(fl, scene, lo);
            const double expected = reflected + fluo;
            EXPECT_NEAR(e.mean, expected, kZ * e.standard_error + 1e-5 * expected + 1e-9)
                << dye << " under " << background_spectrum << " at " << lo << " nm (lane " << j << "): reflected "
                << reflected << ", re-emitted " << fluo;
            // Power: the planted error (no λi/λo) is out of reach where the glow matters.
            if (fluo > 0.2 * expected && fluo > 1e-4) {
                glowed = true;
                const double wrong = reflected + reemitted(fl, scene, lo, false);
                EXPECT_GT(std::fabs(e.mean - wrong), kZ * e.standard_error)
                    << dye << " at " << lo << " nm: the test cannot tell the planted error apart";
            }
        }
    }
    EXPECT_EQ(glowed, expect_glow) << dye << " under " << background_spectrum;
}

TEST(FluorescenceOracle, NamedDyesUnderD65MatchTheDonaldsonIntegral) {
    const std::string d65 = R"({"type": "illuminant", "name": "D65"})";
    expect_oracle("fluorescein", d65, {450, 515, 540, 600}, true);
    expect_oracle("rhodamine6g", d65, {520, 555, 580, 650}, true);
    expect_oracle("stilbene", d65, {420, 440, 480}, true);
    // D65 has little UV where quinine absorbs (347 nm): its glow stays below a fifth of L.
    expect_oracle("quinine", d65, {440, 460, 520}, false);
}

TEST(FluorescenceOracle, NamedDyesUnderIlluminantAMatchTheDonaldsonIntegral) {
    const std::string a = R"({"type": "illuminant", "name": "A"})";
    expect_oracle("fluorescein", a, {515, 560}, true);
    expect_oracle("rhodamine6g", a, {555, 600}, true);
}

/// The 365 nm LED has (almost) nothing in the visible: what the camera sees at 450 nm was
/// carried from below the film's range, 300–380 nm (the transport range at work).
TEST(FluorescenceOracle, UvLedExcitesDyesFromBelowTheObserversRange) {
    const std::string led = R"({"type": "uv_lamp", "name": "led365"})";
    expect_oracle("stilbene", led, {420, 440, 480}, true);
    expect_oracle("quinine", led, {430, 460, 520}, true);
    // Rhodamine's weak near-UV band (0.1 of its peak): a dimmer glow, still checked exactly.
    expect_oracle("rhodamine6g", led, {555, 580}, true);
}

/// The surface under the layer may be any type: a smooth gold surface reflects the
/// environment only through its delta lobe (no next-event estimation of the reflectance part
/// can find it), a plastic's coat is the surface's own business.
TEST(FluorescenceOracle, DyeOverASmoothMetalMatchesTheDonaldsonIntegral) {
    const std::string d65 = R"({"type": "illuminant", "name": "D65"})";
    expect_oracle("fluorescein", d65, {450, 515, 540, 600}, true, R"("surface": {"type": "conductor", "metal": "Au"})");
    expect_oracle("rhodamine6g", d65, {520, 555, 650}, true, R"("surface": {"type": "conductor", "metal": "Ag"})");
}

/// The mean and standard error of the hero lane's radiance at λo along the ray from (0, 0, 3)
/// towards the origin, 20000 paths.
Estimate hero_radiance(const Scene& scene, float lo) {
    IntegratorSettings is;
    is.roulette = false;
    PathStats stats;
    double s = 0, s2 = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        Rng rng(3, 0, static_cast<std::uint64_t>(i));
        SampledWavelengths lambda;
        lambda.lambda = {lo, 400.f, 650.f, 700.f};
        lambda.pdf = {1.f, 1.f, 1.f, 1.f};
        const SampledSpectrum L = trace_path(scene, is, {{0, 0, 3}, {0, 0, -1}, kInfinity}, 0.f, lambda, rng, stats);
        s += L[0], s2 += double(L[0]) * L[0];
    }
    const double mean = s / n;
    return {mean, std::sqrt(std::max(0.0, s2 / n - mean * mean) / n)};
}

/// A sphere of `surface` under a dye that absorbs and emits the same band with quantum yield
/// 1, in a furnace of radiance 1.
Scene furnace(const std::string& surface) {
    const std::string band = R"({"type": "gaussian", "center_nm": 520, "width_nm": 30})";
    const std::string text = R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]}, "background": 1,
      "materials": {"m": {"type": "fluorescent", )" + surface + R"(, "density": 3,
                          "dye": {"excitation": )" + band + R"(, "emission": )" + band + R"(, "quantum_yield": 1}}},
      "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}]})";
    return load_scene_text(text, "test.json", "test", SpectralResolution{}, {});
}

/// White furnace with a white diffuse surface. A convex body sees only the environment, so
/// its radiance is (1 − a(λo)) + ∫D(λi, λo) dλi; it must not exceed 1 at any wavelength.
TEST(FluorescenceFurnace, QuantumYieldOneSameBandsStaysBelowTheIlluminant) {
    const Scene scene = furnace(R"("base": 1)");
    const Material& m = patch(scene);
    const Fluorescence& fl = *m.fluorescence;
    const DiffuseBsdf& base = std::get<DiffuseBsdf>(m.bsdf);
    // Every wavelength pair: what is reflected plus re-emitted from light absorbed at λi.
    for (int k = 0; k < 530; ++k) {
        const float li = kTransportMin + k + 0.5f;
        double out = (1.0 - fl.absorptance(li)) * base.kd.eval(li);
        for (int j = 0; j < 530; ++j) out += fl.donaldson(li, kTransportMin + j + 0.5f);
        EXPECT_LE(out, 1.0 + 1e-5) << "energy created from light at " << li << " nm";
    }
    for (float lo = 480.f; lo <= 600.f; lo += 20.f) {
        double expected = (1.0 - fl.absorptance(lo)) * base.kd.eval(lo);
        for (double l = kTransportMin + 0.025; l < kTransportMax; l += 0.05)
            expected += fl.donaldson(static_cast<float>(l), lo) * 0.05;
        EXPECT_LE(expected, 1.0) << lo << " nm";
        const Estimate e = hero_radiance(scene, lo);
        EXPECT_NEAR(e.mean, expected, kZ * e.standard_error + 1e-5 * expected) << lo << " nm";
        EXPECT_LE(e.mean, 1.0 + kZ * e.standard_error) << lo << " nm: brighter than the furnace";
    }
}

/// The same furnace with surfaces of other types, smooth and rough, that reflect every
/// photon or close to it (a silver-white conductor η = 0.2 + 4i, a clear glass, a white
/// plastic): nothing comes out brighter than the furnace, and where the dye absorbs the
/// radiance falls below what the surface alone would give. (Glass is two-sided: light
/// refracted into the sphere meets the layer again from inside.)
TEST(FluorescenceFurnace, AnySurfaceUnderTheLayerStaysBelowTheIlluminant) {
    for (const std::string surface : {
             R"("surface": {"type": "conductor", "eta": 0.2, "k": 4})",
             R"("surface": {"type": "conductor", "eta": 0.2, "k": 4, "roughness": 0.4})",
             R"("surface": {"type": "dielectric", "ior": 1.5})",
             R"("surface": {"type": "dielectric", "ior": 1.5, "roughness": 0.3})",
             R"("surface": {"type": "plastic", "kd": 1, "roughness": 0.2})"}) {
        const Scene scene = furnace(surface);
        for (float lo = 480.f; lo <= 600.f; lo += 40.f) {
            const Estimate e = hero_radiance(scene, lo);
            EXPECT_LE(e.mean, 1.0 + kZ * e.standard_error) << surface << " at " << lo << " nm";
            EXPECT_GT(e.mean, 0.0) << surface << " at " << lo << " nm";
        }
    }
}

/// "base" is shorthand for a diffuse surface: the same material, the same paths.
TEST(FluorescenceScene, BaseIsADiffuseSurface) {
    const Scene a = furnace(R"("base": 0.7)");
    const Scene b = furnace(R"("surface": {"type": "diffuse", "kd": 0.7})");
    for (float lo : {450.f, 530.f, 600.f}) {
        const Estimate ea = hero_radiance(a, lo), eb = hero_radiance(b, lo);
        EXPECT_EQ(ea.mean, eb.mean) << lo << " nm";
    }
}

/// sample_excitation draws λi with the density excitation_pdf says: a histogram of 10 nm
/// bins against the pdf's integral over each, and the pdf integrates to 1.
void expect_excitation_follows_pdf(const Fluorescence& fl, const std::string& name) {
    double total = 0;
    for (double l = kTransportMin + 0.05; l < kTransportMax; l += 0.1) total += fl.excitation_pdf(float(l)) * 0.1;
    EXPECT_NEAR(total, 1.0, 1e-3) << name;
    const int bins = 53, n = 400000;
    std::vector<double> counts(bins, 0.0);
    Rng rng(11, 0, 0);
    for (int i = 0; i < n; ++i) {
        float pdf = 0.f;
        const float l = fl.sample_excitation(rng.uniform(), pdf);
        ASSERT_GE(l, kTransportMin);
        ASSERT_LT(l, kTransportMax);
        ASSERT_NEAR(pdf, fl.excitation_pdf(l), 1e-6f * std::max(1.f, pdf));
        counts[static_cast<int>((l - kTransportMin) / 10.f)] += 1;
    }
    double chi2 = 0;
    int dof = 0;
    for (int b = 0; b < bins; ++b) {
        double p = 0;
        for (double l = kTransportMin + 10 * b + 0.05; l < kTransportMin + 10 * (b + 1); l += 0.1)
            p += fl.excitation_pdf(float(l)) * 0.1;
        const double expected = p * n;
        if (expected < 5) {
            EXPECT_LT(counts[b], 5 + 5 * std::sqrt(5.0)) << name << " bin " << b;
            continue;
        }
        chi2 += (counts[b] - expected) * (counts[b] - expected) / expected;
        ++dof;
    }
    // χ² with ~50 degrees of freedom: its mean is dof, its 1e-6 quantile ~ dof + 6·√(2·dof).
    EXPECT_LT(chi2, dof + 6 * std::sqrt(2.0 * dof)) << name << ": " << dof << " bins";
}

TEST(FluorescenceSampling, ExcitationSamplesFollowTheirPdf) {
    for (const std::string& name : dye_names()) {
        const DyeInfo d = *find_dye(name);
        const Fluorescence fl(d.excitation, d.emission, 1.0, d.quantum_yield, name);
        expect_excitation_follows_pdf(fl, name);
        for (float l = kTransportMin + 0.5f; l < kTransportMax; l += 1.f)
            ASSERT_NEAR(fl.excitation_pdf(l), fl.absorptance(l) / fl.absorbed_integral(), 1e-6f) << name;
    }
}

/// Under a 365 nm LED, rhodamine 6G's weak near-UV band is drawn far more often than by its
/// absorptance alone, its green band still at least half as often: p = ½·a/A + ½·a·S/B.
TEST(FluorescenceSampling, ExcitationFollowsTheLightsSpectrumToo) {
    const DyeInfo d = *find_dye("rhodamine6g");
    Fluorescence fl(d.excitation, d.emission, 1.0, d.quantum_yield, "rhodamine6g");
    const SpectrumSource led = *find_uv_lamp("led365");
    std::vector<double> illumination(kTransportBins);
    for (int k = 0; k < kTransportBins; ++k) illumination[k] = led.eval(kTransportMin + k + 0.5);
    const Fluorescence by_absorption = fl;
    fl.sample_excitation_by(illumination);
    expect_excitation_follows_pdf(fl, "rhodamine6g under led365");
    double uv = 0, uv_before = 0;
    for (float l = 340.5f; l < 390.f; l += 1.f) uv += fl.excitation_pdf(l), uv_before += by_absorption.excitation_pdf(l);
    EXPECT_GT(uv, 0.5) << "the lit band holds half the samples, and its share of the other half";
    EXPECT_LT(uv_before, 0.2);
    for (float l = kTransportMin + 0.5f; l < kTransportMax; l += 1.f)
        ASSERT_GE(fl.excitation_pdf(l), 0.5f * by_absorption.excitation_pdf(l) * (1 - 1e-5f)) << l;
    // No light in the dye's bands: sampling by absorption alone.
    Fluorescence dark = by_absorption;
    dark.sample_excitation_by(std::vector<double>(kTransportBins, 0.0));
    EXPECT_EQ(dark.excitation_pdf(530.5f), by_absorption.excitation_pdf(530.5f));
}

/// In a scene with fluorescent materials a UV lamp is chosen for next-event estimation by
/// what it emits over the transport range, not by its (almost nil) visible power.
TEST(FluorescenceScene, UvLampsAreChosenByTheirUltravioletPower) {
    auto scene_with = [](const std::string& material) {
        const std::string text = R"({"camera": {"position": [0, 1, 3], "look_at": [0, 0, 0]},
          "materials": {"m": )" + material + R"(},
          "shapes": [{"type": "plane", "normal": [0, 1, 0], "point": [0, 0, 0], "material": "m"},
                     {"type": "quad", "origin": [-1, 2, -1], "edge1": [1, 0, 0], "edge2": [0, 0, 1],
                      "emission": {"type": "illuminant", "name": "D65"}},
                     {"type": "quad", "origin": [0.5, 2, -1], "edge1": [1, 0, 0], "edge2": [0, 0, 1],
                      "emission": {"type": "uv_lamp", "name": "led365"}}]})";
        return load_scene_text(text, "test.json", "test", SpectralResolution{}, {});
    };
    // The lamp's share of the power over [lo, hi] (10 nm steps), and its choice probability.
    auto uv_share = [](const Scene& scene, float lo, float hi, float& probability) {
        double uv = 0, all = 0;
        probability = -1.f;
        for (std::size_t i = 0; i < scene.lights.size(); ++i) {
            const Light& light = scene.lights[i];
            double p = 0;
            for (float l = lo; l <= hi; l += 10.f) p += light_spectral_power(light, l);
            all += p;
            if (light_spectral_power(light, 365.f) > 10 * light_spectral_power(light, 560.f)) {
                uv = p;
                probability = scene.area_light_choice.probability(static_cast<int>(i));
            }
        }
        return uv / all;
    };
    float plain = 0, fluorescent = 0;
    const double plain_share = uv_share(scene_with(R"({"kd": 0.5})"), 380, 780, plain);
    const double fluorescent_share =
        uv_share(scene_with(R"({"type": "fluorescent", "dye": "quinine"})"), 300, 830, fluorescent);
    EXPECT_NEAR(plain, plain_share, 1e-4);
    EXPECT_NEAR(fluorescent, fluorescent_share, 1e-4);
    EXPECT_GT(fluorescent, 5 * plain) << plain;
}

/// Stokes' rule and the energy factor of the Donaldson matrix.
TEST(FluorescenceModel, DonaldsonMatrixIsStokesShiftedAndScaledByEnergy) {
    const DyeInfo d = *find_dye("fluorescein");
    const Fluorescence fl(d.excitation, d.emission, 1.0, d.quantum_yield, "fluorescein");
    EXPECT_EQ(fl.donaldson(520.f, 510.f), 0.f);
    EXPECT_EQ(fl.donaldson(515.f, 515.f), 0.f);
    EXPECT_NEAR(fl.donaldson(490.f, 520.f),
                fl.absorptance(490.f) * 0.925f * fl.emission(520.f) * (490.f / 520.f), 1e-7f);
    EXPECT_NEAR(fl.absorptance(490.5f), 1.0 - std::pow(10.0, -1.0 * d.excitation.eval(490.5)), 2e-3);
    double e = 0;
    for (int k = 0; k < 530; ++k) e += fl.emission(kTransportMin + k + 0.5f);
    EXPECT_NEAR(e, 1.0, 1e-4);
}

TEST(FluorescenceIntegrators, BidirectionalIntegratorsRefuseWithAMessage) {
    const Scene scene = plane_scene(R"({"type": "fluorescent", "dye": "fluorescein"})", "1");
    EXPECT_EQ(test::integrator_refusal(IntegratorKind::path, scene), "(no error)");
    for (IntegratorKind k : {IntegratorKind::bdpt, IntegratorKind::vcm})
        EXPECT_NE(test::integrator_refusal(k, scene).find("cannot render"), std::string::npos) << test::integrator_refusal(k, scene);
}

TEST(FluorescenceScene, FluorescentScenesAreExactAndOthersUnchanged) {
    const Scene plain = plane_scene(R"({"kd": 0.5})", "1");
    EXPECT_FALSE(plain.effects.fluorescence);
    const Scene fl = plane_scene(R"({"type": "fluorescent", "dye": "stilbene", "base": 0.8})", "1");
    EXPECT_TRUE(fl.effects.fluorescence);
    // Exact spectra: the 365 nm lamp keeps its line (bins would hold their 380 nm value).
    const Scene lamp = plane_scene(R"({"type": "fluorescent", "dye": "quinine"})",
                                   R"({"type": "uv_lamp", "name": "led365"})");
    EXPECT_NEAR(background(lamp, 365.f), 1.0, 1e-6);
    EXPECT_LT(background(lamp, 420.f), 1e-6);
}

std::string load_error(const std::string& material) {
    try {
        plane_scene(material, "1");
    } catch (const LocatedError& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(FluorescenceScene, BadDyesAreErrorsThatSayWhatIsExpected) {
    EXPECT_NE(load_error(R"({"type": "fluorescent", "dye": "fluorescin"})").find("fluorescein"), std::string::npos);
    EXPECT_NE(load_error(R"({"type": "fluorescent", "dye": "quinine", "quantum_yield": 1.5})").find("[0, 1]"),
              std::string::npos);
    EXPECT_NE(load_error(R"({"type": "fluorescent", "dye": "quinine", "density": 0})").find("density"),
              std::string::npos);
    EXPECT_NE(load_error(R"({"type": "fluorescent", "dye": {"excitation": 0, "emission": 1, "quantum_yield": 1}})")
                  .find("expected a band"),
              std::string::npos);
    EXPECT_NE(load_error(R"({"type": "fluorescent"})").find("dye"), std::string::npos);
}

TEST(FluorescenceScene, BadSurfacesAreErrorsThatSayWhatIsExpected) {
    const std::string both =
        load_error(R"({"type": "fluorescent", "dye": "quinine", "base": 0.5, "surface": {"type": "diffuse"}})");
    EXPECT_NE(both.find("expected one of them"), std::string::npos) << both;
    const std::string nested = load_error(
        R"({"type": "fluorescent", "dye": "quinine", "surface": {"type": "fluorescent", "dye": "stilbene"}})");
    EXPECT_NE(nested.find("Expected one of: diffuse"), std::string::npos) << nested;
    EXPECT_EQ(nested.find("fluorescent, "), std::string::npos) << nested;
    const std::string unknown =
        load_error(R"({"type": "fluorescent", "dye": "quinine", "surface": {"type": "diffuse", "ks": 1}})");
    EXPECT_NE(unknown.find("surface"), std::string::npos) << unknown;
    EXPECT_NE(unknown.find("ks"), std::string::npos) << unknown;
    const std::string bad_range = load_error(
        R"({"type": "fluorescent", "dye": "quinine", "surface": {"type": "conductor", "metal": "Au", "roughness": 2}})");
    EXPECT_NE(bad_range.find("roughness"), std::string::npos) << bad_range;
    EXPECT_NE(load_error(R"({"type": "fluorescent", "dye": "quinine", "surface": 0.5})").find("expected a material"),
              std::string::npos);
}

}  // namespace
}  // namespace spt

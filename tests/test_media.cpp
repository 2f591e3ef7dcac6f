// Participating media: transmittance estimators against closed forms, the Henyey–Greenstein
// sampler against its density, and the volumetric path tracer in furnaces with known answers.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "chi2.h"
#include "render/medium_tracking.h"
#include "render/volumetric_path.h"
#include "test_scenes.h"

namespace spt {
namespace {

/// Four wavelengths spread over the visible range (hero 450 nm).
SampledWavelengths four_wavelengths() {
    SampledWavelengths w;
    w.lambda = {450.f, 520.f, 600.f, 680.f};
    w.pdf = {1.f, 1.f, 1.f, 1.f};
    return w;
}

Scene load(const std::string& json) {
    const RelativeFileReader none = [](const std::string&, std::string&, std::string&, std::string& why) {
        why = "no files in this test";
        return false;
    };
    return load_scene_text(json, "test.json", "test", SpectralResolution{}, none);
}

// ---------------------------- Homogeneous slab ----------------------------

/// A slab z ∈ [0, d] of a chromatic medium between two planes without a surface, in vacuum.
Scene slab_scene(double d) {
    return load(R"({"camera": {"position": [0, 0, -5], "look_at": [0, 0, 0]},
        "media": {"ink": {"type": "homogeneous",
                          "sigma_a": {"type": "table", "points": [[380, 0.2], [780, 1.4]]},
                          "sigma_s": {"type": "table", "points": [[380, 0.3], [780, 0.1]]}}},
        "shapes": [{"type": "plane", "normal": [0, 0, -1], "point": [0, 0, 0], "interior": "ink"},
                   {"type": "plane", "normal": [0, 0, 1], "point": [0, 0, )" + std::to_string(d) + R"(], "interior": "ink"}]})");
}

TEST(MediaTransmittance, HomogeneousSlabIsBeerLambertPerWavelength) {
    const double d = 1.7;
    const Scene scene = slab_scene(d);
    ASSERT_TRUE(scene.effects.media);
    const SampledWavelengths lambda = four_wavelengths();
    Rng rng(1, 2, 3);
    PathStats stats;
    // From in front of the slab to behind it, through both surfaceless planes.
    const Ray ray{{0.1f, 0.2f, -1.f}, {0.f, 0.f, 1.f}, static_cast<float>(d) + 2.f};
    const SegmentTransmittance st = segment_transmittance(scene, ray, -1, lambda, rng, stats);
    const Medium& ink = scene.media[0];
    for (int i = 0; i < kLambdaCount; ++i) {
        // σt as the medium holds it (binned), and the table's exact line (binning error < 1e-3).
        const double l = lambda.lambda[i];
        const double sigma_t = ink.sigma_a.eval(float(l)) + ink.sigma_s.eval(float(l));
        EXPECT_NEAR(st.T[i], std::exp(-sigma_t * d), 1e-6) << l << " nm";
        const double exact = (0.2 + 1.2 * (l - 380) / 400) + (0.3 - 0.2 * (l - 380) / 400);
        EXPECT_NEAR(st.T[i], std::exp(-exact * d), 1e-3) << l << " nm";
    }
    // Ratio tracking and delta tracking (stochastic) agree with it on average.
    const Ray inside{{0.f, 0.f, 0.f}, {0.f, 0.f, 1.f}, kInfinity};
    const int n = 200000;
    SampledSpectrum ratio_sum(0.f);
    double delta_sum = 0;
    for (int k = 0; k < n; ++k) {
        ratio_sum += ratio_tracking_transmittance(ink, inside, static_cast<float>(d), lambda, rng);
        delta_sum += delta_tracking_transmittance(ink, inside, static_cast<float>(d), lambda, rng);
    }
    for (int i = 0; i < kLambdaCount; ++i) {
        const double expected = st.T[i], mean = ratio_sum[i] / n;
        // In a homogeneous medium every collision is real: ratio tracking is binary with
        // weights T_i/T_0; a bound of 5 standard errors of that estimator.
        const double w = expected / st.T[0];
        const double sd = w * std::sqrt(st.T[0] * (1 - st.T[0]) / n);
        EXPECT_NEAR(mean, expected, 5 * sd + 1e-6) << "ratio tracking at " << lambda.lambda[i] << " nm";
    }
    EXPECT_NEAR(delta_sum / n, st.T[0], 5 * std::sqrt(st.T[0] * (1 - st.T[0]) / n));
}

TEST(MediaTransmittance, NestedMediaFollowTheInterfaces) {
    // A sphere of medium A (radius 2) holding a sphere of medium B (radius 1) whose outside
    // is A, both without a surface: a ray through the centre crosses 2 of A and 2 of B.
    const Scene scene = load(R"({"camera": {"position": [0, 0, -5], "look_at": [0, 0, 0]},
        "media": {"a": {"type": "homogeneous", "sigma_a": 0.3, "sigma_s": 0.1},
                  "b": {"type": "homogeneous", "sigma_a": 0.9, "sigma_s": 0.6}},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 2, "interior": "a"},
                   {"type": "sphere", "center": [0, 0, 0], "radius": 1, "interior": "b", "exterior": "a"}]})");
    Rng rng(1, 1, 1);
    PathStats stats;
    const SegmentTransmittance st =
        segment_transmittance(scene, {{0.f, 0.f, -3.f}, {0.f, 0.f, 1.f}, 6.f}, -1, four_wavelengths(), rng, stats);
    EXPECT_NEAR(st.T[0], std::exp(-0.4 * 2 - 1.5 * 2), 1e-5);
    // A surface on the way blocks the shadow ray; so does running out of interfaces nowhere.
    const Scene walled = load(R"({"camera": {"position": [0, 0, -5], "look_at": [0, 0, 0]},
        "materials": {"white": {"kd": 0.5}},
        "media": {"a": {"type": "homogeneous", "sigma_a": 0.3, "sigma_s": 0.1}},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 2, "interior": "a"},
                   {"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "material": "white", "exterior": "a"}]})");
    EXPECT_TRUE(segment_transmittance(walled, {{0.f, 0.f, -3.f}, {0.f, 0.f, 1.f}, 6.f}, -1, four_wavelengths(), rng,
                                      stats).T.is_zero());
}

TEST(MediaLoader, GridFileIsReadAndInterpolated) {
    const Scene scene = load_scene_file(std::string(SPT_TEST_DIR) + "/scenes/medium_grid.json", SpectralResolution{});
    ASSERT_EQ(scene.media.size(), 1u);
    const Medium& m = scene.media[0];
    EXPECT_EQ(m.scale, 0.5f);
    EXPECT_FLOAT_EQ(m.phase.g, 0.4f);
    // Cell centres at x = −0.5 (1) and 0.5 (3); linear between, held outside; 0 beyond the box.
    EXPECT_FLOAT_EQ(m.density_at({-0.75f, 0.f, 0.f}), 1.f);
    EXPECT_FLOAT_EQ(m.density_at({0.f, 0.3f, -0.2f}), 2.f);
    EXPECT_FLOAT_EQ(m.density_at({0.9f, 0.f, 0.f}), 3.f);
    EXPECT_EQ(m.density_at({1.5f, 0.f, 0.f}), 0.f);
    EXPECT_EQ(m.max_density({{0.f, 0.f, 0.f}, {1.f, 0.f, 0.f}, kInfinity}, 0.f, 1.f), 3.f);
}

// ---------------------------- Heterogeneous densities ----------------------------

/// A 4×1×1 grid in the unit box: along x the density is v0 up to the first cell centre,
/// linear between centres, v3 after the last: ∫₀¹ d(x) dx = 0.125·v0 + 0.25·(v0+v1)/2 +
/// 0.25·(v1+v2)/2 + 0.25·(v2+v3)/2 + 0.125·v3.
Medium grid_medium(double sigma_t) {
    Medium m;
    m.name = "grid";
    m.sigma_a = test::constant_spectrum(0.25 * sigma_t);
    m.sigma_s = test::constant_spectrum(0.75 * sigma_t);
    auto grid = std::make_shared<DensityGrid>();
    grid->nx = 4, grid->ny = 1, grid->nz = 1;
    grid->values = {0.5f, 2.0f, 0.25f, 1.0f};
    GridDensity g;
    g.grid = grid;
    g.lo = {0.f, 0.f, 0.f}, g.hi = {1.f, 1.f, 1.f};
    g.max_value = 2.0f;
    m.density = g;
    return m;
}

TEST(MediaTransmittance, RatioAndDeltaTrackingAgreeOnAGridOfKnownIntegral) {
    const double sigma_t = 1.5;
    const Medium m = grid_medium(sigma_t);
    const double integral = 0.125 * 0.5 + 0.25 * (0.5 + 2.0) / 2 + 0.25 * (2.0 + 0.25) / 2 +
                            0.25 * (0.25 + 1.0) / 2 + 0.125 * 1.0;
    const double expected = std::exp(-sigma_t * integral);
    // The ray starts outside the box and runs along x through its middle.
    const Ray ray{{-0.5f, 0.5f, 0.5f}, {1.f, 0.f, 0.f}, kInfinity};
    const SampledWavelengths lambda = four_wavelengths();
    Rng rng(7, 8, 9);
    const int n = 200000;
    double ratio = 0, ratio2 = 0, delta = 0;
    for (int k = 0; k < n; ++k) {
        const double r = ratio_tracking_transmittance(m, ray, 3.f, lambda, rng)[0];
        ratio += r, ratio2 += r * r;
        delta += delta_tracking_transmittance(m, ray, 3.f, lambda, rng);
    }
    ratio /= n, delta /= n;
    const double ratio_se = std::sqrt((ratio2 / n - ratio * ratio) / n);
    const double delta_se = std::sqrt(expected * (1 - expected) / n);
    EXPECT_NEAR(ratio, expected, 5 * ratio_se);
    EXPECT_NEAR(delta, expected, 5 * delta_se);
    EXPECT_NEAR(ratio, delta, 5 * std::hypot(ratio_se, delta_se));
    // Ratio tracking is the lower-variance estimator of the two.
    EXPECT_LT(ratio_se, delta_se);
}

TEST(MediaTransmittance, HeightFogVerticalIntegralIsAnalytic) {
    Medium m;
    m.name = "fog";
    m.sigma_a = test::constant_spectrum(0.4);
    m.sigma_s = test::constant_spectrum(0.6);
    HeightFogDensity h;
    h.base = 0.5f, h.scale_height = 0.7f, h.top = 4.f;
    m.density = h;
    // From y = −1 up to y = 2: density 1 below 0.5, then exp(−(y − 0.5)/0.7).
    const double integral = 1.5 + 0.7 * (1 - std::exp(-1.5 / 0.7));
    const double expected = std::exp(-1.0 * integral);
    const Ray ray{{0.f, -1.f, 0.f}, {0.f, 1.f, 0.f}, kInfinity};
    const SampledWavelengths lambda = four_wavelengths();
    Rng rng(3, 1, 4);
    const int n = 200000;
    double ratio = 0, ratio2 = 0;
    for (int k = 0; k < n; ++k) {
        const double r = ratio_tracking_transmittance(m, ray, 3.f, lambda, rng)[0];
        ratio += r, ratio2 += r * r;
    }
    ratio /= n;
    EXPECT_NEAR(ratio, expected, 5 * std::sqrt((ratio2 / n - ratio * ratio) / n));
    // Above `top` there is nothing: a ray that starts there and rises sees T = 1 exactly.
    const Ray above{{0.f, 4.5f, 0.f}, {0.f, 1.f, 0.f}, kInfinity};
    EXPECT_EQ(ratio_tracking_transmittance(m, above, kInfinity, lambda, rng)[0], 1.f);
}

// ---------------------------- Henyey–Greenstein ----------------------------

/// χ² of sampled cos θ against the HG density integrated over each of 40 bins (the density
/// in cos θ is 2π·p, integrated in closed form). `sampled_g` is the g the sampler uses, `density_g` the one tested.
spt_test::Chi2Result hg_chi2(float sampled_g, float density_g) {
    const HenyeyGreenstein hg{sampled_g};
    const Vec3 wo = normalize(Vec3(0.3f, -0.5f, 0.8f));
    constexpr int kBins = 40, kSamples = 400000;
    std::vector<double> observed(kBins, 0.0), expected(kBins, 0.0);
    Rng rng(11, 12, 13);
    for (int i = 0; i < kSamples; ++i) {
        const Vec3 wi = hg.sample(wo, rng.uniform(), rng.uniform());
        const double c = std::clamp(double(dot(-wo, wi)), -1.0, 1.0);
        observed[std::min(kBins - 1, static_cast<int>((c + 1) / 2 * kBins))] += 1;
    }
    for (int b = 0; b < kBins; ++b) {
        // The exact probability of the bin: ∫ 2π·p dc = (1 − g²)/(2g)·[(1 + g² − 2gc)^(−1/2)].
        const double c0 = -1 + 2.0 * b / kBins, c1 = c0 + 2.0 / kBins, g = density_g;
        const double p = std::fabs(g) < 1e-6 ? (c1 - c0) / 2
                                             : (1 - g * g) / (2 * g) *
                                                   (1 / std::sqrt(1 + g * g - 2 * g * c1) - 1 / std::sqrt(1 + g * g - 2 * g * c0));
        expected[b] = kSamples * p;
    }
    return spt_test::chi2_test(observed, expected);
}

TEST(HenyeyGreenstein, SamplingMatchesItsDensity) {
    for (float g : {-0.7f, 0.f, 0.3f, 0.9f}) {
        const spt_test::Chi2Result r = hg_chi2(g, g);
        EXPECT_GT(r.p_value, 0.001) << "g = " << g << ", X² = " << r.statistic << " over " << r.dof << " dof";
        // The density is the sampler's pdf and integrates to 1 over the sphere.
        const HenyeyGreenstein hg{g};
        const Vec3 wo(0.f, 0.f, 1.f);
        double integral = 0;
        const int n = 2000;
        for (int i = 0; i < n; ++i) {
            const float c = -1.f + 2.f * (i + 0.5f) / n;
            integral += 2 * std::numbers::pi * HenyeyGreenstein::density(c, g) * 2.0 / n;
        }
        EXPECT_NEAR(integral, 1.0, 2e-3) << "g = " << g;
        EXPECT_NEAR(hg.eval(wo, -wo), HenyeyGreenstein::density(1.f, g), 1e-6f);
    }
}

TEST(HenyeyGreenstein, ChiSquareRejectsAPlantedBug) {
    // Planted bug: samples drawn with g = 0.3 tested against the density of g = 0.35 (or a
    // sampler that forgot the sign convention: g = −0.3).
    EXPECT_LT(hg_chi2(0.3f, 0.35f).p_value, 1e-6);
    EXPECT_LT(hg_chi2(0.3f, -0.3f).p_value, 1e-6);
}

// ---------------------------- Furnaces ----------------------------

/// Camera at the centre of an emitting sphere (radius R, radiance 1, reflecting nothing)
/// filled with a medium of σt = 1 and albedo `albedo`.
Scene medium_furnace(double radius, double albedo, double g = 0.3) {
    return load(R"({"camera": {"position": [0, 0, 0], "look_at": [0, 0, -1]},
        "media": {"m": {"type": "homogeneous", "sigma_a": )" + std::to_string(1 - albedo) +
                R"(, "sigma_s": )" + std::to_string(albedo) + R"(, "g": )" + std::to_string(g) + R"(}},
        "medium": "m",
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": )" + std::to_string(radius) +
                R"(, "emission": 1}]})");
}

/// The furnace without its medium: each pixel sees the emitter directly (radiance 1), with
/// the very wavelengths the furnace's samples draw (same seeds).
Scene empty_furnace(double radius) {
    return load(R"({"camera": {"position": [0, 0, 0], "look_at": [0, 0, -1]},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": )" + std::to_string(radius) +
                R"(, "emission": 1}]})");
}

TEST(MediaFurnace, NonAbsorbingMediumSeesExactlyOneWithoutLightSampling) {
    // Unidirectional sampling without roulette: every path scatters until it reaches the
    // emitter with throughput exactly 1 (σs/σs at each scattering, T/T on the way out), so
    // each pixel equals the medium-free render sample for sample: the only noise left is
    // that of the wavelengths, which both share.
    const Scene scene = medium_furnace(2.0, 1.0);
    RenderSettings s = test::small_settings(8, 8, 16);
    s.integrator.light_sampling = LightSampling::bsdf;
    s.integrator.roulette = false;
    const auto film = test::render_film(scene, s);
    const auto reference = test::render_film(empty_furnace(2.0), s);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const Xyz a = film->pixel_xyz(x, y), b = reference->pixel_xyz(x, y);
            EXPECT_NEAR(a.x, b.x, 1e-4 * b.x) << x << "," << y;
            EXPECT_NEAR(a.y, b.y, 1e-4 * b.y) << x << "," << y;
            EXPECT_NEAR(a.z, b.z, 1e-4 * b.z) << x << "," << y;
        }
}

TEST(MediaFurnace, NonAbsorbingMediumSeesOneWithMisAndRoulette) {
    const Scene scene = medium_furnace(2.0, 1.0);
    const auto film = test::render_film(scene, test::small_settings(16, 16, 64));
    const test::ImageMean m = test::image_mean_y(*film);
    EXPECT_NEAR(m.mean, 1.0, 4 * m.standard_error + 1e-3) << "± " << m.standard_error;
}

TEST(MediaFurnace, PureAbsorberIsBeerLambert) {
    // Albedo 0: only the unscattered emission arrives, exp(−σt·R). Free flight ends the path
    // at an absorption (probability 1 − T), so each sample is 0 or the medium-free value.
    const Scene scene = medium_furnace(1.5, 0.0);
    const RenderSettings s = test::small_settings(16, 16, 64);
    const test::ImageMean m = test::image_mean_y(*test::render_film(scene, s));
    const test::ImageMean free = test::image_mean_y(*test::render_film(empty_furnace(1.5), s));
    EXPECT_NEAR(m.mean, std::exp(-1.5) * free.mean, 4 * m.standard_error) << "± " << m.standard_error;
}

/// E[a^N] for the number N of scatterings of a walk from the centre of a sphere of radius R
/// in a medium of σt = 1 (isotropic phase, so the walk is independent of g's sampling code):
/// a second, independent Monte Carlo of the same radiative transfer.
double albedo_walk_reference(double radius, double albedo, int walks, double& standard_error) {
    Rng rng(99, 98, 97);
    double sum = 0, sum2 = 0;
    for (int w = 0; w < walks; ++w) {
        Vec3 p(0.f, 0.f, 0.f);
        double weight = 1;
        for (;;) {
            const Vec3 d = sample_uniform_sphere(rng.uniform(), rng.uniform());
            const double t = -std::log1p(-double(rng.uniform()));
            // Distance to the sphere along d from p.
            const double b = dot(p, d), c = dot(p, p) - radius * radius;
            const double exit = -b + std::sqrt(b * b - c);
            if (t >= exit) break;
            p = p + d * static_cast<float>(t);
            weight *= albedo;
        }
        sum += weight, sum2 += weight * weight;
    }
    const double mean = sum / walks;
    standard_error = std::sqrt((sum2 / walks - mean * mean) / walks);
    return mean;
}

TEST(MediaFurnace, AbsorbingMediumMatchesAnIndependentRandomWalk) {
    const double radius = 1.5, albedo = 0.6;
    double ref_se = 0;
    const double reference = albedo_walk_reference(radius, albedo, 400000, ref_se);
    const Scene scene = medium_furnace(radius, albedo, 0.0);
    const auto film = test::render_film(scene, test::small_settings(16, 16, 256));
    const test::ImageMean m = test::image_mean_y(*film);
    EXPECT_NEAR(m.mean, reference, 4 * std::hypot(m.standard_error, ref_se))
        << "render " << m.mean << " ± " << m.standard_error << ", walk " << reference << " ± " << ref_se;
    EXPECT_GT(m.mean, std::exp(-radius));  // scattering adds light to the unscattered part
    EXPECT_LT(m.mean, 1.0);
}

}  // namespace
}  // namespace spt

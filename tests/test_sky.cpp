// The Hosek–Wilkie sky and sun (model/lights/hosek_wilkie.h, sky_light.h, sun_light.h):
// the evaluated model against the datasets it comes from (curve ends and integer turbidity
// and albedo give the tabulated numbers), against values published independently of its
// spectral dataset (the zenith's chromaticity from the model's own CIE XYZ dataset; the
// sun's irradiance against the ASTM G173 direct spectrum), continuity, the sun's cone
// sampling at its real size, the sky's density, and the scene format.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "chi2.h"
#include "model/lights/light.h"
#include "scene/scene_loader.h"
#include "spectral/cie.h"
#include "spectral/spectral_table.h"

namespace spt {
namespace {

constexpr double kPiD = 3.14159265358979323846;
constexpr double kDeg = kPiD / 180;

double column(const SpectralTable& t, const std::string& name, int channel) {
    return t.column(name)[static_cast<std::size_t>(channel)];
}

float param(const HosekWilkieSky::Channel& c, char p) {
    switch (p) {
        case 'A': return c.A;
        case 'B': return c.B;
        case 'C': return c.C;
        case 'D': return c.D;
        case 'E': return c.E;
        case 'F': return c.F;
        case 'G': return c.G;
        case 'H': return c.H;
        case 'I': return c.I;
        default: return c.L_M;
    }
}

TEST(HosekWilkieSky, CurveEndsAtIntegerTurbidityAndAlbedoAreTheTabulatedNumbers) {
    // Elevation 0 is the Bézier curve's first control point, 90° its last; looked up by the
    // columns' names (not the code's index arithmetic), H and I included.
    const SpectralTable& t = embedded_spectral_table("hosek_wilkie_sky.csv");
    for (int a : {0, 1})
        for (int turbidity : {1, 4, 10})
            for (int end : {0, 5}) {
                const HosekWilkieSky sky = HosekWilkieSky::make(end == 0 ? 0.0 : kPiD / 2, turbidity, a);
                for (int c = 0; c < kSkyChannels; ++c)
                    for (char p : std::string("ABCDEFGHIL")) {
                        const std::string name = "a" + std::to_string(a) + "_t" + std::to_string(turbidity) + "_k" +
                                                 std::to_string(end) + "_" + std::string(1, p);
                        const double want = column(t, name, c);
                        EXPECT_NEAR(param(sky.channels[std::size_t(c)], p), want, 2e-6 * std::fabs(want) + 1e-12) << name;
                    }
            }
    // Between them, bilinear in turbidity and albedo: T = 4.25, albedo 0.5 at elevation 0.
    const HosekWilkieSky mid = HosekWilkieSky::make(0.0, 4.25, 0.5);
    for (int c = 0; c < kSkyChannels; ++c)
        for (char p : std::string("ABCDEFGHIL")) {
            double want = 0;
            for (int a : {0, 1})
                for (int turbidity : {4, 5})
                    want += 0.5 * (turbidity == 4 ? 0.75 : 0.25) *
                            column(t, "a" + std::to_string(a) + "_t" + std::to_string(turbidity) + "_k0_" + std::string(1, p), c);
            EXPECT_NEAR(param(mid.channels[std::size_t(c)], p), want, 2e-6 * std::fabs(want) + 1e-12) << p << c;
        }
}

TEST(HosekWilkieSun, PieceStartsAtIntegerTurbidityAreTheTabulatedConstants) {
    // At the start of piece i ((i/45)³·90°) the cubic is its constant term; the limb
    // darkening is the table's, and 1 at the disc's centre.
    const SpectralTable& t = embedded_spectral_table("hosek_wilkie_sun.csv");
    for (int turbidity : {1, 3, 10})
        for (int piece : {0, 7, 20, 44}) {
            const double eta = std::pow(piece / 45.0, 3.0) * kPiD / 2 + 1e-12;
            const HosekWilkieSun sun = HosekWilkieSun::make(eta, turbidity);
            for (int c = 0; c < kSkyChannels; ++c) {
                const double want = std::max(0.0, column(t, "t" + std::to_string(turbidity) + "_s" + std::to_string(piece) + "_c0", c));
                EXPECT_NEAR(sun.centre[std::size_t(c)], want, 1e-5 * want + 1e-6) << turbidity << " " << piece << " " << c;
            }
        }
    const HosekWilkieSun sun = HosekWilkieSun::make(0.5, 3);
    for (int c = 0; c < kSkyChannels; ++c) {
        for (int k = 0; k < 6; ++k)
            EXPECT_FLOAT_EQ(sun.limb[std::size_t(c)][std::size_t(k)], float(column(t, "ld" + std::to_string(k), c)));
        EXPECT_NEAR(sun.darkening(c, 1.f), 1.f, 2e-3f) << c;
        EXPECT_LT(sun.darkening(c, 0.f), 0.5f) << c;  // the limb is dark
    }
}

/// The chromaticity x, y of the sky at the zenith (CIE 1931, 360–830 nm at 1 nm).
std::array<double, 2> zenith_xy(double elevation_deg, double turbidity, double albedo) {
    SkyLight sky;
    sky.model = make_sky_model(elevation_deg * kDeg, 0.3, turbidity, albedo, 16);
    const Observer& cie = Cie1931::get();
    double X = 0, Y = 0, Z = 0;
    for (int i = 0; i < Observer::kRows; ++i) {
        SampledWavelengths lambda = SampledWavelengths::sample(0.5f);
        for (int k = 0; k < kLambdaCount; ++k) lambda.lambda[k] = kLambdaMin + float(i);
        const float L = sky.arriving({0, 1, 0}, lambda)[0];
        const Xyz c = cie.cmf(kLambdaMin + float(i));
        X += L * c.x, Y += L * c.y, Z += L * c.z;
    }
    return {X / (X + Y + Z), Y / (X + Y + Z)};
}

TEST(HosekWilkieSky, ZenithChromaticityMatchesTheModelsXyzDataset) {
    // x, y of the zenith from the model's CIE XYZ dataset (ArHosekSkyModelData_CIEXYZ.h,
    // fitted by the authors to the same simulations in XYZ), and from the spectral dataset by
    // a second implementation in Python: validation/sky_zenith_xyz.py, its output in
    // validation/results/sky_zenith_xyz.txt. The two fits differ by up to 0.007; ours must be
    // within 0.01 of the XYZ fit and 0.001 of the Python evaluation of the same spectra.
    struct Case {
        double elevation, turbidity, albedo, x_xyz, y_xyz, x_spectral, y_spectral;
    };
    const Case cases[] = {
        {5, 3, 0.1, 0.2608, 0.2768, 0.2580, 0.2817},  {15, 2, 0.1, 0.2410, 0.2485, 0.2376, 0.2538},
        {30, 3, 0.1, 0.2404, 0.2466, 0.2410, 0.2502}, {60, 6, 0.1, 0.2777, 0.2901, 0.2808, 0.2924},
        {85, 3, 0.1, 0.2970, 0.3134, 0.2984, 0.3125},
    };
    for (const Case& c : cases) {
        const auto [x, y] = zenith_xy(c.elevation, c.turbidity, c.albedo);
        EXPECT_LT(std::hypot(x - c.x_xyz, y - c.y_xyz), 0.01) << c.elevation << "°: " << x << ", " << y;
        EXPECT_LT(std::hypot(x - c.x_spectral, y - c.y_spectral), 0.001) << c.elevation << "°: " << x << ", " << y;
    }
    // A blue sky (x, y well below white's 0.31), yellowing as the sun climbs to the zenith.
    EXPECT_LT(zenith_xy(30, 3, 0.1)[0], 0.25);
    EXPECT_GT(zenith_xy(85, 3, 0.1)[0], zenith_xy(30, 3, 0.1)[0] + 0.03);
}

TEST(HosekWilkieSun, IrradianceIsCloseToTheAstmG173DirectSpectrum) {
    // ASTM G173-03 direct + circumsolar irradiance (sun 41.81° high, a clear rural sky;
    // NREL's table, the band means of ±20 nm about each channel) against the sun's disc at
    // 41.81° and turbidity 2: measured 0.77–0.97 of it (the model's extraterrestrial
    // spectrum and atmosphere are not G173's); a wrong table layout is off by far more.
    const double g173[] = {1.093, 1.329, 1.338, 1.344, 1.321, 1.274, 1.215, 1.086};  // 440 … 720 nm
    SunLight sun;
    sun.model = make_sun_model(41.81 * kDeg, 0.0, 2.0);
    const Vec3 s = sun.model->direction;
    const Frame frame(s);
    const double r = kSunAngularRadiusDegrees * kDeg;
    for (int i = 0; i < 8; ++i) {
        SampledWavelengths lambda = SampledWavelengths::sample(0.5f);
        for (int k = 0; k < kLambdaCount; ++k) lambda.lambda[k] = 440.f + 40.f * float(i);
        // E = ∫ over the disc of L dω, by rings.
        double E = 0;
        const int rings = 200;
        for (int j = 0; j < rings; ++j) {
            const double g = r * (j + 0.5) / rings;
            const Vec3 d = normalize(frame.to_world({float(std::sin(g)), 0.f, float(std::cos(g))}));
            E += sun.arriving(d, lambda)[0] * 2 * kPiD * std::sin(g) * (r / rings);
        }
        EXPECT_GT(E / g173[i], 0.7) << 440 + 40 * i << " nm";
        EXPECT_LT(E / g173[i], 1.05) << 440 + 40 * i << " nm";
    }
    // A low sun is red: 720 nm over 440 nm grows as it sets.
    const auto ratio = [](double elevation_deg) {
        const HosekWilkieSun model = HosekWilkieSun::make(elevation_deg * kDeg, 3);
        return model.centre[10] / model.centre[3];
    };
    EXPECT_GT(ratio(5), 2 * ratio(60));
}

TEST(HosekWilkie, RadianceIsContinuous) {
    const Vec3 d = normalize(Vec3{0.3f, 0.5f, -0.4f});
    // Across integer turbidities and the sun's elevation pieces.
    for (double t : {2.0, 5.0, 9.0}) {
        SkyLight lo, hi;
        lo.model = make_sky_model(0.4, 0.2, t - 1e-6, 0.3, 8);
        hi.model = make_sky_model(0.4, 0.2, t + 1e-6, 0.3, 8);
        for (int c = 0; c < kSkyChannels; ++c)
            EXPECT_NEAR(lo.model->channel_radiance(c, d), hi.model->channel_radiance(c, d), 1e-4 * hi.model->channel_radiance(c, d));
    }
    for (int piece = 1; piece < 45; ++piece) {
        const double eta = std::pow(piece / 45.0, 3.0) * kPiD / 2;
        const HosekWilkieSun a = HosekWilkieSun::make(eta - 1e-9, 3.5), b = HosekWilkieSun::make(eta + 1e-9, 3.5);
        for (int c = 0; c < kSkyChannels; ++c)
            EXPECT_NEAR(a.centre[std::size_t(c)], b.centre[std::size_t(c)], 2e-3 * b.centre[std::size_t(c)] + 1e-2) << piece;
    }
    // Across the channels in wavelength, and onto the horizon.
    SkyLight sky;
    sky.model = make_sky_model(0.2, 0.0, 3.0, 0.1, 8);
    for (float channel = 360.f; channel <= 680.f; channel += 40.f) {
        SampledWavelengths a = SampledWavelengths::sample(0.5f), b = a;
        for (int k = 0; k < kLambdaCount; ++k) a.lambda[k] = channel - 0.01f, b.lambda[k] = channel + 0.01f;
        EXPECT_NEAR(sky.arriving(d, a)[0], sky.arriving(d, b)[0], 1e-3f * sky.arriving(d, b)[0]) << channel;
    }
    const SampledWavelengths lambda = SampledWavelengths::sample(0.3f);
    const float on = sky.arriving(normalize(Vec3{1, 0, 0.2f}), lambda)[0];
    // (√cos θ is steep there: 10⁻⁷ above it, the I term has changed by 3·10⁻⁴ of itself.)
    const float above = sky.arriving(normalize(Vec3{1, 1e-7f, 0.2f}), lambda)[0];
    EXPECT_GT(on, 0.f);
    EXPECT_NEAR(on, above, 2e-3f * on);
    EXPECT_EQ(sky.arriving(normalize(Vec3{1, -1e-3f, 0.2f}), lambda)[0], 0.f);  // below: the ground's
}

TEST(SunLight, ConeSamplingAtTheRealSizeFollowsItsDensity) {
    // The real disc (0.2665°): every sample on it; (1 − cos θ)/(1 − cos r) and φ uniform
    // (chi-square over 10 × 10 cells); pdf × the cone's solid angle = 1.
    SunLight sun;
    sun.model = make_sun_model(0.3, 1.0, 3.0);
    const Vec3 s = sun.model->direction;
    const Frame frame(s);
    const double r = kSunAngularRadiusDegrees * kDeg;
    const double cone = 2 * kPiD * 2 * std::pow(std::sin(r / 2), 2);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    std::vector<double> observed(100, 0.0);
    const LightSampleContext ctx{{0, 0, 0}, {0, 0, 0}, {0, 1, 0}, {0, 1, 0}, false};
    const int n = 200000;
    int lost = 0;
    for (int i = 0; i < n; ++i) {
        LightSample ls;
        if (!sun.sample_li(ctx, SampledWavelengths::sample(0.5f), u(rng), u(rng), ls)) {
            ++lost;
            continue;
        }
        ASSERT_TRUE(sun.on_disc(ls.wi));
        ASSERT_NEAR(ls.pdf * cone, 1.0, 1e-4);
        ASSERT_EQ(sun.pdf_li(ctx, ls.wi), ls.pdf);
        const double a = std::min(0.999999, double(length_squared(ls.wi - s)) / double(sun.model->chord2));
        const Vec3 local = frame.to_local(ls.wi);
        const double phi = std::atan2(double(local.y), double(local.x)) + kPiD;
        observed[std::size_t(int(a * 10) * 10 + std::min(9, int(phi / (2 * kPiD) * 10)))] += 1;
    }
    EXPECT_LT(lost, n / 1000);  // rounding at the rim only
    const std::vector<double> expected(100, double(n - lost) / 100);
    EXPECT_GT(spt_test::chi2_test(observed, expected).p_value, 1e-5);
    // Off the disc: no radiance, no density.
    const Vec3 off = normalize(frame.to_world({float(std::sin(1.01 * r)), 0.f, float(std::cos(1.01 * r))}));
    EXPECT_EQ(sun.pdf_li(ctx, off), 0.f);
    EXPECT_EQ(sun.arriving(off, SampledWavelengths::sample(0.5f))[0], 0.f);
    const Vec3 in = normalize(frame.to_world({float(std::sin(0.99 * r)), 0.f, float(std::cos(0.99 * r))}));
    EXPECT_GT(sun.arriving(in, SampledWavelengths::sample(0.5f))[0], 0.f);
}

TEST(SkyLight, TheHemisphereSquareIsInvertedAndKeepsArea) {
    // Round trip, and equal solid angle per cell: the directions of a fine grid of the
    // square fall into a coarse grid over the hemisphere (bands of cos θ × φ) in
    // proportion to the bands' solid angle.
    // One point jittered in each cell of a 400 × 400 grid: a regular grid's rows would line
    // up with the square rings that the bands of cos θ are, and miscount them by a row.
    const int n = 400;
    std::vector<double> count(64, 0.0);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<float> jitter(0.f, 1.f);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const float u = (float(i) + jitter(rng)) / n, v = (float(j) + jitter(rng)) / n;
            const Vec3 d = square_to_hemisphere(u, v);
            ASSERT_NEAR(length(d), 1.f, 1e-5f);
            ASSERT_GE(d.z, 0.f);
            const auto [u2, v2] = hemisphere_to_square(d);
            ASSERT_NEAR(u2, u, 2e-5f);
            ASSERT_NEAR(v2, v, 2e-5f);
            // Sectors turned by 0.1 rad off the square's diagonals, on which grid points lie.
            const double phi = std::fmod(std::atan2(double(d.y), double(d.x)) + kPiD + 0.1, 2 * kPiD);
            count[std::size_t(std::min(7, int(d.z * 8)) * 8 + std::min(7, int(phi / (2 * kPiD) * 8)))] += 1;
        }
    for (double c : count) EXPECT_NEAR(c, n * n / 64.0, 0.01 * n * n / 64.0);
}

TEST(SkyLight, DensityIsNormalisedAndPositiveWhereverTheSkyShines) {
    SkyLight sky;
    sky.model = make_sky_model(0.1, -1.0, 2.5, 0.5);
    const LightSampleContext ctx{{0, 0, 0}, {0, 0, 0}, {0, 1, 0}, {0, 1, 0}, false};
    const SampledWavelengths lambda = SampledWavelengths::sample(0.4f);
    const int nc = 400, np = 800;
    double integral = 0;
    int unsampled_light = 0;
    for (int i = 0; i < nc; ++i) {
        const double c = -1 + 2 * (i + 0.5) / nc, st = std::sqrt(1 - c * c);
        for (int j = 0; j < np; ++j) {
            const double phi = 2 * kPiD * (j + 0.5) / np;
            const Vec3 d{float(st * std::cos(phi)), float(c), float(st * std::sin(phi))};
            const float pdf = sky.pdf_li(ctx, d);
            integral += pdf * 4 * kPiD / (double(nc) * np);
            if (sky.arriving(d, lambda)[0] > 0.f && !(pdf > 0.f)) ++unsampled_light;
        }
    }
    EXPECT_NEAR(integral, 1.0, 2e-3);
    EXPECT_EQ(unsampled_light, 0);
}

TEST(SkyScene, JsonSkyMakesASkyAndASun) {
    const std::string camera = R"("camera": {"position": [0, 1, 4], "look_at": [0, 1, 0]},
        "materials": {"g": {"kd": 0.5}}, "shapes": [{"type": "sphere", "center": [0, 1, 0], "radius": 1, "material": "g"}],)";
    const auto load = [&](const std::string& bg) {
        return load_scene_text("{" + camera + R"("background": )" + bg + "}", "sky.json", "sky", {}, {});
    };
    const Scene both = load(R"({"type": "sky", "sun_elevation_degrees": 20, "sun_azimuth_degrees": 90, "turbidity": 4,
                                "ground_albedo": 0.5, "scale": 2})");
    ASSERT_EQ(both.infinite_light_indices.size(), 2u);
    const SkyLight& sky = std::get<SkyLight>(both.lights.at(std::size_t(both.infinite_light_indices[0])));
    const SunLight& sun = std::get<SunLight>(both.lights.at(std::size_t(both.infinite_light_indices[1])));
    EXPECT_EQ(sky.scale, 2.f);
    EXPECT_EQ(sun.scale, 2.f);
    // Azimuth 90°: towards +z; 20° up.
    EXPECT_NEAR(sun.model->direction.z, std::cos(20 * kDeg), 1e-6);
    EXPECT_NEAR(sun.model->direction.y, std::sin(20 * kDeg), 1e-6);
    const HosekWilkieSky want = HosekWilkieSky::make(20 * kDeg, 4, 0.5);
    EXPECT_EQ(sky.model->sky.channels[5].A, want.channels[5].A);
    const Scene no_sun = load(R"({"type": "sky", "sun_elevation_degrees": 20, "sun": false})");
    ASSERT_EQ(no_sun.infinite_light_indices.size(), 1u);
    EXPECT_TRUE(std::holds_alternative<SkyLight>(no_sun.lights.at(std::size_t(no_sun.infinite_light_indices[0]))));
}

}  // namespace
}  // namespace spt

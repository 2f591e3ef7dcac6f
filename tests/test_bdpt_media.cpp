// Bidirectional path tracing with participating media and spot lights (bdpt_media.h): bdpt
// against the path tracer on small scenes where both converge, the analytic transmittance of
// an absorbing medium around the camera (every strategy, light tracing included, must apply
// it), finite pixels, bit-identity over thread counts, and which media bdpt and vcm refuse.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "integrator_refusal.h"
#include "test_scenes.h"

namespace spt {
namespace {

/// A closed box [−1, 1]³ of white walls (both sides in `inside`), lit by a small quad under
/// its ceiling, seen from inside; `extra` adds shapes, `media` defines the media.
std::string box_scene(const std::string& media, const std::string& camera_medium, const std::string& extra) {
    const std::string sides = R"(, "interior": ")" + camera_medium + R"(", "exterior": ")" + camera_medium + "\"";
    auto quad = [&](const char* o, const char* e1, const char* e2, const char* what) {
        return std::string(R"({"type": "quad", "origin": )") + o + R"(, "edge1": )" + e1 + R"(, "edge2": )" + e2 +
               ", " + what + sides + "},\n";
    };
    return R"({"camera": {"position": [0, 0, 0.9], "look_at": [0, -0.1, -1], "vfov_degrees": 70},
        "background": 0, "materials": {"white": {"kd": 0.7}, "red": {"kd": [0.7, 0.1, 0.1]}},
        "media": )" + media + R"(, "medium": ")" + camera_medium + R"(",
        "shapes": [)" +
           quad("[-1, -1, -1]", "[2, 0, 0]", "[0, 0, 2]", R"("material": "white")") +
           quad("[-1, 1, -1]", "[2, 0, 0]", "[0, 0, 2]", R"("material": "white")") +
           quad("[-1, -1, -1]", "[0, 2, 0]", "[0, 0, 2]", R"("material": "red")") +
           quad("[1, -1, -1]", "[0, 2, 0]", "[0, 0, 2]", R"("material": "white")") +
           quad("[-1, -1, -1]", "[2, 0, 0]", "[0, 2, 0]", R"("material": "white")") +
           quad("[-1, -1, 1]", "[2, 0, 0]", "[0, 2, 0]", R"("material": "white")") +
           quad("[-0.3, 0.8, -0.3]", "[0.6, 0, 0]", "[0, 0, 0.6]", R"("emission": 6)") + extra + "]}";
}

/// bdpt against the path tracer on `scene` (24 × 24): path at 1024 spp, bdpt as 32 renders of
/// 16 spp with their own seeds, whose spread gives each pixel's standard error with the
/// light-tracing splats included (a film's own error counts only its camera samples, too
/// little where light tracing carries the weight, as in a lit medium). Every pixel within 5σ
/// and the image means within 5 standard errors. Returns the path tracer's film.
std::unique_ptr<Film> expect_bdpt_renders_match_path(const Scene& scene, std::uint64_t seed) {
    constexpr int kRenders = 32, kSize = 24;
    auto path = test::render_film(scene, test::small_settings(kSize, kSize, 1024, seed));
    std::vector<double> sum(kSize * kSize, 0.0), sum2(kSize * kSize, 0.0);
    for (int r = 0; r < kRenders; ++r) {
        RenderSettings rs = test::small_settings(kSize, kSize, 16, seed + 1 + static_cast<std::uint64_t>(r));
        rs.integrator.kind = IntegratorKind::bdpt;
        const auto bdpt = test::render_film(scene, rs);
        EXPECT_EQ(bdpt->rejected_samples(), 0u);
        for (int i = 0; i < kSize * kSize; ++i) {
            const double y = bdpt->pixel_xyz(i % kSize, i / kSize).y;
            sum[i] += y, sum2[i] += y * y;
        }
    }
    double max_z = 0, mean_path = 0, mean_bdpt = 0, var = 0;
    int worst = 0;
    for (int i = 0; i < kSize * kSize; ++i) {
        const double m = sum[i] / kRenders;
        const double se2 = std::max(0.0, sum2[i] / kRenders - m * m) / (kRenders - 1);
        const double p = path->pixel_xyz(i % kSize, i / kSize).y, sp = path->pixel_y_standard_error(i % kSize, i / kSize);
        const double s2 = se2 + sp * sp;
        const double z = s2 > 0 ? std::fabs(m - p) / std::sqrt(s2) : (m == p ? 0.0 : 1e30);
        if (z > max_z) max_z = z, worst = i;
        mean_path += p / (kSize * kSize), mean_bdpt += m / (kSize * kSize), var += s2;
    }
    const double se = std::sqrt(var) / (kSize * kSize);
    const std::string what = "worst pixel (" + std::to_string(worst % kSize) + ", " + std::to_string(worst / kSize) +
                             ") z = " + std::to_string(max_z) + "; means " + std::to_string(mean_path) + " (path) vs " +
                             std::to_string(mean_bdpt) + " ± " + std::to_string(se);
    EXPECT_LE(max_z, 5.0) << what;
    EXPECT_NEAR(mean_bdpt, mean_path, 5.0 * se) << what;
    return path;
}

/// Mean Y of `renders` 24 × 24 renders of `scene` (their own seeds from `seed`) with its
/// standard error from their spread (light-tracing splats included).
test::ImageMean mean_of_renders(const Scene& scene, RenderSettings rs, int renders) {
    double sum = 0, sum2 = 0;
    for (int r = 0; r < renders; ++r) {
        const double m = test::image_mean_y(*test::render_film(scene, rs)).mean;
        sum += m, sum2 += m * m;
        ++rs.seed;
    }
    const double mean = sum / renders;
    return {mean, std::sqrt(std::max(0.0, sum2 / renders - mean * mean) / (renders - 1))};
}

/// Each complete class of bdpt strategies alone and unweighted (IntegratorSettings::bdpt_only_s
/// and bdpt_only_t: s = 0 only where the light is not a delta light) against the path tracer's
/// image mean, within 5 standard errors: a strategy class that is wrong on its own (a subpath
/// that loses track of its medium, a wrong transmittance on its connections) shows here even
/// where MIS gives it little weight in the combined image.
void expect_each_strategy_class_matches_path(const Scene& scene, std::uint64_t seed, bool light_is_delta) {
    constexpr int kSize = 24, kRenders = 8;
    const test::ImageMean path = mean_of_renders(scene, test::small_settings(kSize, kSize, 256, seed), kRenders);
    struct Class {
        int s, t;
        const char* name;
    };
    for (const Class c : {Class{0, -1, "s = 0 (camera paths that hit the light)"},
                          Class{1, -1, "s = 1 (connections to the light)"}, Class{-1, 1, "t = 1 (light tracing)"}}) {
        if (c.s == 0 && light_is_delta) continue;
        RenderSettings rs = test::small_settings(kSize, kSize, 64, seed + 1000);
        rs.integrator.kind = IntegratorKind::bdpt;
        rs.integrator.bdpt_only_s = c.s;
        rs.integrator.bdpt_only_t = c.t;
        const test::ImageMean b = mean_of_renders(scene, rs, kRenders);
        EXPECT_NEAR(b.mean, path.mean, 5.0 * std::hypot(b.standard_error, path.standard_error))
            << c.name << ": " << b.mean << " ± " << b.standard_error << " against path " << path.mean << " ± "
            << path.standard_error;
        EXPECT_GT(b.mean, 0.0) << c.name;
    }
}

Scene bdpt_scene(const std::string& json, const std::string& name) {
    Scene scene = test::load_exact_scene(json, name);
    EXPECT_TRUE(scene.effects.media) << name;
    return scene;
}

/// Fog filling a closed box lit by an area light (the camera and every wall in it).
Scene fog_box() {
    return bdpt_scene(box_scene(R"({"fog": {"type": "homogeneous", "sigma_a": 0.1, "sigma_s": 0.6, "g": 0.4}})",
                                "fog", R"({"type": "sphere", "center": [0.3, -0.6, -0.4], "radius": 0.3,
                                            "material": "white", "interior": "fog", "exterior": "fog"})"),
                      "fog box");
}

TEST(BdptMedia, FogInABoxMatchesThePathTracer) {
    const auto film = expect_bdpt_renders_match_path(fog_box(), 11);
    EXPECT_GT(test::image_mean_y(*film).mean, 0.0);
}

/// A slab of dense forward-scattering chromatic medium bounded by a box without a surface, in a
/// vacuum box: light crosses it many times before it reaches the camera.
Scene scattering_slab() {
    // A slab of dense forward-scattering medium bounded by a box without a surface, in a
    // vacuum box: light crosses it many times before it reaches the camera.
    std::string slab;
    // Every face's normal (edge1 × edge2) points out of the slab: its interior is the slab.
    const char* faces[6][3] = {{"[-0.8, -0.3, -0.8]", "[1.6, 0, 0]", "[0, 0, 1.2]"},
                               {"[-0.8, 0.1, -0.8]", "[0, 0, 1.2]", "[1.6, 0, 0]"},
                               {"[-0.8, -0.3, -0.8]", "[0, 0, 1.2]", "[0, 0.4, 0]"},
                               {"[0.8, -0.3, -0.8]", "[0, 0.4, 0]", "[0, 0, 1.2]"},
                               {"[-0.8, -0.3, -0.8]", "[0, 0.4, 0]", "[1.6, 0, 0]"},
                               {"[-0.8, -0.3, 0.4]", "[1.6, 0, 0]", "[0, 0.4, 0]"}};
    for (const auto& f : faces)
        slab += std::string(R"(, {"type": "quad", "origin": )") + f[0] + R"(, "edge1": )" + f[1] + R"(, "edge2": )" +
                f[2] + R"(, "interior": "slab", "exterior": "vacuum"})";
    // The box's own walls: vacuum on both sides (the camera's medium).
    const std::string json = box_scene(
        R"({"slab": {"type": "homogeneous", "sigma_a": 0.06, "sigma_s": [0.8, 0.5, 0.3], "scale": 5, "g": 0.6}})", "vacuum",
        slab.substr(2));
    return bdpt_scene(json, "scattering slab");
}

// Paths that enter a medium through a shape without a surface and scatter there must go on in
// that medium (the bug that kept bdpt from media: the walk went on in the medium it started
// in, 4-20 % too dark with the MIS weights, and each strategy class off on its own).
TEST(BdptMedia, ScatteringSlabMatchesThePathTracer) { expect_bdpt_renders_match_path(scattering_slab(), 21); }

TEST(BdptMedia, ScatteringSlabEachStrategyClassAloneMatchesThePathTracer) {
    expect_each_strategy_class_matches_path(scattering_slab(), 23, false);
}

TEST(BdptMedia, GlassOfAbsorbingLiquidMatchesThePathTracer) {
    // A glass sphere filled with a strongly chromatic absorber (σt differs between the
    // wavelengths: bdpt keeps only the hero on such paths) on a diffuse floor.
    const std::string json = box_scene(
        R"({"liquid": {"type": "homogeneous", "sigma_a": {"type": "table", "points": [[380, 4], [780, 0.2]]},
                        "sigma_s": 0}})",
        "vacuum",
        R"({"type": "sphere", "center": [0, -0.55, -0.3], "radius": 0.45, "material": "glass",
            "interior": "liquid", "exterior": "vacuum"})");
    std::string with_glass = json;
    with_glass.replace(with_glass.find(R"("red": )"), 0, R"("glass": {"kt": 1, "ior": 1.33}, )");
    Scene scene = bdpt_scene(with_glass, "liquid glass");
    expect_bdpt_renders_match_path(scene, 31);
}

TEST(BdptMedia, ChromaticMediumKeepsThePathTracersColour) {
    // The camera at the centre of an emitting sphere (radiance 1) filled with a strongly
    // chromatic medium: every pixel has the same expected colour, so the image's spread gives
    // the standard error of each channel's mean. bdpt keeps only the hero wavelength on paths
    // through it; its X, Y and Z must match the path tracer's spectral MIS (a wrong weight
    // for the wavelengths of such a path would tint the image).
    const Scene scene = bdpt_scene(R"({"camera": {"position": [0, 0, 0], "look_at": [0, 0, -1]},
        "media": {"m": {"type": "homogeneous", "g": 0.5,
            "sigma_s": {"type": "table", "points": [[380, 2.5], [780, 0.2]]},
            "sigma_a": {"type": "table", "points": [[380, 0.05], [780, 0.8]]}}},
        "medium": "m",
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1.5, "emission": 1, "interior": "m"}]})",
                                   "chromatic furnace");
    RenderSettings rs = test::small_settings(32, 32, 16, 81);
    const auto path = test::render_film(scene, rs);
    rs.integrator.kind = IntegratorKind::bdpt;
    rs.seed = 82;
    const auto bdpt = test::render_film(scene, rs);
    EXPECT_EQ(test::count_bad_pixels(*bdpt), 0);
    auto channel = [](const Film& film, int k, double& mean, double& se) {
        const int n = film.width() * film.height();
        double sum = 0, sum2 = 0;
        for (int y = 0; y < film.height(); ++y)
            for (int x = 0; x < film.width(); ++x) {
                const Xyz c = film.pixel_xyz(x, y);
                const double v = k == 0 ? c.x : k == 1 ? c.y : c.z;
                sum += v, sum2 += v * v;
            }
        mean = sum / n;
        se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / (n - 1));
    };
    for (int k = 0; k < 3; ++k) {
        double mp, sp, mb, sb;
        channel(*path, k, mp, sp);
        channel(*bdpt, k, mb, sb);
        EXPECT_NEAR(mb, mp, 5.0 * std::hypot(sp, sb)) << "XYZ channel " << k;
        EXPECT_GT(mb, 0.0);
    }
}

/// A spot light over a ball of haze (a sphere without a surface) around a diffuse floor, the
/// beam seen from the side. The light stays well out of the haze (0.7 from it): next-event
/// estimation from medium points near a point light has infinite variance (∫ 1/r⁴), and
/// close to it the path tracer's pixel errors would not be trustworthy.
Scene spot_in_haze() {
    return bdpt_scene(R"({"camera": {"position": [0, 0.8, 3], "look_at": [0, 0.6, 0], "vfov_degrees": 50},
        "materials": {"floor": {"kd": 0.6}},
        "media": {"haze": {"type": "homogeneous", "sigma_a": 0.05, "sigma_s": 0.4, "g": 0.5}},
        "shapes": [{"type": "quad", "origin": [-0.8, 0, -0.8], "edge1": [0, 0, 1.6], "edge2": [1.6, 0, 0],
                    "material": "floor", "interior": "haze", "exterior": "haze"},
                   {"type": "sphere", "center": [0, 0.6, 0], "radius": 1.3, "interior": "haze", "exterior": "vacuum"}],
        "lights": [{"type": "spot", "position": [0, 2.6, 0], "direction": [0.3, -1, 0], "intensity": 16,
                    "cone_degrees": 25, "falloff_degrees": 15}]})",
                      "spot in haze");
}

TEST(BdptMedia, SpotLightThroughHazeMatchesThePathTracer) {
    const auto film = expect_bdpt_renders_match_path(spot_in_haze(), 41);
    EXPECT_GT(test::image_mean_y(*film).mean, 0.0);
}

TEST(BdptMedia, SpotLightThroughHazeEachStrategyClassAloneMatchesThePathTracer) {
    expect_each_strategy_class_matches_path(spot_in_haze(), 43, true);
}

TEST(BdptMedia, LightInFogBehindShapesWithoutMediaMatchesThePathTracer) {
    // A ball of fog (a sphere without a surface) around a small emitting sphere, a diffuse
    // floor and an opaque sphere between the camera and the light, none of which names the
    // fog as its exterior (so their exterior is the camera's vacuum). The light subpaths
    // start in the fog (only shapes without a surface bound media: walking the line from the
    // camera through the opaque sphere's declared sides would put the light in vacuum), and
    // paths reflected by the floor or the sphere stay in the fog, as the path tracer tracks
    // it.
    const Scene scene = bdpt_scene(R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "vfov_degrees": 50},
        "materials": {"white": {"kd": 0.7}},
        "media": {"fog": {"type": "homogeneous", "sigma_a": 0.1, "sigma_s": 0.6, "g": 0.3}},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1.2, "interior": "fog", "exterior": "vacuum"},
                   {"type": "sphere", "center": [0, 0.3, -0.4], "radius": 0.12, "emission": 8},
                   {"type": "sphere", "center": [0, 0.2, 0.3], "radius": 0.25, "material": "white"},
                   {"type": "quad", "origin": [-0.7, -0.6, -0.7], "edge1": [0, 0, 1.4], "edge2": [1.4, 0, 0],
                    "material": "white"}]})",
                                   "light in fog");
    expect_bdpt_renders_match_path(scene, 91);
}

TEST(BdptSpotLight, ConeAndFalloffMatchThePathTracerWithoutMedia) {
    // A spot over a lit plane seen from above, its whole cone and the fading ring in view:
    // the connections to the spot (s = 1) apply the falloff, light paths leave within the cone.
    Scene scene = test::lit_plane_scene(0.5, 2.0, 1.f, 0.f, 0.f, 0.f, 2.f, 80.f);
    SpotLight spot;
    spot.position = {0.f, 1.f, 0.f};
    spot.direction = normalize(Vec3{0.2f, -1.f, 0.f});
    spot.intensity = test::constant_spectrum(2.0);
    spot.cos_cone = std::cos(35.f * kPi / 180.f);
    spot.cos_falloff = std::cos(15.f * kPi / 180.f);
    scene.lights.clear();
    scene.lights.emplace_back(spot);
    scene.finalize();
    const auto film = expect_bdpt_renders_match_path(scene, 51);
    // The film shows the lit cone and black outside it.
    EXPECT_GT(film->pixel_xyz(12, 12).y, 0.0);
    EXPECT_EQ(film->pixel_xyz(0, 0).y, 0.0);
}

TEST(BdptMedia, AbsorbingMediumAroundTheCameraScalesEveryStrategyByItsTransmittance) {
    // The camera at the centre of a sphere without a surface (radius R) filled with a pure
    // absorber σa, looking at a plane lit by a point light outside it: every path to the
    // camera crosses exactly R of the medium, so the image is exp(−σa·R) times the one in
    // vacuum. A wide view, so that light tracing (t = 1, splats through the medium) carries
    // much of the weight: a strategy that forgot the transmittance would be off by a share of
    // 1 − e⁻¹ of its weight.
    const std::string common = R"("camera": {"position": [0, 1, 0], "look_at": [0, 0, 0], "up": [0, 0, -1],
            "vfov_degrees": 90},
        "materials": {"floor": {"kd": 0.6}},
        "lights": [{"type": "point", "position": [0.3, 0.4, 0], "intensity": 2}],)";
    const std::string floor = R"({"type": "plane", "normal": [0, 1, 0], "point": [0, 0, 0], "material": "floor")";
    const Scene vacuum = test::load_exact_scene("{" + common + R"("shapes": [)" + floor + "}]}", "vacuum");
    const float radius = 0.5f, sigma_a = 2.f;
    const Scene absorbing = test::load_exact_scene(
        "{" + common + R"("media": {"ink": {"type": "homogeneous", "sigma_a": 2, "sigma_s": 0}}, "medium": "ink",
        "shapes": [)" + floor + R"(, "interior": "vacuum", "exterior": "vacuum"},
                   {"type": "sphere", "center": [0, 1, 0], "radius": 0.5, "interior": "ink", "exterior": "vacuum"}]})",
        "absorbing");
    RenderSettings rs = test::small_settings(16, 16, 256, 61);
    rs.integrator.kind = IntegratorKind::bdpt;
    const auto a = test::render_film(absorbing, rs);
    rs.seed = 62;
    const auto v = test::render_film(vacuum, rs);
    EXPECT_EQ(test::count_bad_pixels(*a), 0);
    const double T = std::exp(-static_cast<double>(sigma_a * radius));
    const test::ImageMean ma = test::image_mean_y(*a), mv = test::image_mean_y(*v);
    EXPECT_NEAR(ma.mean, T * mv.mean, 5.0 * std::hypot(ma.standard_error, T * mv.standard_error))
        << "with the medium " << ma.mean << ", in vacuum " << mv.mean << " × T = " << T * mv.mean;
    EXPECT_GT(ma.mean, 0.0);
}

/// A grey ball under a constant white environment, seen from inside fog: the fog fills all
/// space (`bounded` false) or a sphere of radius 2 around the camera and the ball.
Scene environment_through_fog(bool bounded) {
    const std::string boundary = bounded ? R"(, {"type": "sphere", "center": [0, 0, 0], "radius": 2,
                                                "interior": "fog", "exterior": "vacuum"})"
                                         : "";
    return bdpt_scene(R"({"camera": {"position": [0, 0, 1.5], "look_at": [0, 0, 0], "vfov_degrees": 50},
        "media": {"fog": {"type": "homogeneous", "sigma_a": 0.05, "sigma_s": 0.3}}, "medium": "fog",
        "background": 1, "materials": {"grey": {"kd": 0.7}},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "material": "grey",
                    "interior": "fog", "exterior": "fog"})" + boundary + "]}",
                      bounded ? "fog around the scene" : "fog everywhere");
}

TEST(BdptMedia, EnvironmentReachesNothingThroughFogThatFillsAllSpace) {
    // Light from infinity crosses an infinite stretch of fog: nothing arrives, in either
    // integrator (bdpt's light subpaths start on the bounding disk, inside the fog).
    const Scene scene = environment_through_fog(false);
    for (const IntegratorKind kind : {IntegratorKind::path, IntegratorKind::bdpt}) {
        RenderSettings rs = test::small_settings(16, 16, 16, 81);
        rs.integrator.kind = kind;
        EXPECT_EQ(test::image_mean_y(*test::render_film(scene, rs)).mean, 0.0) << integrator_name(kind);
    }
}

TEST(BdptMedia, EnvironmentThroughABoundedFogMatchesThePathTracer) {
    const auto film = expect_bdpt_renders_match_path(environment_through_fog(true), 91);
    EXPECT_GT(test::image_mean_y(*film).mean, 0.0);
}

TEST(BdptMedia, ThreadCountDoesNotChangeTheFilmAndEveryPixelIsFinite) {
    const Scene scene = spot_in_haze();
    RenderSettings rs = test::small_settings(16, 16, 8, 71, 1);
    rs.integrator.kind = IntegratorKind::bdpt;
    const auto one = test::render_film(scene, rs);
    rs.threads = 3;
    const auto many = test::render_film(scene, rs);
    EXPECT_EQ(test::count_bad_pixels(*one), 0);
    ASSERT_EQ(one->xyz_sums().size(), many->xyz_sums().size());
    EXPECT_EQ(std::memcmp(one->xyz_sums().data(), many->xyz_sums().data(), one->xyz_sums().size() * sizeof(double)),
              0);
    EXPECT_GT(test::image_mean_y(*one).mean, 0.0);
}

TEST(BdptMedia, BdptTakesHomogeneousMediaAndRefusesHeterogeneousOnesVcmRefusesMedia) {
    const Scene fog = fog_box();
    EXPECT_EQ(test::integrator_refusal(IntegratorKind::bdpt, fog), "(no error)");
    const std::string vcm = test::integrator_refusal(IntegratorKind::vcm, fog);
    EXPECT_NE(vcm.find("does not support participating media"), std::string::npos) << vcm;
    EXPECT_NE(vcm.find("expected --integrator bdpt or path"), std::string::npos) << vcm;
    // Height fog: delta tracking has no closed-form distance density for bdpt's MIS weights.
    const Scene height_fog = bdpt_scene(
        box_scene(R"({"fog": {"type": "height_fog", "sigma_a": 0.1, "sigma_s": 0.6, "base": -1, "scale_height": 1}})", "fog",
                  R"({"type": "sphere", "center": [0, -0.6, -0.4], "radius": 0.3, "material": "white",
                      "interior": "fog", "exterior": "fog"})"),
        "height fog");
    for (IntegratorKind kind : {IntegratorKind::bdpt, IntegratorKind::vcm}) {
        const std::string error = test::integrator_refusal(kind, height_fog);
        EXPECT_NE(error.find("does not support"), std::string::npos) << error;
        EXPECT_NE(error.find("--integrator path"), std::string::npos) << error;
    }
    EXPECT_NE(test::integrator_refusal(IntegratorKind::bdpt, height_fog).find("heterogeneous"), std::string::npos);
}

}  // namespace
}  // namespace spt

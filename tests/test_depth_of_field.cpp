// Thin-lens depth of field: the aperture's sampling, the circle of confusion of the thin lens,
// the blades' polygon, a sharp plane of focus, agreement of the integrators, determinism, and
// the camera keys of the scene format.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <string>

#include "model/aperture.h"
#include "model/camera.h"
#include "scene/scene_loader.h"
#include "test_scenes.h"

namespace spt {
namespace {

using test::compare;
using test::Comparison;
using test::describe;
using test::region_mean_y;
using test::render_film;
using test::small_settings;

constexpr double kZ = 5.0;
constexpr double kPiD = std::numbers::pi;

Scene load(const std::string& text) { return test::load_exact_scene(text, "dof"); }
std::string error_of(const std::string& text) { return test::scene_error(text, "dof"); }

/// <r²> over a regular N-gon of circumradius R (N = 0: the disc): R²(1 + 2cos²(π/N))/6,
/// R²/2 for the disc.
double polygon_second_moment(double R, int blades) {
    if (blades == 0) return R * R / 2;
    const double c = std::cos(kPiD / blades);
    return R * R * (1 + 2 * c * c) / 6;
}

/// Whether (x, y) is inside the regular polygon of `aperture` grown by `margin` (negative:
/// shrunk), in the aperture's own coordinates (x right, y up).
bool inside_polygon(const Aperture& aperture, double x, double y, double margin) {
    const int n = aperture.blades;
    const double inradius = aperture.radius * std::cos(kPiD / n);
    for (int k = 0; k < n; ++k) {
        // Edge k joins corners k and k + 1; its outward normal points half-way between them.
        const double a = (aperture.rotation_degrees + 90.0) * kPiD / 180.0 + (k + 0.5) * 2 * kPiD / n;
        if (x * std::cos(a) + y * std::sin(a) > inradius + margin) return false;
    }
    return true;
}

/// Uniform over the opening: every sample inside, mean at the centre, second moment of the
/// polygon (a density ∝ r, e.g. a missing √ in the triangle warp, or a wrongly rotated polygon,
/// fails), and the corners reached.
TEST(DepthOfField, ApertureSamplesAreUniformOverTheOpening) {
    for (const Aperture aperture : {Aperture{0.7f, 0, 0.f}, Aperture{0.7f, 6, 15.f}, Aperture{0.7f, 3, -40.f}}) {
        Rng rng(3, 4, 5);
        constexpr int kN = 400000;
        double sx = 0, sy = 0, sr2 = 0, sr2_2 = 0, reach = 0;
        for (int i = 0; i < kN; ++i) {
            const float u1 = rng.uniform(), u2 = rng.uniform();
            const AperturePoint p = aperture.sample(u1, u2);
            const double r2 = double(p.x) * p.x + double(p.y) * p.y;
            sx += p.x, sy += p.y, sr2 += r2, sr2_2 += r2 * r2;
            if (aperture.blades == 0) ASSERT_LE(r2, 0.7 * 0.7 * (1 + 1e-5));
            else ASSERT_TRUE(inside_polygon(aperture, p.x, p.y, 1e-5)) << p.x << ", " << p.y;
            const double corner = (aperture.rotation_degrees + 90.0) * kPiD / 180.0;  // corner 0
            reach = std::max(reach, p.x * std::cos(corner) + p.y * std::sin(corner));
        }
        const double mean_r2 = sr2 / kN;
        const double se_r2 = std::sqrt((sr2_2 / kN - mean_r2 * mean_r2) / kN);
        EXPECT_NEAR(sx / kN, 0.0, 0.005);
        EXPECT_NEAR(sy / kN, 0.0, 0.005);
        EXPECT_NEAR(mean_r2, polygon_second_moment(0.7, aperture.blades), kZ * se_r2) << aperture.blades;
        EXPECT_GT(reach, 0.69) << aperture.blades;  // corner 0 (or the disc's top) is reached
        const double expected_area = aperture.blades == 0 ? kPiD * 0.49 : 0.5 * aperture.blades * 0.49 * std::sin(2 * kPiD / aperture.blades);
        EXPECT_NEAR(aperture.area(), expected_area, 1e-5);
    }
}

/// A small emitting sphere (radius rho, radiance 1, at depth z on the axis) seen through a
/// thin lens of aperture `aperture_json` focused at distance f, 64×64 pixels, vfov 30°.
std::string bokeh_scene(double z, double rho, double f, const std::string& aperture_json) {
    return "{\"camera\": {\"position\": [0, 0, 0], \"look_at\": [0, 0, -1], \"vfov_degrees\": 30, " + aperture_json +
           ", \"focus_distance\": " + std::to_string(f) + "},\n\"shapes\": [{\"type\": \"sphere\", \"center\": [0, 0, " +
           std::to_string(-z) + "], \"radius\": " + std::to_string(rho) + ", \"emission\": 1}]}";
}
constexpr int kBokehSize = 64;
/// Pixels per unit length on the plane at distance 1 (half the image height is tan 15°).
const double kPixelsPerUnit = kBokehSize / (2 * std::tan(15 * kPiD / 180));

/// The thin lens's circle of confusion: a point at depth z through an aperture of radius R
/// focused at f lands on a disc of radius R·|z − f|/z on the focus plane, R·|z − f|/(z·f) on
/// the plane at distance 1. The image of the sphere is that disc convolved with the sphere's
/// own (radius rho/z there): second moments add, so √(2<r²>) = √(Rc² + Rs²), less Sheppard's
/// 1/6 px² for pixel centres. Behind and in front of the plane of focus; a pinhole-sized or
/// doubled aperture, or a wrong focus distance, is off by far more than the 3 % allowed.
TEST(DepthOfField, OutOfFocusLightImagesToTheCircleOfConfusion) {
    const double R = 0.3, f = 2, rho = 0.03;
    for (const double z : {6.0, 1.2}) {
        const Scene scene = load(bokeh_scene(z, rho, f, "\"aperture_radius\": 0.3"));
        const auto film = render_film(scene, small_settings(kBokehSize, kBokehSize, 256, 21));
        double sum = 0, sx = 0, sy = 0, sr2 = 0;
        for (int pass = 0; pass < 2; ++pass)
            for (int y = 0; y < kBokehSize; ++y)
                for (int x = 0; x < kBokehSize; ++x) {
                    const double v = film->pixel_xyz(x, y).y, cx = x + 0.5, cy = y + 0.5;
                    if (pass == 0) sum += v, sx += v * cx, sy += v * cy;
                    else sr2 += v * (std::pow(cx - sx / sum, 2) + std::pow(cy - sy / sum, 2));
                }
        const double Rc = R * std::fabs(z - f) / (z * f) * kPixelsPerUnit;
        const double Rs = rho / z * kPixelsPerUnit;
        const double measured = std::sqrt(2 * (sr2 / sum + 1.0 / 6));
        EXPECT_NEAR(measured, std::sqrt(Rc * Rc + Rs * Rs), 0.03 * Rc) << "z = " << z;
        // The centroid's noise (delta method: dc/dv_i = (x_i − c)/sum): the tiny sphere is
        // hit by few lens samples, about 0.3 px at 256 spp, so a fixed 0.5 px passed by luck.
        double var_x = 0, var_y = 0;
        for (int y = 0; y < kBokehSize; ++y)
            for (int x = 0; x < kBokehSize; ++x) {
                const double se = film->pixel_y_standard_error(x, y);
                var_x += std::pow((x + 0.5 - sx / sum) * se / sum, 2);
                var_y += std::pow((y + 0.5 - sy / sum) * se / sum, 2);
            }
        EXPECT_NEAR(sx / sum, kBokehSize / 2.0, kZ * std::sqrt(var_x)) << "z = " << z;
        EXPECT_NEAR(sy / sum, kBokehSize / 2.0, kZ * std::sqrt(var_y)) << "z = " << z;
    }
}

/// Six blades turned by 15°: the bokeh of a point behind the focus plane is the aperture's
/// hexagon, upright (the image of lens point l on the focus plane moves by l·(1 − f/z)),
/// scaled to the circle of confusion. Outside the hexagon grown by the sphere's image and a
/// pixel nothing may land (a disc of the same radius would); inside it shrunk by the same
/// margin every pixel sees the sphere from a fraction πρ²/((1 − z/f)²·aperture area) of the
/// lens, which the mean must match within noise (a non-uniform or mis-sized opening fails).
TEST(DepthOfField, BladesGiveThePolygon) {
    const double z = 6, f = 2, rho = 0.03;
    const Aperture aperture{0.6f, 6, 15.f};
    const Scene scene = load(bokeh_scene(z, rho, f, "\"aperture_radius\": 0.6, \"blades\": 6, \"rotation_degrees\": 15"));
    const auto film = render_film(scene, small_settings(kBokehSize, kBokehSize, 512, 22));
    const double scale = (1 - f / z) / f * kPixelsPerUnit;  // lens units → pixels
    const double margin = rho / z * kPixelsPerUnit + 1.0;  // sphere image + a pixel
    auto lens_coordinates = [&](int x, int y, double& lx, double& ly) {
        lx = (x + 0.5 - kBokehSize / 2.0) / scale;
        ly = (kBokehSize / 2.0 - (y + 0.5)) / scale;  // image y points down
    };
    int outside_lit = 0, inside = 0;
    for (int y = 0; y < kBokehSize; ++y)
        for (int x = 0; x < kBokehSize; ++x) {
            double lx, ly;
            lens_coordinates(x, y, lx, ly);
            if (!inside_polygon(aperture, lx, ly, margin / scale) && film->pixel_xyz(x, y).y != 0.0) ++outside_lit;
            inside += inside_polygon(aperture, lx, ly, -margin / scale);
        }
    EXPECT_EQ(outside_lit, 0);
    ASSERT_GT(inside, 600);
    const auto m = region_mean_y(*film, [&](int x, int y) {
        double lx, ly;
        lens_coordinates(x, y, lx, ly);
        return inside_polygon(aperture, lx, ly, -margin / scale);
    });
    const double expected = kPiD * rho * rho / (std::pow(1 - z / f, 2) * aperture.area());
    EXPECT_NEAR(m.mean, expected, kZ * m.standard_error + 0.01 * expected) << "σ = " << m.standard_error;
}

/// Emitting stripes lying in a plane at distance f: focused there, every ray of a film
/// position meets the same point of the plane, so the image is the pinhole's up to noise
/// (per-pixel z ≤ 5 against the measured errors of both). Focusing 50 % further must blur
/// the stripes' edges far beyond the noise: the comparison can fail.
TEST(DepthOfField, PlaneAtTheFocusDistanceIsSharp) {
    auto scene_text = [](const std::string& lens) {
        std::string shapes;
        for (int i = 0; i < 4; ++i) {
            const double x0 = -1.0 + 0.5 * i;
            shapes += std::string(i ? ", " : "") + "{\"type\": \"quad\", \"origin\": [" + std::to_string(x0) +
                      ", -1, -3], \"edge1\": [0.22, 0, 0], \"edge2\": [0, 2, 0], \"emission\": " + std::to_string(1 + i) + "}";
        }
        return "{\"camera\": {\"position\": [0, 0, 0], \"look_at\": [0, 0, -1], \"vfov_degrees\": 40" + lens +
               "},\n\"shapes\": [" + shapes + "]}";
    };
    const RenderSettings rs = small_settings(48, 32, 128, 31);
    const auto pinhole = render_film(load(scene_text("")), rs);
    const auto focused = render_film(load(scene_text(", \"aperture_radius\": 0.5, \"focus_distance\": 3")), rs);
    const Comparison same = compare(*pinhole, *focused, [](int, int) { return true; });
    EXPECT_LE(same.max_z, kZ) << describe(same);
    EXPECT_NEAR(same.mean_a, same.mean_b, kZ * same.se) << describe(same);
    const auto blurred = render_film(load(scene_text(", \"aperture_radius\": 0.5, \"focus_distance\": 4.5")), rs);
    EXPECT_GT(compare(*pinhole, *blurred, [](int, int) { return true; }).max_z, 2 * kZ);
}

/// Diffuse floor and spheres under a point light, the near sphere in focus, the rest blurred.
/// The light reaches the film along every bidirectional strategy, light tracing's splats
/// through the lens (t = 1) among them.
const char* kDiffuseDofScene = R"({
  "camera": {"position": [0, 1, 4], "look_at": [0, 0.3, 0], "vfov_degrees": 40,
             "aperture_radius": 0.25, "focus_point": [0.5, 0.4, 1], "blades": 5},
  "materials": {"grey": {"kd": 0.6}, "red": {"kd": {"type": "rgb", "value": [0.7, 0.1, 0.1]}}},
  "shapes": [
    {"type": "plane", "normal": [0, 1, 0], "point": [0, 0, 0], "material": "grey"},
    {"type": "sphere", "center": [0.5, 0.4, 1], "radius": 0.4, "material": "red"},
    {"type": "sphere", "center": [-0.8, 0.5, -1.5], "radius": 0.5, "material": "grey"}
  ],
  "lights": [{"type": "point", "position": [0, 2.5, 1], "intensity": 8}]
})";

/// bdpt and vcm against the path tracer with the lens: a splat through the pinhole's
/// projection instead of the lens point's (max z 12 when planted), or vcm's light subpaths
/// splatting from the lens centre, shows here.
TEST(DepthOfField, BidirectionalIntegratorsAgreeWithThePathTracer) {
    const Scene scene = load(kDiffuseDofScene);
    ASSERT_TRUE(scene.effects.depth_of_field);
    const auto path = test::expect_bdpt_matches_path(scene, 41);
    RenderSettings rs = small_settings(24, 24, 512, 42);
    // vcm: a pixel's samples come from independent passes, so its z holds; the pixels of a
    // pass share their light subpaths' wavelengths, so the image mean gets a 1 % margin.
    rs.integrator.kind = IntegratorKind::vcm;
    rs.seed = 43;
    const auto vcm = render_film(scene, rs);
    EXPECT_EQ(vcm->rejected_samples(), 0u);
    const Comparison v = compare(*path, *vcm, [](int, int) { return true; });
    EXPECT_LE(v.max_z, kZ) << describe(v);
    EXPECT_NEAR(v.mean_a, v.mean_b, kZ * v.se + 0.01 * v.mean_a) << describe(v);
}

/// The lens point comes from each sample's own stream (and a splat's from its light path's):
/// the film is the same bits for any thread count, in all three integrators.
TEST(DepthOfField, ThreadCountDoesNotChangeTheFilm) {
    const Scene scene = load(kDiffuseDofScene);
    for (const IntegratorKind kind : {IntegratorKind::path, IntegratorKind::bdpt, IntegratorKind::vcm}) {
        RenderSettings rs = small_settings(20, 16, 4, 9, 1);
        rs.integrator.kind = kind;
        const auto one = render_film(scene, rs);
        rs.threads = 3;
        const auto three = render_film(scene, rs);
        const std::vector<double>& a = one->xyz_sums();
        const std::vector<double>& b = three->xyz_sums();
        ASSERT_EQ(a.size(), b.size());
        EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0) << static_cast<int>(kind);
    }
}

TEST(DepthOfField, SceneKeys) {
    auto camera = [](const std::string& keys) {
        return "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]" + keys + "}, \"shapes\": []}";
    };
    const Scene pinhole = load(camera(""));
    EXPECT_EQ(pinhole.camera.aperture.radius, 0.f);
    EXPECT_FALSE(pinhole.effects.depth_of_field);
    EXPECT_EQ(pinhole.effects.describe().find("depth of field"), std::string::npos);
    // f-number N: radius = focal length / (2N); the focus defaults to the look_at distance.
    const Scene f_number = load(camera(", \"f_number\": 2.8, \"focal_length\": 0.05"));
    EXPECT_FLOAT_EQ(f_number.camera.aperture.radius, 0.05f / 5.6f);
    EXPECT_FLOAT_EQ(f_number.camera.focus_distance, 5.f);
    EXPECT_NE(f_number.effects.describe().find("depth of field"), std::string::npos);
    // A focus point: its distance along the view axis (not to the eye).
    const Scene point = load(camera(", \"aperture_radius\": 0.1, \"focus_point\": [3, 0, 1]"));
    EXPECT_FLOAT_EQ(point.camera.focus_distance, 4.f);
    EXPECT_EQ(point.camera.aperture.blades, 0);
    const Scene blades = load(camera(", \"aperture_radius\": 0.1, \"blades\": 7, \"rotation_degrees\": 12"));
    EXPECT_EQ(blades.camera.aperture.blades, 7);
    EXPECT_FLOAT_EQ(blades.camera.aperture.rotation_degrees, 12.f);

    const struct {
        std::string keys, message;
    } errors[] = {
        {", \"aperture_radius\": 0.1, \"f_number\": 2", "both aperture_radius and f_number"},
        {", \"f_number\": 2", "f_number needs \"focal_length\""},
        {", \"focal_length\": 0.05", "focal_length only goes with f_number"},
        {", \"focus_distance\": 3", "need an aperture"},
        {", \"blades\": 6", "need an aperture"},
        {", \"aperture_radius\": 0.1, \"focus_distance\": 0", "camera focus_distance is 0; expected a number in (0"},
        {", \"aperture_radius\": -1", "camera aperture_radius is -1"},
        {", \"aperture_radius\": 0.1, \"focus_point\": [0, 0, 6]", "focus_point is not in front of the camera"},
        {", \"aperture_radius\": 0.1, \"focus_point\": [0, 0, 1], \"focus_distance\": 2", "both focus_distance and focus_point"},
        {", \"aperture_radius\": 0.1, \"blades\": 2", "camera blades is 2; expected an integer from 3"},
        {", \"aperture_radius\": 0.1, \"rotation_degrees\": 5", "rotation_degrees turns the blades"},
    };
    for (const auto& e : errors) EXPECT_NE(error_of(camera(e.keys)).find(e.message), std::string::npos) << error_of(camera(e.keys));
}

/// Scenes built in code are checked too: a lens needs a positive focus distance and a
/// non-negative radius, blades 0 or 3 to 64.
TEST(DepthOfField, SceneChecksTheLens) {
    auto finalized = [](float radius, float focus, int blades) {
        Scene scene;
        scene.camera.aperture = {radius, blades, 0.f};
        scene.camera.focus_distance = focus;
        scene.finalize();
    };
    EXPECT_NO_THROW(finalized(0.1f, 2.f, 6));
    EXPECT_NO_THROW(finalized(0.f, 0.f, 0));  // the pinhole has no focus
    EXPECT_THROW(finalized(-0.1f, 2.f, 0), SceneError);
    EXPECT_THROW(finalized(0.1f, 0.f, 0), SceneError);
    EXPECT_THROW(finalized(0.1f, 2.f, 2), SceneError);
}

}  // namespace
}  // namespace spt

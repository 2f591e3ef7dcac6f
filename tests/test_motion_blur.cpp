// Motion blur: the rigid motion's interpolation and swept bounds, the time coverage of a
// translating sphere against its analytic value, a shutter on a static scene, a frozen instant
// against the static shape placed there, moving meshes against the same mesh moved by hand,
// agreement of path and bdpt, determinism, and the scene keys.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <string>

#include "core/rng.h"
#include "geometry/dvec3.h"
#include "geometry/motion.h"
#include "scene/scene_loader.h"
#include "test_scenes.h"

namespace spt {
namespace {

using test::compare;
using test::Comparison;
using test::describe;
using test::render_film;
using test::small_settings;

constexpr double kZ = 5.0;
constexpr float kPi_f = std::numbers::pi_v<float>;

Scene load(const std::string& text) { return test::load_exact_scene(text, "motion"); }
std::string error_of(const std::string& text) { return test::scene_error(text, "motion"); }
void expect_near(const Vec3& a, const Vec3& b, float tolerance, const std::string& what) {
    EXPECT_NEAR(a.x, b.x, tolerance) << what;
    EXPECT_NEAR(a.y, b.y, tolerance) << what;
    EXPECT_NEAR(a.z, b.z, tolerance) << what;
}

/// Translation 0 → (2, 0, 0) and rotation 0 → 90° about z around the pivot (1, 0, 0): at
/// t = 0.5 the point (2, 0, 0) has turned 45° about the pivot and moved by 1; the inverse
/// undoes it; outside the keyframes the motion holds still.
/// Rays from the plane z = 4 towards the box [x0, x0 + 2] × [−1, 1]²: `moving` at `time` is hit
/// where `placed` (the same shapes moved by hand to their place at `time`) is, at the same
/// distance, point and normal, and occludes up to that distance and no further; more than
/// `min_hits` hits, and at most 4 rays that graze an edge or rim hit one and miss the other
/// (rounding may differ there).
void expect_hits_where_placed(const Scene& moving, const Scene& placed, float time, Rng& rng, float x0, int min_hits) {
    int hits = 0, mismatches = 0;
    for (int i = 0; i < 4000; ++i) {
        const Vec3 o(rng.uniform() * 6 - 3, rng.uniform() * 6 - 3, 4.f);
        const Vec3 target(rng.uniform() * 2 + x0, rng.uniform() * 2 - 1, rng.uniform() * 2 - 1);
        const Ray ray{o, normalize(target - o), kInfinity};
        const auto a = moving.intersect(ray, time);
        const auto b = placed.intersect(ray);
        if (a.has_value() != b.has_value()) {
            ++mismatches;
            continue;
        }
        if (!a) continue;
        ++hits;
        EXPECT_NEAR(a->t, b->t, 1e-4f * b->t) << time;
        expect_near(a->p, b->p, 1e-4f, "hit point");
        EXPECT_NEAR(dot(a->n, b->n), 1.f, 1e-4f);
        EXPECT_EQ(a->prim.kind(), ShapeKind::moving);
        EXPECT_EQ(moving.occluded(Ray{o, ray.d, a->t * 0.999f}, {}, time), false);
        EXPECT_EQ(moving.occluded(Ray{o, ray.d, a->t * 1.001f}, {}, time), true);
    }
    EXPECT_GT(hits, min_hits) << time;
    EXPECT_LE(mismatches, 4) << time;
}

TEST(MotionBlur, RigidMotionInterpolatesAndInverts) {
    RigidMotion m;
    m.pivot = Vec3(1, 0, 0);
    m.keys = {Keyframe{0.f, Vec3(0, 0, 0), Quaternion{}},
              Keyframe{1.f, Vec3(2, 0, 0), Quaternion::axis_angle(Vec3(0, 0, 1), 0.5f * kPi_f)}};
    const float s = std::sqrt(0.5f);
    expect_near(m.at(0.5f).point(Vec3(2, 0, 0)), Vec3(1 + s + 1, s, 0), 1e-6f, "half way");
    expect_near(m.at(1.f).point(Vec3(2, 0, 0)), Vec3(1 + 2, 1, 0), 1e-6f, "end");
    expect_near(m.at(7.f).point(Vec3(2, 0, 0)), Vec3(1 + 2, 1, 0), 1e-6f, "after the last keyframe");
    expect_near(m.at(-3.f).point(Vec3(2, 0, 0)), Vec3(2, 0, 0), 0.f, "before the first keyframe");
    expect_near(m.at(0.5f).vector(Vec3(1, 0, 0)), Vec3(s, s, 0), 1e-6f, "a direction turns only");
    Rng rng(1, 2, 3);
    for (int i = 0; i < 1000; ++i) {
        const RigidTransform xf = m.at(rng.uniform());
        const Vec3 x(rng.uniform() * 4 - 2, rng.uniform() * 4 - 2, rng.uniform() * 4 - 2);
        expect_near(xf.inverse_point(xf.point(x)), x, 1e-5f, "inverse");
        EXPECT_NEAR(length(xf.vector(normalize(x))), 1.f, 1e-6f);
    }
    // Slerp takes the shorter arc: keyframes at 0° and 270° turn by −90° (through −45°).
    const Quaternion a{}, b = Quaternion::axis_angle(Vec3(0, 0, 1), 1.5f * kPi_f);
    expect_near(slerp(a, b, 0.5f).rotate(Vec3(1, 0, 0)), Vec3(s, -s, 0), 1e-6f, "shorter arc");
}

/// Every point of the shape at every time lies in the swept box, with and without rotation
/// (a box bound from the keyframes' boxes alone would miss a turning shape's corners).
TEST(MotionBlur, SweptBoundsHoldTheShapeAtEveryTime) {
    const Aabb rest{Vec3(0.5f, -0.2f, 1.f), Vec3(1.5f, 0.3f, 1.2f)};
    for (const bool rotate : {false, true}) {
        RigidMotion m;
        m.pivot = Vec3(0, 0, 1);
        const Quaternion turn = rotate ? Quaternion::axis_angle(normalize(Vec3(1, 2, 3)), 2.5f) : Quaternion{};
        m.keys = {Keyframe{0.f, Vec3(0, 0, 0), Quaternion{}}, Keyframe{0.3f, Vec3(1, -2, 0.5f), turn},
                  Keyframe{1.f, Vec3(-1, 0, 0), Quaternion{}}};
        const Aabb swept = m.swept_bounds(rest);
        Rng rng(4, 5, 6);
        for (int i = 0; i < 20000; ++i) {
            const Vec3 x(rest.lo.x + rng.uniform() * (rest.hi.x - rest.lo.x),
                         rest.lo.y + rng.uniform() * (rest.hi.y - rest.lo.y),
                         rest.lo.z + rng.uniform() * (rest.hi.z - rest.lo.z));
            const Vec3 p = m.at(rng.uniform()).point(x);
            for (int a = 0; a < 3; ++a) {
                ASSERT_GE(p[a], swept.lo[a]) << rotate;
                ASSERT_LE(p[a], swept.hi[a]) << rotate;
            }
        }
    }
}

/// The fraction of the shutter [0, 1] during which the ray from the origin along unit d
/// passes within R of the centre c0 + v·t: |c × d|² < R² is a quadratic in t.
double covered_time(const DVec3& d, const DVec3& c0, const DVec3& v, double R) {
    const double cd = dot(c0, d), vd = dot(v, d);
    const double A = dot(v, v) - vd * vd, B = 2 * (dot(c0, v) - cd * vd), C = dot(c0, c0) - cd * cd - R * R;
    const double disc = B * B - 4 * A * C;
    if (A <= 0 || disc <= 0) return C < 0 ? 1.0 : 0.0;
    const double t0 = (-B - std::sqrt(disc)) / (2 * A), t1 = (-B + std::sqrt(disc)) / (2 * A);
    return std::max(0.0, std::min(t1, 1.0) - std::max(t0, 0.0));
}

/// A black sphere crossing the frame at constant speed in front of a white environment. A
/// pixel's value, relative to the same render without the sphere (same seed: the same
/// wavelengths and jitter per sample), is the fraction of the pixel's rays × shutter that
/// miss the sphere: the analytic time coverage averaged over the pixel (a 16×16 grid of its
/// rays). Each pixel within 5σ of its Bernoulli noise. A sphere moving at another speed, over
/// another interval, at times not uniform in the shutter, or culled by a wrong swept box,
/// fails at many pixels.
TEST(MotionBlur, TranslatingSphereCoversEachPixelForTheAnalyticTime) {
    const int W = 40, H = 12, spp = 400;
    const double R = 0.3, z = -4, x0 = -1.2, x1 = 1.0, vfov = 20;
    auto scene_text = [&](bool sphere) {
        return std::string("{\"camera\": {\"position\": [0, 0, 0], \"look_at\": [0, 0, -1], \"vfov_degrees\": 20, "
                           "\"shutter\": [0, 1]}, \"background\": 1, \"materials\": {\"black\": {\"kd\": 0}}, "
                           "\"shapes\": [") +
               (sphere ? "{\"type\": \"sphere\", \"center\": [-1.2, 0.1, -4], \"radius\": 0.3, \"material\": \"black\", "
                         "\"motion\": {\"keyframes\": [{\"time\": 0}, {\"time\": 1, \"translate\": [2.2, 0, 0]}]}}"
                       : "") +
               "]}";
    };
    const Scene moving = load(scene_text(true));
    ASSERT_TRUE(moving.effects.motion_blur);
    const RenderSettings rs = small_settings(W, H, spp, 5);
    const auto film = render_film(moving, rs);
    const auto empty = render_film(load(scene_text(false)), rs);
    const double half_h = std::tan(vfov / 2 * std::numbers::pi / 180), half_w = half_h * W / H;
    int checked = 0, partial = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            double expected = 0;
            constexpr int kSub = 16;
            for (int j = 0; j < kSub; ++j)
                for (int i = 0; i < kSub; ++i) {
                    const double fx = (x + (i + 0.5) / kSub) / W, fy = (y + (j + 0.5) / kSub) / H;
                    const DVec3 d = normalize(DVec3((2 * fx - 1) * half_w, (1 - 2 * fy) * half_h, -1));
                    expected += 1 - covered_time(d, DVec3(x0, 0.1, z), DVec3(x1 - x0, 0, 0), R);
                }
            expected /= kSub * kSub;
            const double measured = film->pixel_xyz(x, y).y / empty->pixel_xyz(x, y).y;
            const double sigma = std::sqrt(expected * (1 - expected) / spp) * 1.2 + 2e-3;
            EXPECT_NEAR(measured, expected, kZ * sigma) << "pixel " << x << ", " << y;
            ++checked;
            partial += expected > 0.05 && expected < 0.95;
        }
    EXPECT_GT(partial, 40);  // the sphere's streak crosses many pixels partly
}

/// A cornell-like box whose grey sphere and point light may move.
std::string box_scene(const std::string& camera_extra, const std::string& sphere_extra,
                      const std::string& light_extra = "", const std::string& sphere_center = "[0, -0.5, 0]",
                      const std::string& light_position = "[0.5, 0.5, 0.5]") {
    return R"({"camera": {"position": [0, 0, 3.5], "look_at": [0, 0, 0], "vfov_degrees": 40)" + camera_extra + R"(},
  "materials": {"grey": {"kd": 0.7}, "red": {"kd": {"type": "rgb", "value": [0.7, 0.1, 0.1]}},
                "glass": {"kt": 1, "ior": 1.5}, "lamp": {"emission": 3}},
  "shapes": [
    {"type": "plane", "normal": [0, 1, 0], "point": [0, -1, 0], "material": "grey"},
    {"type": "plane", "normal": [0, 0, 1], "point": [0, 0, -1], "material": "red"},
    {"type": "quad", "origin": [-0.3, 0.99, -0.3], "edge1": [0.6, 0, 0], "edge2": [0, 0, 0.6], "material": "lamp"},
    {"type": "sphere", "center": )" + sphere_center + R"(, "radius": 0.4, "material": "grey")" + sphere_extra + R"(}
  ],
  "lights": [{"type": "point", "position": )" + light_position + R"(, "intensity": 1)" + light_extra + R"(}]})";
}
const char* kMovingSphere = R"(, "motion": {"keyframes": [{"time": 0}, {"time": 1, "translate": [0.6, 0.3, 0],
    "rotate": {"axis": [0, 0, 1], "degrees": 40}}]})";
const char* kMovingLight = R"(, "motion": {"keyframes": [{"time": 0}, {"time": 1, "translate": [-1, 0, 0]}]})";

/// Nothing moves: a shutter interval changes nothing, not one bit (no time is drawn).
TEST(MotionBlur, StaticSceneWithAShutterRendersAsWithoutOne) {
    const Scene plain = load(box_scene("", ""));
    const Scene shutter = load(box_scene(", \"shutter\": [0, 2]", ""));
    EXPECT_FALSE(shutter.effects.motion_blur);
    for (const IntegratorKind kind : {IntegratorKind::path, IntegratorKind::bdpt}) {
        RenderSettings rs = small_settings(24, 24, 8, 3);
        rs.integrator.kind = kind;
        const auto a = render_film(plain, rs);
        const auto b = render_film(shutter, rs);
        ASSERT_EQ(a->xyz_sums().size(), b->xyz_sums().size());
        EXPECT_EQ(std::memcmp(a->xyz_sums().data(), b->xyz_sums().data(), a->xyz_sums().size() * sizeof(double)), 0);
    }
}

/// A shutter that opens and closes at t = 0.5 shows the moving sphere and light where they
/// stand then: the image of the static scene with them placed there by hand, within noise.
/// The rest-frame intersection and its error bounds must hold (self-intersection of the moved
/// sphere would darken it far beyond the noise).
TEST(MotionBlur, AnInstantOfTheMotionIsTheStaticSceneThere) {
    const Scene instant = load(box_scene(", \"shutter\": [0.5, 0.5]", kMovingSphere, kMovingLight));
    EXPECT_FALSE(instant.effects.motion_blur);
    ASSERT_EQ(instant.moving_shapes.size(), 1u);
    const Scene placed = load(box_scene("", "", "", "[0.3, -0.35, 0]", "[0, 0.5, 0.5]"));
    const auto a = render_film(instant, small_settings(32, 32, 256, 7));
    const auto b = render_film(placed, small_settings(32, 32, 256, 8));
    const Comparison c = compare(*a, *b, [](int, int) { return true; });
    EXPECT_LE(c.max_z, kZ) << describe(c);
    EXPECT_NEAR(c.mean_a, c.mean_b, kZ * c.se) << describe(c);
}

/// A moving mesh (past the handful of triangles that are looped over, so through its rest
/// BVH) hit at time t exactly where the same triangles moved by hand to their place at t are.
TEST(MotionBlur, MovingMeshHitsWhereTheMovedMeshIs) {
    Rng rng(8, 9, 10);
    std::vector<std::array<Vec3, 3>> rest;
    for (int i = 0; i < 40; ++i) {
        const Vec3 c(rng.uniform() * 2 - 1, rng.uniform() * 2 - 1, rng.uniform() * 2 - 1);
        std::array<Vec3, 3> t{c, c + Vec3(0.3f * rng.uniform(), 0.05f, 0.1f), c + Vec3(0.02f, 0.3f * rng.uniform(), 0.2f)};
        rest.push_back(t);
    }
    // Built in code, as the loader builds a moving mesh: its triangles, then make_moving.
    Scene moving;
    moving.add_material(test::diffuse_material(0.5));
    for (const auto& t : rest) moving.triangles.push_back(Triangle{t[0], t[1], t[2], 0, -1, -1});
    RigidMotion motion;
    motion.pivot = Vec3(0.1f, 0.2f, 0.f);
    motion.keys = {Keyframe{0.f, Vec3(0, 0, 0), Quaternion{}},
                   Keyframe{1.f, Vec3(0.5f, -0.2f, 0.3f), Quaternion::axis_angle(normalize(Vec3(1, 1, 0)), 1.f)}};
    moving.make_moving(ShapeCounts{}, motion);
    moving.finalize();
    ASSERT_EQ(moving.moving_shapes.size(), 1u);
    ASSERT_FALSE(moving.moving_shapes[0].bvh.empty());
    for (const float time : {0.f, 0.37f, 1.f}) {
        Scene placed;
        placed.add_material(test::diffuse_material(0.5));
        const RigidTransform xf = motion.at(time);
        for (const auto& t : rest)
            placed.triangles.push_back(Triangle{xf.point(t[0]), xf.point(t[1]), xf.point(t[2]), 0, -1, -1});
        placed.finalize();
        expect_hits_where_placed(moving, placed, time, rng, -0.5f, 150);
    }
}

/// Every bounded shape type moves (geometry/shape.h, kCanMove): a disk, a cylinder and a cone
/// moving together (looped over, no BVH) are hit at time t where the same shapes moved by hand
/// to their place at t are; a scene file gives them "motion" too.
TEST(MotionBlur, MovingQuadricsHitWhereTheMovedQuadricsAre) {
    Rng rng(3, 4, 5);
    const Disk disk{{0.2f, -0.3f, 0.f}, normalize(Vec3(0.2f, 0.3f, 1.f)), 0.6f, 0, -1};
    const Cylinder cylinder{{-0.6f, -0.5f, -0.2f}, normalize(Vec3(0.1f, 1.f, 0.f)), 0.3f, 0.9f, 0, -1};
    const Cone cone{{0.6f, -0.4f, -0.3f}, normalize(Vec3(0.f, 1.f, 0.2f)), 0.4f, 0.8f, 0, -1};
    Scene moving;
    moving.add_material(test::diffuse_material(0.5));
    moving.disks.push_back(disk), moving.cylinders.push_back(cylinder), moving.cones.push_back(cone);
    RigidMotion motion;
    motion.pivot = Vec3(0.f, 0.1f, 0.f);
    motion.keys = {Keyframe{0.f, Vec3(0, 0, 0), Quaternion{}},
                   Keyframe{1.f, Vec3(0.4f, -0.2f, 0.3f), Quaternion::axis_angle(normalize(Vec3(1, 0, 1)), 0.7f)}};
    moving.make_moving(ShapeCounts{}, motion);
    moving.finalize();
    ASSERT_EQ(moving.moving_shapes.size(), 1u);
    EXPECT_TRUE(moving.disks.empty() && moving.cylinders.empty() && moving.cones.empty());
    for (const float time : {0.f, 0.61f, 1.f}) {
        const RigidTransform xf = motion.at(time);
        Scene placed;
        placed.add_material(test::diffuse_material(0.5));
        Disk d = disk;
        d.center = xf.point(d.center), d.normal = normalize(xf.vector(d.normal));
        Cylinder c = cylinder;
        c.base = xf.point(c.base), c.axis = normalize(xf.vector(c.axis));
        Cone k = cone;
        k.base = xf.point(k.base), k.axis = normalize(xf.vector(k.axis));
        placed.disks.push_back(d), placed.cylinders.push_back(c), placed.cones.push_back(k);
        placed.finalize();
        expect_hits_where_placed(moving, placed, time, rng, -1.f, 300);
    }
    const Scene loaded = load(R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]}, "materials": {"g": {"kd": 0.5}},
      "shapes": [{"type": "cone", "base": [0, 0, 0], "axis": [0, 1, 0], "radius": 0.5, "height": 1, "material": "g",
                  "motion": {"keyframes": [{"time": 0}, {"time": 1, "translate": [1, 0, 0]}]}}]})");
    ASSERT_EQ(loaded.moving_shapes.size(), 1u);
    EXPECT_EQ(loaded.moving_shapes[0].cones.size(), 1u);
    EXPECT_TRUE(loaded.cones.empty());
}

/// bdpt against the path tracer with the sphere and the point light moving: a light subpath
/// at another time than its camera subpath, or a shadow ray at time 0, shows here.
TEST(MotionBlur, BdptAgreesWithThePathTracer) {
    const Scene scene = load(box_scene("", kMovingSphere, kMovingLight));
    ASSERT_TRUE(scene.effects.motion_blur);
    test::expect_bdpt_matches_path(scene, 51);
}

/// The time comes from each sample's own stream: the same bits for any thread count, with
/// the lens too. vcm refuses the scene.
TEST(MotionBlur, ThreadCountDoesNotChangeTheFilmAndVcmRefuses) {
    const Scene scene = load(box_scene(", \"aperture_radius\": 0.1, \"focus_distance\": 3.5", kMovingSphere, kMovingLight));
    ASSERT_TRUE(scene.effects.motion_blur && scene.effects.depth_of_field);
    for (const IntegratorKind kind : {IntegratorKind::path, IntegratorKind::bdpt}) {
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
    RenderSettings rs = small_settings(8, 8, 1, 9, 1);
    rs.integrator.kind = IntegratorKind::vcm;
    EXPECT_THROW(render_film(scene, rs), std::invalid_argument);
}

TEST(MotionBlur, SceneKeys) {
    const Scene s = load(box_scene(", \"shutter\": [0.25, 0.75]", kMovingSphere, kMovingLight));
    EXPECT_FLOAT_EQ(s.camera.shutter_open, 0.25f);
    EXPECT_FLOAT_EQ(s.camera.shutter_close, 0.75f);
    ASSERT_EQ(s.moving_shapes.size(), 1u);
    EXPECT_EQ(s.moving_shapes[0].spheres.size(), 1u);
    EXPECT_EQ(s.spheres.size(), 0u);  // it left the static shapes
    expect_near(s.moving_shapes[0].motion.pivot, Vec3(0, -0.5f, 0), 1e-6f, "default pivot: the shape's centre");
    EXPECT_NE(s.effects.describe().find("motion blur"), std::string::npos);
    const Scene light_only = load(box_scene("", "", kMovingLight));
    EXPECT_TRUE(light_only.effects.motion_blur);
    EXPECT_EQ(load(box_scene("", "")).effects.describe().find("motion blur"), std::string::npos);

    const struct {
        std::string camera, sphere, message;
    } errors[] = {
        {", \"shutter\": [1, 0]", "", "camera shutter closes before it opens"},
        {", \"shutter\": [0]", "", "camera shutter is an array of 1 values"},
        {"", R"(, "motion": {"keyframes": [{"time": 0}]})", "at least 2 keyframes"},
        {"", R"(, "motion": {"keyframes": [{"time": 1}, {"time": 0.5}]})", "does not follow 1; expected increasing times"},
        {"", R"(, "motion": {"keyframes": [{"time": 0}, {"time": 1, "spin": 3}]})", "unknown key \"spin\""},
        {"", R"(, "motion": {"keyframes": [{"time": 0}, {"time": 1, "rotate": {"axis": [0, 0, 0], "degrees": 3}}]})",
         "axis is the zero vector"},
        // A half turn between two keyframes goes either way round: refused, at its "rotate".
        {"", R"(, "motion": {"keyframes": [{"time": 0}, {"time": 1, "rotate": {"axis": [0, 1, 0], "degrees": 180}}]})",
         "motion keyframe rotate turns 180 degrees from the keyframe before, which is ambiguous"},
        {"", R"(, "motion": {"keyframes": [{"time": 0, "rotate": {"axis": [1, 0, 0], "degrees": 90}},
                 {"time": 1, "rotate": {"axis": [1, 0, 0], "degrees": -90}}]})", "turns 180 degrees"},
        {"", R"(, "motion": {"keyframes": [{"time": 0, "rotate": {"axis": [0, 0, 1], "degrees": 540}}, {"time": 1}]})",
         "turns 180 degrees"},
    };
    for (const auto& e : errors) {
        const std::string message = error_of(box_scene(e.camera, e.sphere));
        EXPECT_NE(message.find(e.message), std::string::npos) << message;
    }
    // Just short of a half turn, or past it (the shorter arc is then the other way), is clear.
    for (const char* degrees : {"179.9", "-179.9", "190"})
        EXPECT_NO_THROW(load(box_scene("", std::string(R"(, "motion": {"keyframes": [{"time": 0}, {"time": 1, "rotate": )"
                                                       R"({"axis": [0, 1, 0], "degrees": )") + degrees + "}}]}")))
            << degrees;
    const std::string plane = error_of(R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]}, "materials": {"g": {"kd": 0.5}},
      "shapes": [{"type": "plane", "normal": [0, 1, 0], "point": [0, 0, 0], "material": "g",
                  "motion": {"keyframes": [{"time": 0}, {"time": 1}]}}]})");
    EXPECT_NE(plane.find("plane (shape 0) cannot move"), std::string::npos) << plane;
    const std::string emitter = error_of(R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]},
      "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "emission": 2,
                  "motion": {"keyframes": [{"time": 0}, {"time": 1}]}}]})");
    EXPECT_NE(emitter.find("emits light and moves"), std::string::npos) << emitter;
    // Media and motion blur together are refused (the volumetric path tracer has no time).
    std::string media_error = "(no error)";
    try {
        load(R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]}, "materials": {"g": {"kd": 0.5}},
          "media": {"fog": {"type": "homogeneous", "sigma_a": 0.1, "sigma_s": 0.1}}, "medium": "fog",
          "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "g",
                      "motion": {"keyframes": [{"time": 0}, {"time": 1, "translate": [1, 0, 0]}]}}]})");
    } catch (const std::exception& e) {
        media_error = e.what();
    }
    EXPECT_NE(media_error.find("participating media and motion blur"), std::string::npos) << media_error;
}

}  // namespace
}  // namespace spt

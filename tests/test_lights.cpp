// Next-event estimation's light sampling (model/lights): for every light type, the sampled
// directions follow the density sample_li returns (chi-square), that density is the one
// pdf_li reports for a ray that finds the light (what MIS weights use), and the irradiance
// estimated from the samples matches the analytic value. Each light stands alone in a scene
// built here, so a ray from the reference point finds it through Scene::intersect, as in the
// path tracer.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <tuple>
#include <variant>
#include <vector>

#include "chi2.h"
#include "cone_histogram.h"
#include "render/direct_light.h"
#include "scene/scene.h"
#include "test_scenes.h"

namespace {

using spt::LightSampleContext;
using spt::Scene;
using spt::ShapeKind;
using spt::Vec3;
constexpr double kPi = std::numbers::pi;

spt::Spectrum constant(double v) { return spt::test::constant_spectrum(v); }

/// A scene with one black diffuse material and nothing else yet.
Scene empty_scene() {
    Scene scene;
    scene.add_material(spt::test::black_material());
    return scene;
}

/// A scene of one black shape of the given kind (stored in `array`) emitting radiance le.
template <typename Shape>
Scene one_emitter_scene(Shape shape, ShapeKind kind, std::vector<Shape> spt::ShapeArray<Shape>::*array, double le) {
    Scene scene = empty_scene();
    shape.material = 0;
    shape.light = scene.add_emitter(kind, constant(le));
    (scene.*array).push_back(shape);
    scene.finalize();
    return scene;
}

Scene sphere_light_scene(Vec3 center, float radius, double le) {
    return one_emitter_scene(spt::Sphere{center, radius}, ShapeKind::sphere, &Scene::spheres, le);
}

/// A parallelogram o, o + e1, o + e1 + e2, o + e2 as two triangles of one light.
Scene quad_light_scene(Vec3 o, Vec3 e1, Vec3 e2, double le) {
    Scene scene = empty_scene();
    const int light = scene.add_emitter(ShapeKind::triangle, constant(le));
    spt::Triangle a{o, o + e1, o + e1 + e2, 0}, b{o, o + e1 + e2, o + e2, 0};
    a.light = b.light = light;
    scene.triangles.push_back(a);
    scene.triangles.push_back(b);
    scene.finalize();
    return scene;
}

Scene plane_light_scene(Vec3 normal, float offset, double le) {
    return one_emitter_scene(spt::Plane{normal, offset}, ShapeKind::plane, &Scene::planes, le);
}

Scene environment_scene(double le) {
    Scene scene = empty_scene();
    scene.set_background(constant(le));
    scene.finalize();
    return scene;
}

LightSampleContext context(Vec3 p, Vec3 n, bool both_sides = false) { return {p, {0, 0, 0}, n, n, both_sides}; }

spt::SampledWavelengths wavelengths() { return spt::SampledWavelengths::sample(0.37f); }

/// pdf_li of light `k` for the ray from ctx.p along d, found through the scene as the path
/// tracer finds it (0 when the ray misses the light).
double pdf_along(const Scene& scene, int k, const LightSampleContext& ctx, const Vec3& d) {
    const std::optional<spt::Hit> hit = scene.intersect({ctx.p, d, spt::kInfinity});
    if (hit && hit->light != k) return 0.0;
    if (!hit && spt::light_type(scene.lights[k]) != spt::LightType::infinite) return 0.0;
    return spt::light_pdf_li(scene.lights[k], ctx, d, hit ? &*hit : nullptr);
}

/// Chi-square test of sample_li's directions against pdf_li over a cone of directions about
/// `axis` (cos θ ≥ cos_max; −1: the whole sphere), in 12 × 12 cells equal in solid angle.
struct DirectionTest {
    spt_test::Chi2Result chi2;
    double max_pdf_mismatch = 0;  ///< largest |ls.pdf / pdf_li − 1| over the samples
    int samples = 0;
};

DirectionTest direction_test(const Scene& scene, int k, const LightSampleContext& ctx, const Vec3& axis,
                             double cos_max, int n, std::uint64_t seed, int sub = 6) {
    spt_test::ConeHistogram histogram(axis, cos_max, 12, 12);
    const std::vector<double> expected =
        histogram.expected([&](const Vec3& d) { return pdf_along(scene, k, ctx, d); }, n, sub);
    DirectionTest result;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    const spt::SampledWavelengths lambda = wavelengths();
    for (int s = 0; s < n; ++s) {
        const auto ls = spt::light_sample_li(scene.lights[k], ctx, lambda, u(rng), u(rng));
        if (!ls) {
            histogram.add_outside();  // no direction: counted with the outside
            continue;
        }
        ++result.samples;
        const double ref = pdf_along(scene, k, ctx, ls->wi);
        result.max_pdf_mismatch =
            std::max(result.max_pdf_mismatch, ref > 0 ? std::fabs(ls->pdf / ref - 1.0) : 1.0);
        histogram.add(ls->wi);
    }
    result.chi2 = spt_test::chi2_test(histogram.observed(), expected);
    return result;
}

/// The significance of each chi-square test: with about 15 tests in this file, a false alarm
/// in any of them stays below 1.5e-4.
constexpr double kAlpha = 1e-5;

/// sub: the midpoint grid per cell side that integrates the expected counts (finer where
/// the density's support ends inside cells).
void expect_directions_follow_pdf(const Scene& scene, int k, const LightSampleContext& ctx, const Vec3& axis,
                                  double cos_max, const std::string& what, double pdf_tolerance = 2e-3,
                                  int sub = 6) {
    const DirectionTest t = direction_test(scene, k, ctx, axis, cos_max, 200000, 12345, sub);
    EXPECT_GT(t.chi2.p_value, kAlpha) << what << ": X² = " << t.chi2.statistic << " dof " << t.chi2.dof;
    EXPECT_EQ(t.chi2.observed_in_empty, 0) << what << ": samples where pdf_li is 0";
    // The returned density is the one pdf_li gives (float rounding of the two computations).
    EXPECT_LT(t.max_pdf_mismatch, pdf_tolerance) << what;
    EXPECT_GT(t.samples, 190000) << what;
}

/// Irradiance at ctx from light k, estimated as the mean of L·max(0, cos θ)/pdf over samples
/// (nothing occludes in these scenes), with its standard error.
struct Estimate {
    double mean, stderr_;
};
Estimate irradiance(const Scene& scene, int k, const LightSampleContext& ctx, int n, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    const spt::SampledWavelengths lambda = wavelengths();
    double sum = 0, sum2 = 0;
    for (int s = 0; s < n; ++s) {
        double x = 0;
        if (const auto ls = spt::light_sample_li(scene.lights[k], ctx, lambda, u(rng), u(rng)))
            x = ls->L[0] * std::max(0.f, spt::dot(ls->wi, ctx.ns)) / ls->pdf;
        sum += x, sum2 += x * x;
    }
    const double mean = sum / n;
    return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n)};
}

void expect_irradiance(const Estimate& e, double analytic, const std::string& what) {
    // 5 standard errors, plus float rounding of the samples (1e-5 relative).
    EXPECT_NEAR(e.mean, analytic, 5 * e.stderr_ + 1e-5 * analytic) << what << " (stderr " << e.stderr_ << ")";
}

// ---------------------------- Sphere: the cone it subtends ----------------------------

TEST(SphereLight, DirectionsFollowTheConeDensity) {
    const Vec3 c(0.3f, 2.f, -0.4f);
    const float r = 0.5f;
    const Scene scene = sphere_light_scene(c, r, 2.0);
    const Vec3 p(0, 0, 0);
    const Vec3 axis = spt::normalize(c - p);
    const double d = spt::length(c - p);
    const double cos_cone = std::sqrt(1 - (r / d) * (r / d));
    // Cells over the cone the sphere subtends (ending at its rim, not across it).
    expect_directions_follow_pdf(scene, 0, context(p, {0, 1, 0}), axis, cos_cone - 1e-5, "outside");
}

TEST(SphereLight, SmallAndFarSphereKeepsItsDensity) {
    // sin²θmax = 1e-8: 1 − cos θmax would cancel to 0 in float without the small-angle form.
    const Vec3 c(0, 1e4f, 0);
    const Scene scene = sphere_light_scene(c, 1.f, 1.0);
    const LightSampleContext ctx = context({0, 0, 0}, {0, 1, 0});
    ASSERT_TRUE(std::holds_alternative<spt::SphereLight>(scene.lights[0]));
    const auto ls = spt::light_sample_li(scene.lights[0], ctx, wavelengths(), 0.5f, 0.25f);
    ASSERT_TRUE(ls.has_value());
    const double solid_angle = 2 * kPi * (1 - std::sqrt(1 - 1e-8));
    EXPECT_NEAR(ls->pdf * solid_angle, 1.0, 1e-4);
    EXPECT_GT(ls->wi.y, 0.9999f);
}

TEST(SphereLight, FromInsideSamplesTheArea) {
    const Scene scene = sphere_light_scene({0, 0, 0}, 1.f, 1.0);
    const LightSampleContext ctx = context({0.2f, -0.3f, 0.1f}, {0, 1, 0});
    // Every direction reaches the sphere: the whole sphere of directions.
    expect_directions_follow_pdf(scene, 0, ctx, {0, 1, 0}, -1.0, "inside", 5e-3);
}

TEST(SphereLight, IrradianceMatchesAnalytic) {
    // Facing the centre at distance d: E = π·L·sin²θmax = π·L·r²/d² (all above the horizon).
    const float r = 0.08f, d = 1.5f;
    const double le = 149.2;
    const Scene scene = sphere_light_scene({0, d, 0}, r, le);
    const Estimate e = irradiance(scene, 0, context({0, 0, 0}, {0, 1, 0}), 100000, 7);
    expect_irradiance(e, kPi * le * r * r / (d * d), "sphere r = 0.08 at 1.5");
}

// ---------------------------- Quad: its area ----------------------------

/// Chi-square of the points sample_li reaches on a parallelogram light o + s·e1 + t·e2 in
/// cells of (s, t), against pdf_li integrated over each cell through the change of measure
/// dω = |cos θ_light| dA / r² (cells in the light's own coordinates have no edge inside them,
/// unlike cells of directions). A wrong solid-angle conversion in pdf_li, or a sampler that
/// is not uniform by area, fails it.
spt_test::Chi2Result parallelogram_test(const Scene& scene, int k, const LightSampleContext& ctx, Vec3 o, Vec3 e1,
                                        Vec3 e2, int n, std::uint64_t seed) {
    constexpr int kCells = 12, kSub = 4;
    const Vec3 cross_e = spt::cross(e1, e2);
    const double area = spt::length(cross_e);
    const Vec3 normal = cross_e / float(area);
    std::vector<double> expected(kCells * kCells, 0.0), observed(kCells * kCells, 0.0);
    for (int i = 0; i < kCells; ++i)
        for (int j = 0; j < kCells; ++j) {
            double sum = 0;
            for (int a = 0; a < kSub; ++a)
                for (int b = 0; b < kSub; ++b) {
                    const float si = float((i + (a + 0.5) / kSub) / kCells), tj = float((j + (b + 0.5) / kSub) / kCells);
                    const Vec3 x = o + e1 * si + e2 * tj;
                    const Vec3 d = x - ctx.p;
                    const double r2 = spt::length_squared(d);
                    const Vec3 w = d / std::sqrt(float(r2));
                    sum += pdf_along(scene, k, ctx, w) * std::fabs(spt::dot(normal, w)) / r2;
                }
            expected[i * kCells + j] = sum / (kSub * kSub) * area / (kCells * kCells) * n;
        }
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    // (s, t) of a point: solve x − o = s·e1 + t·e2 in the plane (Cramer with e1 × e2).
    for (int i = 0; i < n; ++i) {
        const auto ls = spt::light_sample_li(scene.lights[k], ctx, wavelengths(), u(rng), u(rng));
        if (!ls) continue;
        const Vec3 q = ls->p - o;
        const double st_s = spt::dot(spt::cross(q, e2), cross_e) / (area * area);
        const double st_t = spt::dot(spt::cross(e1, q), cross_e) / (area * area);
        const int ci = std::clamp(int(st_s * kCells), 0, kCells - 1), cj = std::clamp(int(st_t * kCells), 0, kCells - 1);
        observed[ci * kCells + cj] += 1;
    }
    return spt_test::chi2_test(observed, expected);
}

TEST(TriangleMeshLight, QuadPointsFollowTheSolidAngleDensity) {
    const Vec3 o(-0.25f, 1.f, -0.25f), e1(0.5f, 0, 0), e2(0, 0, 0.5f);
    const Scene scene = quad_light_scene(o, e1, e2, 1.0);
    const LightSampleContext ctx = context({0.1f, 0, 0.05f}, {0, 1, 0});
    const spt_test::Chi2Result r = parallelogram_test(scene, 0, ctx, o, e1, e2, 200000, 21);
    EXPECT_GT(r.p_value, kAlpha) << "X² = " << r.statistic << " dof " << r.dof;
    // And each sample's density is pdf_li's for its direction.
    const DirectionTest t = direction_test(scene, 0, ctx, {0, 1, 0}, 0.0, 20000, 22);
    EXPECT_LT(t.max_pdf_mismatch, 2e-3);
}

TEST(TriangleMeshLight, UnequalTrianglesAreChosenByArea) {
    // A mesh light of one large and one small triangle: a triangle in proportion to its area
    // (chi-square of the counts), then a uniform point on it (its barycentrics mapped back
    // through the square-root warp are uniform on the unit square: cells of equal count).
    Scene scene = empty_scene();
    const int light = scene.add_emitter(ShapeKind::triangle, constant(1.0));
    spt::Triangle big{{-1, 1, -1}, {1, 1, -1}, {-1, 1, 1}, 0}, small{{1, 1, 1}, {1.2f, 1, 1}, {1, 1, 1.2f}, 0};
    big.light = small.light = light;
    scene.triangles = {big, small};
    scene.finalize();
    const LightSampleContext ctx = context({0, 0, 0}, {0, 1, 0});
    constexpr int kN = 100000, kCells = 6;
    std::vector<double> observed(2 * kCells * kCells, 0.0), expected(2 * kCells * kCells, 0.0);
    const double a_big = 2.0, a_small = 0.02;
    for (int c = 0; c < kCells * kCells; ++c) {
        expected[c] = kN * a_big / (a_big + a_small) / (kCells * kCells);
        expected[kCells * kCells + c] = kN * a_small / (a_big + a_small) / (kCells * kCells);
    }
    std::mt19937_64 rng(23);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (int i = 0; i < kN; ++i) {
        const auto ls = spt::light_sample_li(scene.lights[0], ctx, wavelengths(), u(rng), u(rng));
        ASSERT_TRUE(ls.has_value());
        const bool on_small = ls->p.x >= 0.999f && ls->p.z >= 0.999f;
        const spt::Triangle& t = on_small ? small : big;
        // Barycentrics of p (b1 along p1 − p0, b2 along p2 − p0), then the inverse warp.
        const Vec3 e1 = t.p1 - t.p0, e2 = t.p2 - t.p0, q = ls->p - t.p0, cr = spt::cross(e1, e2);
        const double b1 = spt::dot(spt::cross(q, e2), cr) / spt::length_squared(cr);
        const double b2 = spt::dot(spt::cross(e1, q), cr) / spt::length_squared(cr);
        const double b0 = 1 - b1 - b2, su = 1 - b0;
        const double w1 = su * su, w2 = su > 0 ? b1 / su : 0;
        const int ci = std::clamp(int(w1 * kCells), 0, kCells - 1), cj = std::clamp(int(w2 * kCells), 0, kCells - 1);
        observed[(on_small ? kCells * kCells : 0) + ci * kCells + cj] += 1;
    }
    const spt_test::Chi2Result r = spt_test::chi2_test(observed, expected);
    EXPECT_GT(r.p_value, kAlpha) << "X² = " << r.statistic << " dof " << r.dof;
}

/// Form factor from a differential area to a parallel rectangle a × b at height c with one
/// corner above it (Howell's catalogue, B-3).
double corner_form_factor(double a, double b, double c) {
    const double x = a / c, y = b / c;
    return (x / std::sqrt(1 + x * x) * std::atan(y / std::sqrt(1 + x * x)) +
            y / std::sqrt(1 + y * y) * std::atan(x / std::sqrt(1 + y * y))) /
           (2 * kPi);
}

Scene rectangle_light_scene(Vec3 o, Vec3 e1, Vec3 e2, double le) {
    Scene scene = empty_scene();
    const int light = scene.add_quad_emitter(o, e1, e2, constant(le));
    spt::Triangle a{o, o + e1, o + e1 + e2, 0}, b{o, o + e1 + e2, o + e2, 0};
    a.light = b.light = light;
    scene.triangles = {a, b};
    scene.finalize();
    return scene;
}

TEST(QuadLight, SolidAngleSamplingFollowsItsDensityNearAndFar) {
    // A quad's own light samples the spherical rectangle it subtends where it looks large
    // (Ureña et al. 2013) and its area elsewhere: close above the centre (the ceiling over
    // cornell-quad's light), off to the side, far away, and a rotated rectangle.
    const Vec3 o(-0.25f, 1.f, -0.25f), e1(0.5f, 0, 0), e2(0, 0, 0.5f);
    const Scene scene = rectangle_light_scene(o, e1, e2, 1.0);
    for (const Vec3& p : {Vec3(0, 1.02f, 0), Vec3(0.05f, 0.98f, 0.1f), Vec3(0.1f, 0, 0.05f), Vec3(1.5f, 0.2f, 0.7f)}) {
        const spt_test::Chi2Result r = parallelogram_test(scene, 0, context(p, {0, 1, 0}), o, e1, e2, 200000, 41);
        EXPECT_GT(r.p_value, kAlpha) << "from (" << p.x << ", " << p.y << ", " << p.z << "): X² = " << r.statistic;
    }
    const float c = std::cos(0.5f), s = std::sin(0.5f);
    const Vec3 r1(0.4f * c, 0.4f * s, 0), r2(0, 0, 0.3f), ro(0.2f, 0.5f, -0.1f);
    const Scene rotated = rectangle_light_scene(ro, r1, r2, 1.0);
    const spt_test::Chi2Result r = parallelogram_test(rotated, 0, context({0.3f, 0.4f, 0}, {0, 1, 0}), ro, r1, r2, 200000, 42);
    EXPECT_GT(r.p_value, kAlpha) << "rotated: X² = " << r.statistic;
}

TEST(QuadLight, IrradianceCloseAboveMatchesAnalyticWithLowVariance) {
    // 0.02 below the centre of a 0.5 × 0.5 light (as the ceiling above cornell-quad's light):
    // E = π·L·4·F(0.25, 0.25, 0.02). Sampling the area there makes each sample's weight
    // vary by the (r_max/r_min)² ≈ 300 of the distances; solid angle keeps it within cos θ.
    const double le = 48.0, h = 0.02;
    const Scene quad = rectangle_light_scene({-0.25f, float(h), -0.25f}, {0.5f, 0, 0}, {0, 0, 0.5f}, le);
    const Scene area = quad_light_scene({-0.25f, float(h), -0.25f}, {0.5f, 0, 0}, {0, 0, 0.5f}, le);
    const Estimate e = irradiance(quad, 0, context({0, 0, 0}, {0, 1, 0}), 100000, 43);
    const Estimate a = irradiance(area, 0, context({0, 0, 0}, {0, 1, 0}), 100000, 43);
    expect_irradiance(e, kPi * le * 4 * corner_form_factor(0.25, 0.25, h), "rectangle at 0.02");
    EXPECT_LT(e.stderr_ * 10, a.stderr_) << "solid angle " << e.stderr_ << ", area " << a.stderr_;
}

TEST(QuadLight, ShadowRaysSkipOnlyTheLightsOwnTriangles) {
    // Next-event estimation does not test a quad light's own triangles (ShadowSkip): a segment
    // ending on the quad's plane meets it only there. Same verdict with and without the skip
    // from points all around (through gaps of an occluding pair of triangles, from close to
    // the plane on both sides); negative control: skipping the occluder's light changes it.
    const Vec3 o(-0.25f, 0.98f, -0.25f), e1(0.5f, 0, 0), e2(0, 0, 0.5f);
    Scene scene = empty_scene();
    const int light = scene.add_quad_emitter(o, e1, e2, constant(1.0));
    const int blocker = scene.add_quad_emitter({-0.3f, 0.5f, -0.1f}, {0.4f, 0, 0}, {0, 0.1f, 0.3f}, constant(1.0));
    auto quad_triangles = [](Vec3 q, Vec3 a, Vec3 b, int l) {
        spt::Triangle t0{q, q + a, q + a + b, 0}, t1{q, q + a + b, q + b, 0};
        t0.light = t1.light = l;
        return std::vector<spt::Triangle>{t0, t1};
    };
    scene.triangles = quad_triangles(o, e1, e2, light);
    for (const spt::Triangle& t : quad_triangles({-0.3f, 0.5f, -0.1f}, {0.4f, 0, 0}, {0, 0.1f, 0.3f}, blocker))
        scene.triangles.push_back(t);
    scene.finalize();
    ASSERT_FALSE(scene.uses_bvh());
    std::mt19937 rng(44);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    int planar = 0, blocked = 0, control_differs = 0, samples = 0;
    for (int k = 0; k < 20000; ++k) {
        spt::Hit hit;
        hit.p = Vec3(2.f * u(rng) - 1.f, k % 4 == 0 ? 0.98f + 0.04f * (u(rng) - 0.5f) : 2.f * u(rng) - 1.f,
                     2.f * u(rng) - 1.f);
        hit.p_err = spt::rounded_point_error(hit.p);
        hit.n = hit.ns = Vec3(0, 1, 0);
        const LightSampleContext ctx{hit.p, hit.p_err, hit.n, hit.ns, true};
        const float u1 = u(rng), u2 = u(rng);
        const std::optional<spt::LightSample> ls =
            spt::light_sample_li(scene.lights[light], ctx, spt::SampledWavelengths::sample(0.5f), u1, u2);
        if (!ls) continue;
        ++samples;
        const spt::ShadowRay shadow = spt::shadow_ray_to(scene, hit, *ls, light);
        planar += shadow.skip.planar_light == light;
        const bool exact = scene.occluded(shadow.ray);
        blocked += exact;
        ASSERT_EQ(scene.occluded(shadow.ray, shadow.skip), exact) << "from (" << hit.p.x << ", " << hit.p.y << ", "
                                                                   << hit.p.z << ")";
        control_differs += scene.occluded(shadow.ray, {-1, blocker}) != exact;
    }
    EXPECT_EQ(planar, samples);
    EXPECT_GT(blocked, samples / 50) << "the occluder must block some rays for the test to mean anything";
    EXPECT_GT(control_differs, 0);
}

TEST(TriangleMeshLight, QuadIrradianceMatchesAnalytic) {
    // A 0.5 × 0.5 quad 1.98 above the point, centred: four corner rectangles of 0.25 × 0.25.
    const double le = 24.0, h = 1.98;
    const Scene scene = quad_light_scene({-0.25f, float(h), -0.25f}, {0.5f, 0, 0}, {0, 0, 0.5f}, le);
    const Estimate e = irradiance(scene, 0, context({0, 0, 0}, {0, 1, 0}), 100000, 8);
    expect_irradiance(e, kPi * le * 4 * corner_form_factor(0.25, 0.25, h), "quad 0.5 at 1.98");
}

// ---------------------------- Disk (and the other quadrics): their area ----------------------------

Scene disk_light_scene(Vec3 center, Vec3 normal, float radius, double le) {
    return one_emitter_scene(spt::Disk{center, normal, radius}, ShapeKind::disk, &Scene::disks, le);
}

TEST(QuadricLight, DiskDirectionsFollowTheAreaDensity) {
    const float h = 1.f, r = 0.5f;
    const Scene scene = disk_light_scene({0, h, 0}, {0, -1, 0}, r, 1.0);
    // From the axis the disk is a cone of half-angle atan(r/h) about it: the cells end at its
    // rim (a rim inside a cell would need the cell's integral to resolve an edge).
    const double cos_edge = h / std::sqrt(h * h + r * r);
    expect_directions_follow_pdf(scene, 0, context({0, 0, 0}, {0, 1, 0}), {0, 1, 0}, cos_edge - 1e-5, "disk");
}

TEST(QuadricLight, DiskIrradianceMatchesAnalytic) {
    // On the axis of a disk of radius r at height h: E = π·L·r²/(r² + h²).
    const double le = 12.0, r = 0.4, h = 2.2;
    const Scene scene = disk_light_scene({0, float(h), 0}, {0, -1, 0}, float(r), le);
    const Estimate e = irradiance(scene, 0, context({0, 0, 0}, {0, 1, 0}), 100000, 31);
    expect_irradiance(e, kPi * le * r * r / (r * r + h * h), "disk r = 0.4 at 2.2");
}

// ---------------------------- Infinite plane: the half-space that sees it ----------------------------

TEST(PlaneLight, DirectionsFollowTheLuneDensity) {
    // One side gathers: cosine about ns within the half-space facing the plane, for normals
    // facing it, across it, tilted away and nearly away from it (the lune from the whole
    // hemisphere down to a fifth of it). Cells over the hemisphere about ns; the lune's edge
    // towards the plane crosses them, hence the fine grid for their expected counts.
    const Scene scene = plane_light_scene({0, -1, 0}, -1.f, 1.0);  // y = 1, facing down
    for (const Vec3 n : {Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(0.6f, 0.8f, 0), Vec3(0, -0.6f, 0.8f)}) {
        const Vec3 ns = spt::normalize(n);
        const LightSampleContext ctx = context({0.3f, -0.7f, 0.2f}, ns);
        expect_directions_follow_pdf(scene, 0, ctx, ns, 0.0, "plane, ns.y = " + std::to_string(ns.y), 2e-3, 64);
    }
}

TEST(PlaneLight, BothSidesFollowTheCosineAboutItsNormal) {
    const Scene scene = plane_light_scene({0, -1, 0}, -1.f, 1.0);  // y = 1, facing down
    const LightSampleContext ctx = context({0.3f, -0.7f, 0.2f}, {1, 0, 0}, true);
    expect_directions_follow_pdf(scene, 0, ctx, {0, 1, 0}, 0.0, "plane, both sides");
}

TEST(PlaneLight, EverySampleOfADiffuseSurfaceGivesTheViewFactor) {
    // The lune sampler is proportional to the integrand L·cos θ: each sample's estimate is
    // π·L·(1 + cos α)/2 exactly (cosine sampling about the plane's normal had variance).
    const double le = 2.5;
    const Scene scene = plane_light_scene({0, 1, 0}, 2.f, le);  // y = 2
    for (double alpha_deg : {0.0, 30.0, 90.0, 150.0}) {
        const double a = alpha_deg * kPi / 180;
        const Vec3 n(0.f, float(std::cos(a)), float(std::sin(a)));
        const Estimate e = irradiance(scene, 0, context({0, 0, 0}, spt::normalize(n)), 20000, 3);
        const double exact = kPi * le * (1 + std::cos(a)) / 2;
        EXPECT_NEAR(e.mean, exact, 1e-5 * exact) << alpha_deg;
        EXPECT_LT(e.stderr_, 1e-5 * exact) << alpha_deg;
    }
}

TEST(PlaneLight, IrradianceOfTiltedSurfacesMatchesViewFactor) {
    // A surface tilted by α from facing the plane sees the fraction (1 + cos α)/2 of it:
    // E = π·L·(1 + cos α)/2 (α = 0: π·L, the plane fills the hemisphere).
    const double le = 4.0;
    const Scene scene = plane_light_scene({0, 1, 0}, 2.f, le);  // y = 2
    for (double alpha_deg : {0.0, 40.0, 90.0, 135.0}) {
        const double a = alpha_deg * kPi / 180;
        const Vec3 n(float(std::sin(a)), float(std::cos(a)), 0.f);
        const Estimate e = irradiance(scene, 0, context({0, 0, 0}, spt::normalize(n)), 100000, 9);
        expect_irradiance(e, kPi * le * (1 + std::cos(a)) / 2, "tilt " + std::to_string(alpha_deg));
    }
}

// ---------------------------- Infinite plane seen past other planes (plane_visibility.h) ----------------------------

/// cornell's planes: the emitting ceiling y = 1 and black walls x = ±1, floor y = −1 and
/// (with_back) back z = −1; the front is open.
Scene plane_box_scene(double le, bool with_back) {
    Scene scene = empty_scene();
    spt::Plane ceiling{{0, -1, 0}, -1.f};
    ceiling.material = 0;
    ceiling.light = scene.add_emitter(ShapeKind::plane, constant(le));
    scene.planes.push_back(ceiling);
    std::vector<spt::Plane> walls = {{{1, 0, 0}, -1.f}, {{-1, 0, 0}, -1.f}, {{0, 1, 0}, -1.f}};
    if (with_back) walls.push_back({{0, 0, 1}, -1.f});
    for (spt::Plane w : walls) {
        w.material = 0;
        scene.planes.push_back(w);
    }
    scene.finalize();
    return scene;
}

TEST(PlaneLightPastPlanes, StripIrradianceMatchesItsViewFactor) {
    // Walls x = ±1 leave the strip |x| ≤ 1 of the ceiling (infinite along z). A surface whose
    // normal lies in the x-y plane, at angle β from each edge's direction, sees the fraction
    // (sin β₊ − sin β₋)/2 of the hemisphere's projected solid angle (the 2-D view factor of
    // an infinite strip): E = π·L·(sin β₊ − sin β₋)/2, here with every sample exact too.
    const double le = 3.0;
    const Scene scene = plane_box_scene(le, false);
    for (const auto& [x, y, tilt_deg] : {std::tuple{0.0, -1.0, 0.0}, {0.5, -0.2, 0.0}, {-0.7, 0.3, 35.0},
                                         {0.2, -1.0, -60.0}}) {
        const double a = tilt_deg * kPi / 180;
        const Vec3 n(float(std::sin(a)), float(std::cos(a)), 0.f);
        // Angles of the edges (x = ±1 at height 1 − y) from n, in the x-y plane.
        const double h = 1 - y, to_right = std::atan2(1 - x, h), to_left = std::atan2(-1 - x, h);
        const double exact = kPi * le * (std::sin(to_right - a) - std::sin(to_left - a)) / 2;
        const Estimate e = irradiance(scene, 0, context({float(x), float(y), 0.f}, n), 20000, 5);
        expect_irradiance(e, exact, "strip from (" + std::to_string(x) + ", " + std::to_string(y) + ")");
        // Every sample gives the same value but for the tries that all miss (probability (1 − A)^16).
        EXPECT_LT(e.stderr_, 2e-3 * exact);
    }
}

TEST(PlaneLightPastPlanes, IrradianceMatchesTheLuneSamplerWithShadowRays) {
    // The whole box (back wall too): the sampler of what the walls leave against the plain
    // lune sampler whose directions are traced through the scene (0 where a wall is hit
    // first), at points of every wall and in the air, normals tilted every way.
    const double le = 2.0;
    const Scene box = plane_box_scene(le, true);
    const Scene open = plane_light_scene({0, -1, 0}, -1.f, le);
    const spt::SampledWavelengths lambda = wavelengths();
    struct Case {
        Vec3 p, n;
    };
    for (const Case& c : {Case{{0, -1, 0}, {0, 1, 0}}, Case{{-1, 0.2f, 0.5f}, {1, 0, 0}},
                          Case{{0.3f, -0.4f, -1}, {0, 0, 1}}, Case{{0.4f, 0.6f, 2.5f}, {0.3f, -0.5f, -0.8f}},
                          Case{{-0.9f, -0.95f, -0.9f}, {0.5f, 0.5f, 0.7f}}}) {
        const LightSampleContext ctx = context(c.p, spt::normalize(c.n));
        const Estimate past = irradiance(box, 0, ctx, 200000, 21);
        std::mt19937_64 rng(22);
        std::uniform_real_distribution<float> u(0.f, 1.f);
        double sum = 0, sum2 = 0;
        const int n = 400000;
        for (int s = 0; s < n; ++s) {
            double x = 0;
            if (const auto ls = spt::light_sample_li(open.lights[0], ctx, lambda, u(rng), u(rng))) {
                const std::optional<spt::Hit> hit = box.intersect({ctx.p, ls->wi, spt::kInfinity});
                if (hit && hit->light == 0) x = ls->L[0] * spt::dot(ls->wi, ctx.ns) / ls->pdf;
            }
            sum += x, sum2 += x * x;
        }
        const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
        EXPECT_NEAR(past.mean, mean, 5 * std::hypot(se, past.stderr_) + 1e-5 * mean)
            << "at (" << c.p.x << ", " << c.p.y << ", " << c.p.z << ")";
        EXPECT_LT(past.stderr_, se) << "the walls' shadows are gone";
    }
}

TEST(PlaneLightPastPlanes, DirectionsFollowTheirDensity) {
    // Chi-square of the sampled directions against pdf_li (0 where a wall is found first),
    // and the sample's density equal to pdf_li's. The box is open towards +z, so the visible
    // ceiling reaches the horizon there: from the wall point its sliver runs along the horizon
    // through cells where the midpoint grid finds no support, and a few exact samples land in
    // such "empty" cells. Those are allowed up to 1e-4 of the samples (seen: 9 of 200 000);
    // at each of them the returned density still matches pdf_li (max_pdf_mismatch), so they
    // are the grid's blind spot, not samples where the density is 0.
    const Scene scene = plane_box_scene(1.0, true);
    for (const auto& [p, n] : {std::pair{Vec3(0, -1, 0), Vec3(0, 1, 0)}, std::pair{Vec3(-0.9f, 0, 0.3f), Vec3(1, 0, 0)},
                               std::pair{Vec3(0.2f, -0.3f, 1.5f), Vec3(-0.3f, 0.6f, -0.7f)}}) {
        const Vec3 ns = spt::normalize(n);
        const std::string what = "box, n.y = " + std::to_string(ns.y);
        const DirectionTest t = direction_test(scene, 0, context(p, ns), ns, 0.0, 200000, 12345, 64);
        EXPECT_GT(t.chi2.p_value, kAlpha) << what << ": X² = " << t.chi2.statistic << " dof " << t.chi2.dof;
        EXPECT_LE(t.chi2.observed_in_empty, 20) << what << ": samples in cells the grid finds empty";
        EXPECT_LT(t.max_pdf_mismatch, 2e-3) << what;
        EXPECT_GT(t.samples, 190000) << what;
    }
}

TEST(PlaneLightPastPlanes, NoSampleCrossesAPlane) {
    // Every sampled direction reaches the ceiling before any wall (the shadow ray then skips
    // the planes, LightSample::past_planes).
    const Scene scene = plane_box_scene(1.0, true);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    const spt::SampledWavelengths lambda = wavelengths();
    int sampled = 0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3 p(u(rng) * 1.98f - 0.99f, u(rng) * 1.98f - 0.99f, u(rng) * 4 - 0.99f);
        const Vec3 ns = spt::normalize(Vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f));
        const auto ls = spt::light_sample_li(scene.lights[0], context(p, ns), lambda, u(rng), u(rng));
        if (!ls) continue;
        ++sampled;
        ASSERT_TRUE(ls->past_planes);
        const std::optional<spt::Hit> hit = scene.intersect({p, ls->wi, spt::kInfinity});
        ASSERT_TRUE(hit.has_value());
        EXPECT_EQ(hit->light, 0) << "a wall hit first from (" << p.x << ", " << p.y << ", " << p.z << ")";
    }
    EXPECT_GT(sampled, 10000);
}

/// Planes at random tilts about the origin (distance 0.6–1.4 from it, normals towards it
/// spread over the sphere), the first emitting: regions with corners at any angle, points at
/// infinity and, from many points, a blocker parallel to nothing.
Scene tilted_planes_scene(std::uint64_t seed, int count) {
    Scene scene = empty_scene();
    std::mt19937_64 rng(seed);
    std::normal_distribution<float> g(0.f, 1.f);
    std::uniform_real_distribution<float> u(0.6f, 1.4f);
    for (int i = 0; i < count; ++i) {
        const Vec3 n = spt::normalize(Vec3(g(rng), g(rng), g(rng)));
        spt::Plane plane{n, -u(rng)};  // dot(n, x) = −d: the origin on n's side
        plane.material = 0;
        if (i == 0) plane.light = scene.add_emitter(ShapeKind::plane, constant(1.0));
        scene.planes.push_back(plane);
    }
    scene.finalize();
    return scene;
}

/// The plane's normal turned towards it from p and p's distance from it.
std::pair<Vec3, double> towards_plane(const spt::PlaneLight& light, const Vec3& p) {
    const double s = light.side(p);
    return {light.towards(p), s};
}

TEST(PlaneLightPastPlanes, RegionPolygonMatchesTheClippingConstruction) {
    // The polygon seen through the region precomputed for p's sides of the blockers against
    // the one clipped from the lune at p (plane_visibility.h), at random points of cornell's
    // box (back wall too), on its walls and outside it, and in boxes of tilted planes: the
    // same projected area (both float, ~1e-6 of Φ, or 1e-6·π where Φ is tiny) and the same
    // verdict for directions away from the polygon's edges.
    struct Case {
        Scene scene;
        std::string name;
    };
    std::vector<Case> cases;
    cases.push_back({plane_box_scene(1.0, true), "cornell box"});
    for (std::uint64_t seed = 1; seed <= 4; ++seed)
        cases.push_back({tilted_planes_scene(seed, 3 + int(seed)), "tilted " + std::to_string(seed)});
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    std::normal_distribution<float> g(0.f, 1.f);
    for (const Case& c : cases) {
        const auto& light = std::get<spt::PlaneLight>(c.scene.lights[0]);
        ASSERT_GT(light.blocker_count, 0) << c.name;
        int compared = 0, nonempty = 0, directions = 0;
        for (int i = 0; i < 4000; ++i) {
            Vec3 p(u(rng) * 4 - 2, u(rng) * 4 - 2, u(rng) * 4 - 2);
            Vec3 ns = spt::normalize(Vec3(g(rng), g(rng), g(rng)));
            if (i % 4 == 0) {  // on a blocker, facing its normal's side
                const spt::PlaneBlocker& b = light.blockers[std::size_t(i / 4) % std::size_t(light.blocker_count)];
                p = p - b.normal * (spt::dot(b.normal, p) - b.offset);
                ns = (i / 4) % 2 ? b.normal : -b.normal;
            }
            const auto [m, s] = towards_plane(light, p);
            if (s == 0.0 || !(1.f + spt::dot(ns, m) > 1e-3f)) continue;
            const spt::VisibleLune clipped(p, ns, m, std::fabs(s), light.blockers.data(), light.blocker_count);
            const spt::VisibleLune& region = light.visible_from(p, ns, s);
            ++compared;
            const double phi = clipped.area(), tol = 1e-5 * std::max(phi, 0.1 * kPi);
            ASSERT_NEAR(region.area(), phi, tol) << c.name << " at (" << p.x << ", " << p.y << ", " << p.z << ")";
            if (phi < 1e-3) continue;
            ++nonempty;
            for (int k = 0; k < 50; ++k) {
                Vec3 w = spt::normalize(Vec3(g(rng), g(rng), g(rng)));
                if (spt::dot(w, ns) < 0.f) w = -w;
                // Away from the region polygon's edges (and from ns's and the plane's horizons).
                double margin = std::min(spt::dot(w, ns), spt::dot(w, m));
                const int n = region.vertex_count();
                for (int e = 0; e < n; ++e)
                    margin = std::min(margin, double(std::fabs(spt::dot(
                                                  w, spt::normalize(spt::cross(region.vertex(e),
                                                                               region.vertex((e + 1) % n)))))));
                if (margin < 1e-3) continue;
                ++directions;
                EXPECT_EQ(region.contains(w) && spt::dot(w, m) > 0.f, clipped.contains(w))
                    << c.name << " at (" << p.x << ", " << p.y << ", " << p.z << ")";
            }
        }
        EXPECT_GT(compared, 2000) << c.name;
        EXPECT_GT(nonempty, 300) << c.name;
        EXPECT_GT(directions, 5000) << c.name;
    }
}

TEST(PlaneLightPastPlanes, RegionPolygonFailsWithTheWrongSides) {
    // Negative control for the test above: the region of the other side of one blocker is
    // another polygon (at a point inside cornell's box, where each wall hides a part).
    const Scene scene = plane_box_scene(1.0, true);
    const auto& light = std::get<spt::PlaneLight>(scene.lights[0]);
    const Vec3 p(0.1f, -0.3f, 0.2f), ns = spt::normalize(Vec3(0.2f, 1.f, 0.1f));
    const auto [m, s] = towards_plane(light, p);
    const spt::VisibleLune clipped(p, ns, m, std::fabs(s), light.blockers.data(), light.blocker_count);
    unsigned signs = 0;
    for (int i = 0; i < light.blocker_count; ++i)
        if (spt::dot(light.blockers[std::size_t(i)].normal, p) > light.blockers[std::size_t(i)].offset) signs |= 1u << i;
    const bool reverse = double(light.region_handedness) * s > 0.0;
    EXPECT_NEAR(spt::VisibleLune(p, ns, light.regions[signs], reverse).area(), clipped.area(), 1e-5);
    for (int i = 0; i < light.blocker_count; ++i) {
        const spt::VisibleLune wrong(p, ns, light.regions[signs ^ (1u << i)], reverse);
        EXPECT_GT(std::fabs(wrong.area() - clipped.area()), 1e-2) << "blocker " << i;
    }
}

TEST(PlaneLightPastPlanes, TiltedPlanesDirectionsFollowTheirDensity) {
    // Chi-square as DirectionsFollowTheirDensity, among tilted planes (none parallel to the
    // emitting one; polygons of 4 and 5 corners).
    const Scene scene = tilted_planes_scene(3, 6);
    for (const auto& [p, n] : {std::pair{Vec3(0, 0, 0), Vec3(0.3f, 0.5f, -0.2f)}, std::pair{Vec3(0.2f, -0.3f, 0.1f), Vec3(-0.6f, 0.1f, 0.4f)}}) {
        const Vec3 ns = spt::normalize(n);
        // The polygons are small (Φ 0.14 and 0.02 of the lune's 1.7 and 1.05) and cut few
        // cells: their expected counts need the fine grid (at 32 per side the midpoint rule's
        // error alone gave X² = 144 for 21 dof from the first point, 16 at 128).
        const DirectionTest t = direction_test(scene, 0, context(p, ns), ns, 0.0, 200000, 777, 128);
        EXPECT_GT(t.chi2.p_value, kAlpha) << "X² = " << t.chi2.statistic << " dof " << t.chi2.dof;
        EXPECT_LE(t.chi2.observed_in_empty, 20);
        EXPECT_LT(t.max_pdf_mismatch, 2e-3);
        EXPECT_GT(t.samples, 50000);
    }
}

TEST(PlaneLightPastPlanes, RememberedPolygonGivesTheFreshDensity) {
    // pdf_li right after sample_li at the same point (the polygon remembered, as for the MIS
    // weight of the next bounce) equals the sample's density and pdf_li after another point
    // evicted it (built afresh), bit for bit; and the memo tells lights apart: the box
    // without its back wall, asked at the same point, answers with its own polygon.
    const Scene box = plane_box_scene(1.0, true), open = plane_box_scene(1.0, false);
    const spt::SampledWavelengths lambda = wavelengths();
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    int checked = 0, differ = 0;
    for (int i = 0; i < 2000; ++i) {
        const Vec3 p(u(rng) * 1.98f - 0.99f, u(rng) * 1.98f - 0.99f, u(rng) * 1.98f - 0.99f);
        const Vec3 ns = spt::normalize(Vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f));
        const LightSampleContext ctx = context(p, ns);
        const auto ls = spt::light_sample_li(box.lights[0], ctx, lambda, u(rng), u(rng));
        if (!ls) continue;
        ++checked;
        const float remembered = spt::light_pdf_li(box.lights[0], ctx, ls->wi, nullptr);
        const float other = spt::light_pdf_li(open.lights[0], ctx, ls->wi, nullptr);
        spt::light_pdf_li(box.lights[0], context(-p, ns), ls->wi, nullptr);  // evicts ctx
        const float fresh = spt::light_pdf_li(box.lights[0], ctx, ls->wi, nullptr);
        ASSERT_EQ(std::bit_cast<std::uint32_t>(remembered), std::bit_cast<std::uint32_t>(fresh));
        ASSERT_EQ(std::bit_cast<std::uint32_t>(ls->pdf), std::bit_cast<std::uint32_t>(fresh));
        // The open box's density at the same point is its own (built afresh after another
        // point evicted it), and differs wherever the back wall hid a part.
        spt::light_pdf_li(open.lights[0], context(-p, ns), ls->wi, nullptr);
        const float other_fresh = spt::light_pdf_li(open.lights[0], ctx, ls->wi, nullptr);
        ASSERT_EQ(std::bit_cast<std::uint32_t>(other), std::bit_cast<std::uint32_t>(other_fresh));
        if (other != remembered) ++differ;
    }
    EXPECT_GT(checked, 1000);
    EXPECT_GT(differ, checked / 4);
}

/// The sampler of the lune minus what the blockers hide, one try after the other as it was
/// written before its tries went four at a time in lanes, with Lambert's formula for Φ from
/// the polygon's vertices one edge at a time (scalar atan2): the reference sample_li must
/// equal bit for bit. first_try: the try whose numbers are the sample's own (1: a planted
/// off-by-one).
struct ScalarPastPlanes {
    Vec3 wi;
    float pdf = 0.f;
    bool found = false;
    int tries = 0;  ///< tries made
};
ScalarPastPlanes scalar_past_planes(const spt::PlaneLight& light, const LightSampleContext& ctx, float u1, float u2,
                                    int first_try = 0) {
    ScalarPastPlanes r;
    const double s = light.side(ctx.p);
    if (s == 0.0) return r;
    const Vec3 m = s > 0.0 ? -light.plane.normal : light.plane.normal;
    const float c = spt::dot(ctx.ns, m);
    if (!(1.f + c > spt::PlaneLight::kMinLune)) return r;
    const spt::VisibleLune& visible = light.visible_from(ctx.p, ctx.ns, s);
    if (visible.empty()) return r;
    // Φ edge by edge.
    double sum = 0.0;
    const int n = visible.vertex_count();
    for (int i = 0; i < n; ++i) {
        const Vec3 a = visible.vertex(i), b = visible.vertex(i + 1 == n ? 0 : i + 1);
        const Vec3 axb = spt::cross(a, b);
        const float sin_t = spt::length(axb);
        const float theta = static_cast<float>(spt::atan2_nonnegative(sin_t, spt::dot(a, b)));
        sum += double(sin_t > 1e-7f ? theta / sin_t : 1.f) * spt::dot(axb, ctx.ns);
    }
    const float area = static_cast<float>(0.5 * sum);
    EXPECT_EQ(std::bit_cast<std::uint32_t>(area), std::bit_cast<std::uint32_t>(visible.area()));
    const float c_lune = spt::PlaneLight::sampling_c(visible, c);
    const spt::PlaneLight::Lune lune(ctx.ns, c_lune == c ? m : visible.bound_normal(), c_lune);
    float v1 = u1, v2 = u2, cos_n = 0.f;
    for (int k = first_try; k < first_try + spt::PlaneLight::kMaxTries && !r.found; ++k) {
        ++r.tries;
        if (k > 0) spt::PlaneLight::retry_numbers(u1, u2, k, v1, v2);
        r.wi = lune.direction(v1, v2);
        cos_n = spt::dot(r.wi, ctx.ns);
        bool inside = true;
        for (int i = 0; i < n; ++i)
            inside = inside && spt::dot(r.wi, spt::cross(visible.vertex(i), visible.vertex(i + 1 == n ? 0 : i + 1))) >= 0.f;
        r.found = cos_n > 0.f && spt::dot(r.wi, m) > 0.f && inside;
    }
    if (r.found) r.pdf = spt::PlaneLight::visible_pdf(cos_n, c_lune, area);
    return r;
}

TEST(PlaneLightPastPlanes, LanesGiveTheOneTryAtATimeBits) {
    // sample_li (tries four at a time in lanes, the polygon's edges in lanes) against the
    // sampler written one try and one edge at a time: the same direction and density, bit
    // for bit, in the box with and without its back wall (3- and 4-vertex polygons, and more
    // where a vertex lies below ns's horizon and the polygon is clipped).
    const spt::SampledWavelengths lambda = wavelengths();
    std::mt19937_64 rng(21);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (const bool with_back : {true, false}) {
        const Scene scene = plane_box_scene(1.0, with_back);
        const spt::PlaneLight& light = std::get<spt::PlaneLight>(scene.lights[0]);
        int sampled = 0, late = 0, later_group = 0, shifted_differs = 0;
        for (int i = 0; i < 20000; ++i) {
            Vec3 p(u(rng) * 1.98f - 0.99f, u(rng) * 1.98f - 0.99f, u(rng) * 1.98f - 0.99f);
            if (i % 5 == 0) p.x = -1.f;  // on a wall: the polygon clipped by ns's hemisphere
            const Vec3 ns = spt::normalize(Vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f));
            const LightSampleContext ctx = context(p, ns);
            const float u1 = u(rng), u2 = u(rng);
            spt::LightSample ls;
            const bool found = light.sample_li(ctx, lambda, u1, u2, ls);
            const ScalarPastPlanes ref = scalar_past_planes(light, ctx, u1, u2);
            ASSERT_EQ(found, ref.found) << i;
            if (!found) continue;
            ++sampled;
            ASSERT_EQ(std::bit_cast<std::uint32_t>(ls.wi.x), std::bit_cast<std::uint32_t>(ref.wi.x)) << i;
            ASSERT_EQ(std::bit_cast<std::uint32_t>(ls.wi.y), std::bit_cast<std::uint32_t>(ref.wi.y)) << i;
            ASSERT_EQ(std::bit_cast<std::uint32_t>(ls.wi.z), std::bit_cast<std::uint32_t>(ref.wi.z)) << i;
            ASSERT_EQ(std::bit_cast<std::uint32_t>(ls.pdf), std::bit_cast<std::uint32_t>(ref.pdf)) << i;
            // Tries past the first, and past the first four lanes, are exercised.
            if (ref.tries > 1) ++late;
            if (ref.tries > 4) ++later_group;
            // Planted bug: tries shifted by one (try 1's numbers first) give other directions.
            const ScalarPastPlanes shifted = scalar_past_planes(light, ctx, u1, u2, 1);
            if (!shifted.found || shifted.wi != ref.wi) ++shifted_differs;
        }
        EXPECT_GT(sampled, 10000) << with_back;
        EXPECT_GT(late, sampled / 10) << with_back;
        EXPECT_GT(later_group, 100) << with_back;
        EXPECT_GT(shifted_differs, sampled / 2) << with_back;
    }
}

// ---------------------------- Environment: cosine, or uniform where both sides matter ----------------------------

TEST(EnvironmentLight, CosineAboutTheShadingNormal) {
    const Scene scene = environment_scene(1.0);
    const Vec3 n = spt::normalize(Vec3(0.2f, 0.9f, -0.3f));
    expect_directions_follow_pdf(scene, scene.infinite_light_indices.at(0), context({0, 0, 0}, n), n, 0.0, "cosine");
}

TEST(EnvironmentLight, UniformWhenBothSidesMatter) {
    const Scene scene = environment_scene(1.0);
    expect_directions_follow_pdf(scene, scene.infinite_light_indices.at(0), context({0, 0, 0}, {0, 1, 0}, true), {0, 1, 0}, -1.0,
                                 "uniform");
}

TEST(EnvironmentLight, IrradianceIsPiL) {
    const double le = 0.7;
    const Scene scene = environment_scene(le);
    const Estimate e = irradiance(scene, scene.infinite_light_indices.at(0), context({0, 0, 0}, {0, 0, 1}), 20000, 10);
    // Cosine sampling of a constant environment is exact: every sample is π·L.
    EXPECT_NEAR(e.mean, kPi * le, 1e-5);
    EXPECT_LT(e.stderr_, 1e-5);
}

// ---------------------------- The light list ----------------------------

TEST(LightList, LightsAreChosenInProportionToPower) {
    // Two spheres of radiance 1 and 3 and equal size, a point light and an emitting plane:
    // next-event estimation chooses among the spheres (point lights are all sampled, planes
    // by default not) with probabilities 1/4 and 3/4.
    Scene scene = empty_scene();
    spt::Sphere a{{-2, 0, 0}, 0.5f, 0}, b{{2, 0, 0}, 0.5f, 0};
    a.light = scene.add_emitter(ShapeKind::sphere, constant(1.0));
    b.light = scene.add_emitter(ShapeKind::sphere, constant(3.0));
    scene.spheres = {a, b};
    scene.add_point_light({0, 3, 0}, constant(5.0));
    spt::Plane p{{0, -1, 0}, -10.f, 0};
    p.light = scene.add_emitter(ShapeKind::plane, constant(1.0));
    scene.planes.push_back(p);
    scene.finalize();
    EXPECT_EQ(scene.point_light_indices, std::vector<int>{2});
    EXPECT_NEAR(scene.area_light_choice.probability(a.light), 0.25, 1e-6);
    EXPECT_NEAR(scene.area_light_choice.probability(b.light), 0.75, 1e-6);
    EXPECT_EQ(scene.area_light_choice.probability(p.light), 0.f);
    EXPECT_GT(scene.area_light_choice_with_planes.probability(p.light), 0.f);
    float prob = 0.f;
    EXPECT_EQ(scene.area_light_choice.sample(0.2f, prob), a.light);
    EXPECT_EQ(scene.area_light_choice.sample(0.3f, prob), b.light);
    EXPECT_NEAR(prob, 0.75, 1e-6);
}

TEST(LightList, RemovingTheEnvironmentKeepsEveryShapesEmitter) {
    // The environment added first, then emitters of each kind; removing the environment moves
    // the later lights down one place, and every shape's light index must follow.
    Scene scene = empty_scene();
    scene.set_background(constant(1.0));
    spt::Sphere s{{0, 0, 0}, 0.5f, 0};
    s.light = scene.add_emitter(ShapeKind::sphere, constant(2.0));
    spt::Disk d{{3, 0, 0}, {0, 1, 0}, 0.5f, 0};
    d.light = scene.add_emitter(ShapeKind::disk, constant(3.0));
    spt::Cylinder c{{-3, 0, 0}, {0, 1, 0}, 0.5f, 1.f, 0};
    c.light = scene.add_emitter(ShapeKind::cylinder, constant(4.0));
    scene.spheres.push_back(s);
    scene.disks.push_back(d);
    scene.cylinders.push_back(c);
    scene.set_background(constant(0.0));
    ASSERT_NO_THROW(scene.finalize());
    EXPECT_TRUE(scene.infinite_light_indices.empty());
    ASSERT_EQ(scene.lights.size(), 3u);
    EXPECT_TRUE(std::holds_alternative<spt::SphereLight>(scene.lights[scene.spheres[0].light]));
    EXPECT_TRUE(std::holds_alternative<spt::QuadricLight>(scene.lights[scene.disks[0].light]));
    EXPECT_TRUE(std::holds_alternative<spt::QuadricLight>(scene.lights[scene.cylinders[0].light]));
    EXPECT_NE(scene.disks[0].light, scene.cylinders[0].light);
}

TEST(LightList, EmitterNotAttachedToAShapeIsRejected) {
    Scene scene = empty_scene();
    scene.add_emitter(ShapeKind::sphere, constant(1.0));
    scene.spheres.push_back({{0, 0, 0}, 1.f, 0});  // light −1: the emitter belongs to nothing
    EXPECT_THROW(scene.finalize(), spt::SceneError);
}

}  // namespace

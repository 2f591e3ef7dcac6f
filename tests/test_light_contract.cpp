// The contract of model/lights/light.h, checked for every type of the closed set, one row per
// type (each light alone in a scene built here, so a ray finds it through Scene::intersect as
// in the path tracer): sample_li's directions follow pdf_li (chi-square over the sphere of
// directions), the density a sample carries is pdf_li's for its direction, delta lights
// return pdf 1 with `delta` set, power() equals the numerical integral of the emitted
// radiance or intensity, sample_le's directions follow pdf_le_dir (chi-square) and its
// point density is pdf_le_pos; and a planted bug (a density off by a factor) is rejected.
// The lights a scene may make one-sided have a second row each as one-sided (only the front
// emits: sample_li, pdf_li, sample_le, pdf_le_dir and power() must all agree on it), and
// one-sided lights seen from behind send nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "chi2.h"
#include "cone_histogram.h"
#include "model/lights/light.h"
#include "scene/scene.h"
#include "test_scenes.h"

namespace {

using namespace spt;
constexpr double kPiD = std::numbers::pi;
constexpr double kAlpha = 1e-5;  ///< per chi-square test (about 20 in this file)

Spectrum constant(double v) { return test::constant_spectrum(v); }
SampledWavelengths wavelengths() { return SampledWavelengths::sample(0.37f); }

Scene empty_scene() {
    Scene scene;
    scene.add_material(test::black_material());
    return scene;
}

struct Row {
    std::string name;
    std::function<Scene()> make;
    Vec3 ref;               ///< the reference point lights are sampled from
    double power_integral;  ///< ∫ emitted over area (or solid angle) and directions, / mean Le; <0: not tested
    Vec3 towards{0, 1, 0};  ///< axis of the cone of directions the chi-square bins (from ref)
    double cos_max = -1;    ///< the cone's extent (−1: the whole sphere)
    /// Whether the direction chi-square runs here. Polygons (quad, triangles) have straight
    /// edges across the cells that the midpoint rule of the expected counts resolves badly:
    /// test_lights.cpp bins them in their own parametrization instead.
    bool chi2 = true;
    /// The light is flat (one normal): sample_le's directions are binned against pdf_le_dir.
    bool flat = false;
    /// Whether sample_le's directions are binned here (a portal's density, piecewise constant
    /// in its rectified (u, v), grows without bound at grazing directions, beyond what the
    /// cells' midpoint rule resolves: test_portal_light.cpp bins them in (u, v)).
    bool le_chi2 = true;
};

/// An equal-area map of 16 × 16 coloured texels of moderate contrast (the cone histogram's
/// cells cut across texels: its midpoint rule resolves small steps well, and the lat-long
/// density's 1/sin θ at the poles badly: test_environment_map.cpp bins lat-long maps by
/// texel), turned by 30° about an oblique axis.
EnvironmentMapLight smooth_environment_map() {
    const int w = 16, h = 16;
    std::vector<float> rgb;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float a = 1.f + 0.4f * float(std::sin(2 * kPiD * x / w)), b = 1.f + 0.3f * float(y) / h;
            rgb.insert(rgb.end(), {a * b, a, 1.2f * b});
        }
    EnvironmentMapLight l;
    l.map = make_environment_map(w, h, 3, rgb, EnvironmentMapping::equal_area);
    const Vec3 axis = normalize(Vec3{1, 2, 0.5f});
    const float c = std::cos(0.5236f), sn = std::sin(0.5236f), k = 1 - c;
    l.world_from_map[0] = {c + axis.x * axis.x * k, axis.x * axis.y * k - axis.z * sn, axis.x * axis.z * k + axis.y * sn};
    l.world_from_map[1] = {axis.y * axis.x * k + axis.z * sn, c + axis.y * axis.y * k, axis.y * axis.z * k - axis.x * sn};
    l.world_from_map[2] = {axis.z * axis.x * k - axis.y * sn, axis.z * axis.y * k + axis.x * sn, c + axis.z * axis.z * k};
    l.scale = 1.5f;
    return l;
}

/// πR² ∫ (mean over 380–780 nm of the arriving radiance) dω by the midpoint rule over a grid
/// uniform in solid angle: an infinite light's power; or, `first_wavelength`, of the radiance
/// at the first of wavelengths() (what emitted_by_sample_le integrates).
double infinite_power_by_directions(const Light& light, float radius, bool first_wavelength) {
    const int nc = 600, np = 1200;
    double sum = 0;
    for (int i = 0; i < nc; ++i) {
        const double c = -1 + 2 * (i + 0.5) / nc, st = std::sqrt(1 - c * c);
        for (int j = 0; j < np; ++j) {
            const double phi = 2 * kPiD * (j + 0.5) / np;
            const Vec3 d{float(st * std::cos(phi)), float(c), float(st * std::sin(phi))};
            if (first_wavelength) {
                sum += 41 * light_arriving(light, d, wavelengths())[0];
                continue;
            }
            for (int k = 0; k < 41; k += 4) {
                SampledWavelengths lambda = wavelengths();
                for (int q = 0; q < 4; ++q) lambda.lambda[q] = 380.f + 10.f * float(std::min(k + q, 40));
                const SampledSpectrum L = light_arriving(light, d, lambda);
                for (int q = 0; q < 4 && k + q <= 40; ++q) sum += L[q];
            }
        }
    }
    return kPiD * radius * radius * sum / 41 * (4 * kPiD / (double(nc) * np));
}

/// The row's scene with its light made one-sided (and the row renamed).
Row one_sided(Row row, const Vec3& ref, double power_integral) {
    row.name += " one-sided";
    row.make = [make = row.make] {
        Scene s = make();
        EXPECT_TRUE(light_can_be_one_sided(s.lights[0]));
        light_make_one_sided(s.lights[0]);
        s.finalize();
        return s;
    };
    row.ref = ref;
    row.power_integral = power_integral;
    return row;
}

std::vector<Row> rows() {
    const double le = 1.5;
    std::vector<Row> r;
    r.push_back({"point", [] {
                     Scene s = empty_scene();
                     s.add_point_light({0.2f, 2.f, -0.1f}, constant(1.5));
                     s.finalize();
                     return s;
                 },
                 {0, 0, 0}, 4 * kPiD * le});
    r.push_back({"spot", [] {
                     Scene s = empty_scene();
                     SpotLight spot;
                     spot.position = {0.f, 2.f, 0.f};
                     spot.direction = normalize(Vec3{0.2f, -1.f, 0.f});
                     spot.intensity = constant(1.5);
                     spot.cos_cone = std::cos(40.f * float(kPiD) / 180.f);
                     spot.cos_falloff = std::cos(20.f * float(kPiD) / 180.f);
                     s.lights.emplace_back(spot);
                     s.finalize();
                     return s;
                 },
                 {0.1f, 0, 0}, -2});  // -2: integrated numerically below
    r.push_back({"sphere", [] {
                     Scene s = empty_scene();
                     Sphere sp{{0.3f, 2.f, -0.4f}, 0.5f};
                     sp.material = 0;
                     sp.light = s.add_emitter(ShapeKind::sphere, constant(1.5));
                     s.spheres.push_back(sp);
                     s.finalize();
                     return s;
                 },
                 {0, 0, 0}, 2 * kPiD * 4 * kPiD * 0.25 * le, normalize(Vec3{0.3f, 2.f, -0.4f}), 0.95});
    r.push_back({"quad", [] {
                     Scene s = empty_scene();
                     const Vec3 o(-0.25f, 1.f, -0.25f), e1(0.5f, 0, 0), e2(0, 0, 0.5f);
                     const int light = s.add_quad_emitter(o, e1, e2, constant(1.5));
                     Triangle a{o, o + e1, o + e1 + e2, 0}, b{o, o + e1 + e2, o + e2, 0};
                     a.light = b.light = light;
                     s.triangles = {a, b};
                     s.finalize();
                     return s;
                 },
                 {0.1f, 0.7f, 0.05f}, 2 * kPiD * 0.25 * le, normalize(Vec3{-0.1f, 0.3f, -0.05f}), 0.3, false, true});
    // The quad faces down (e1 × e2 = −y): the reference point below it is in front.
    r.push_back(one_sided(r.back(), r.back().ref, kPiD * 0.25 * le));
    r.push_back({"triangles", [] {
                     Scene s = empty_scene();
                     const int light = s.add_emitter(ShapeKind::triangle, constant(1.5));
                     Triangle a{{-0.5f, 1.f, -0.2f}, {0.4f, 1.2f, -0.3f}, {0.f, 1.1f, 0.6f}, 0};
                     a.light = light;
                     s.triangles = {a};
                     s.finalize();
                     return s;
                 },
                 {0, 0, 0}, -1, normalize(Vec3{-0.033f, 1.1f, 0.033f}), 0.8, false, true});  // power: area computed below
    // One-sided, with a second triangle beside it that shows the reference point its back
    // (normal up): that one's points are no samples, and pdf_li is 0 where a ray finds it.
    r.push_back(one_sided({"triangles", [] {
                               Scene s = empty_scene();
                               const int light = s.add_emitter(ShapeKind::triangle, constant(1.5));
                               Triangle a{{-0.5f, 1.f, -0.2f}, {0.4f, 1.2f, -0.3f}, {0.f, 1.1f, 0.6f}, 0};
                               Triangle b{{0.6f, 1.f, 0.f}, {1.2f, 1.1f, 0.5f}, {1.f, 1.2f, -0.4f}, 0};
                               a.light = b.light = light;
                               s.triangles = {a, b};
                               s.finalize();
                               return s;
                           },
                           {0, 0, 0}, -1, {0, 1, 0}, 0.5, false},
                          {0, 0, 0}, -1));
    r.push_back({"disk", [] {
                     Scene s = empty_scene();
                     Disk d{{0.f, 1.5f, 0.2f}, normalize(Vec3{0.2f, -1.f, 0.1f}), 0.6f};
                     d.material = 0;
                     d.light = s.add_emitter(ShapeKind::disk, constant(1.5));
                     s.disks.push_back(d);
                     s.finalize();
                     return s;
                 },
                 {0, 0, 0}, 2 * kPiD * kPiD * 0.36 * le, normalize(Vec3{0.f, 1.5f, 0.2f}), 0.85, true, true});
    r.push_back(one_sided(r.back(), r.back().ref, kPiD * kPiD * 0.36 * le));  // its normal points down
    // A one-sided cylinder seen from outside: the sampled points on its far half show the
    // reference point their back and are no samples, so the directions that remain are the
    // ones a ray finds first (a two-sided one sends two points along each: no row of its own).
    // No chi-square: its density diverges at the silhouette, which the expected counts'
    // midpoint rule cannot integrate.
    r.push_back(one_sided({"cylinder", [] {
                               Scene s = empty_scene();
                               Cylinder c{{-0.4f, 1.5f, 0.f}, {1.f, 0.f, 0.f}, 0.3f, 0.8f};
                               c.material = 0;
                               c.light = s.add_emitter(ShapeKind::cylinder, constant(1.5));
                               s.cylinders.push_back(c);
                               s.finalize();
                               return s;
                           },
                           {0, 0, 0}, -3, {0, 1, 0}, 0.85, false},
                          {0, 0, 0}, kPiD * 2 * kPiD * 0.3 * 0.8 * le));
    r.push_back({"plane", [] {
                     Scene s = empty_scene();
                     Plane p{{0, 1, 0}, 2.f};
                     p.material = 0;
                     p.light = s.add_emitter(ShapeKind::plane, constant(1.5));
                     s.planes.push_back(p);
                     s.finalize();
                     return s;
                 },
                 {0, 0, 0}, -3});  // no finite power: not tested
    r.push_back({"environment", [] {
                     Scene s = empty_scene();
                     s.set_background(constant(1.5));
                     s.finalize();
                     return s;
                 },
                 {0, 0, 0}, -4});  // -4: an infinite light, integrated numerically below
    r.push_back({"environment map", [] {
                     Scene s = empty_scene();
                     s.set_background(smooth_environment_map());
                     s.finalize();
                     return s;
                 },
                 {0, 0, 0}, -4});
    // A 1 × 1 portal above the reference point, its front (x × −z = +y) facing the map: the
    // portal's straight edges cut the chi-square's cells (as a quad's do), so its directions
    // are binned in its own (u, v) in test_portal_light.cpp.
    r.push_back({"portal", [] {
                     Scene s = empty_scene();
                     s.set_background(make_portal_light(smooth_environment_map(), {-0.5f, 1.f, 0.5f}, {1, 0, 0}, {0, 0, -1}));
                     s.finalize();
                     return s;
                 },
                 {0, 0, 0}, -5, {0, 1, 0}, -1, false, false, false});  // -5: the flux through the portal, integrated below
    r.push_back({"sky", [] {
                     Scene s = empty_scene();
                     SkyLight sky;
                     sky.model = make_sky_model(1.0, 1.0, 4.0, 0.3);
                     sky.scale = 1.5f;
                     s.set_background(sky, std::nullopt);
                     s.finalize();
                     return s;
                 },
                 // The cone above 11.5°: the sky brightens steeply within a few degrees of the
                 // horizon, which the expected counts' midpoint rule underestimates (0.06 %
                 // of the whole at 10 × 10 points a cell); the band below goes to the outside cell.
                 {0, 0, 0}, -4, {0, 1, 0}, 0.2});
    // A sun of 20° radius (the real one, 0.27°, is finer than the power integral's grid;
    // test_sky.cpp samples that one), its cone the chi-square's.
    r.push_back({"sun", [] {
                     Scene s = empty_scene();
                     SunLight sun;
                     sun.model = make_sun_model(0.9, 2.0, 3.0, 0.35);
                     sun.scale = 1e-4f;
                     s.lights.emplace_back(sun);
                     s.finalize();
                     return s;
                 },
                 {0, 0, 0}, -4, sun_direction_of(0.9, 2.0), std::cos(0.35)});
    return r;
}

/// A ∫ over the portal's front of (the mean over 380–780 nm, or `first_wavelength` the value
/// at the first of wavelengths(), of) the arriving radiance times cos θ: the flux through a
/// portal, by the midpoint rule over a grid uniform in solid angle.
double portal_flux_by_directions(const PortalLight& light, bool first_wavelength) {
    const Portal& p = light.portal();
    const int nc = 400, np = 1200;
    double sum = 0;
    for (int i = 0; i < nc; ++i) {
        const double c = (i + 0.5) / nc, st = std::sqrt(1 - c * c);
        for (int j = 0; j < np; ++j) {
            const double phi = 2 * kPiD * (j + 0.5) / np;
            const Vec3 d = normalize(p.x * float(st * std::cos(phi)) + p.y * float(st * std::sin(phi)) + p.z * float(c));
            SampledWavelengths lambda = wavelengths();
            if (first_wavelength) {
                sum += c * light.arriving(d, lambda)[0];
                continue;
            }
            double mean = 0;
            for (int k = 0; k <= 40; k += 4) {
                for (int q = 0; q < 4; ++q) lambda.lambda[q] = 380.f + 10.f * float(std::min(k + q, 40));
                const SampledSpectrum L = light.arriving(d, lambda);
                for (int q = 0; q < 4 && k + q <= 40; ++q) mean += L[q] / 41;
            }
            sum += c * mean;
        }
    }
    return double(p.width) * p.height * sum * (2 * kPiD / (double(nc) * np));
}

LightSampleContext context(const Vec3& p, const Vec3& n, bool both) { return {p, {0, 0, 0}, n, n, both}; }

/// pdf_li of light 0 for the ray from ctx.p along d, found through the scene (0 on a miss).
double pdf_along(const Scene& scene, const LightSampleContext& ctx, const Vec3& d) {
    const std::optional<Hit> hit = scene.intersect({ctx.p, d, kInfinity});
    if (hit && hit->light != 0) return 0.0;
    if (!hit && light_type(scene.lights[0]) != LightType::infinite) return 0.0;
    return light_pdf_li(scene.lights[0], ctx, d, hit ? &*hit : nullptr);
}

/// Chi-square of sample_li's directions against `pdf` over the row's cone (12 × 12 cells
/// equal in solid angle, plus the outside).
spt_test::Chi2Result li_chi2(const Scene& scene, const Row& row, const LightSampleContext& ctx,
                             const std::function<double(const Vec3&)>& pdf, int n, std::uint64_t seed) {
    spt_test::ConeHistogram h(row.towards, row.cos_max, 12, 12);
    const std::vector<double> expected = h.expected(pdf, n, 10);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (int i = 0; i < n; ++i) {
        LightSample ls;
        if (light_sample_li(scene.lights[0], ctx, wavelengths(), u(rng), u(rng), ls)) h.add(ls.wi);
        else h.add_outside();
    }
    return spt_test::chi2_test(h.observed(), expected);
}

TEST(LightContract, EveryTypeHasARow) {
    // One row per alternative of Light: a new light type must add its row here.
    std::vector<bool> seen(std::variant_size_v<Light>, false);
    for (const Row& row : rows()) seen[row.make().lights.at(0).index()] = true;
    for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_TRUE(seen[i]) << "no row for Light alternative " << i;
}

TEST(LightContract, SampledDirectionsFollowPdfLi) {
    for (const Row& row : rows()) {
        const Scene scene = row.make();
        const Light& light = scene.lights[0];
        for (bool both : {false, true}) {
            const LightSampleContext ctx = context(row.ref, {0, 1, 0}, both);
            if (is_delta_light(light)) {
                // The delta sample: pdf 1, delta set, L = I(−wi)/r², direction towards the light.
                LightSample ls;
                ASSERT_TRUE(light_sample_li(light, ctx, wavelengths(), 0.3f, 0.6f, ls)) << row.name;
                EXPECT_EQ(ls.pdf, 1.f) << row.name;
                EXPECT_TRUE(ls.delta) << row.name;
                const Vec3 d = light_position_at(light, 0.f) - ctx.p;
                EXPECT_NEAR(dot(ls.wi, normalize(d)), 1.0, 1e-6) << row.name;
                const SampledSpectrum I = light_I_max(light, wavelengths()) * light_falloff(light, -ls.wi);
                EXPECT_NEAR(ls.L[0], I[0] / length_squared(d), 1e-5 * I[0]) << row.name;
                EXPECT_EQ(light_pdf_li(light, ctx, ls.wi, nullptr), 0.f) << row.name;
                continue;
            }
            if (row.chi2) {
                const spt_test::Chi2Result r =
                    li_chi2(scene, row, ctx, [&](const Vec3& d) { return pdf_along(scene, ctx, d); }, 100000, 7);
                EXPECT_GT(r.p_value, kAlpha) << row.name << (both ? " (both sides)" : "") << ": X² = " << r.statistic;
                EXPECT_EQ(r.observed_in_empty, 0) << row.name;
            }
            // The density a sample carries is pdf_li's for its direction. Not at grazing points
            // of curved lights (the cylinder's silhouette), where the ray towards the sample
            // finds a point that rounding moves far along the surface, with another cosine.
            std::mt19937_64 rng(11);
            std::uniform_real_distribution<float> u(0.f, 1.f);
            for (int i = 0; i < 2000; ++i) {
                LightSample ls;
                if (!light_sample_li(light, ctx, wavelengths(), u(rng), u(rng), ls)) continue;
                if (ls.n != Vec3() && std::fabs(dot(ls.n, ls.wi)) < 0.02f) continue;
                const double ref = pdf_along(scene, ctx, ls.wi);
                ASSERT_NEAR(ls.pdf, ref, 2e-3 * ref) << row.name;
            }
        }
    }
}

TEST(LightContract, OneSidedLightsSendNothingBehind) {
    // From points behind a one-sided light (its sampled points pushed back along −n; for the
    // cylinder, its axis, where every point shows its inside) no sample arrives, pdf_li of the
    // ray that reaches it is 0, L towards there is 0 and sample_le never leaves that way; from
    // in front (pushed along n) L is the two-sided light's Le.
    int rows_seen = 0;
    for (const Row& row : rows()) {
        if (!row.name.ends_with(" one-sided")) continue;
        ++rows_seen;
        const Scene scene = row.make();
        const Light& light = scene.lights[0];
        std::mt19937_64 rng(29);
        std::uniform_real_distribution<float> u(0.f, 1.f);
        int behind_checked = 0;
        for (int i = 0; i < 200; ++i) {
            const auto o = light_sample_le(light, wavelengths(), u(rng), u(rng), u(rng), u(rng), u(rng), 0.f);
            ASSERT_TRUE(o.has_value()) << row.name;
            ASSERT_GT(dot(o->n, o->w), 0.f) << row.name << ": sample_le leaves by the back";
            EXPECT_EQ(light_pdf_le_dir(light, o->n, -o->w), 0.f) << row.name;
            const Vec3 front = o->p + o->n * 0.05f;
            const Vec3 behind = row.name == "cylinder one-sided" ? Vec3(o->p.x, 1.5f, 0.f) : o->p - o->n * 0.05f;
            // L leaving the point towards each side.
            const SampledSpectrum L_front = light_emitted(light, o->p, o->n, normalize(front - o->p), wavelengths());
            EXPECT_FLOAT_EQ(L_front[0], 1.5f) << row.name;
            EXPECT_EQ(light_emitted(light, o->p, o->n, normalize(behind - o->p), wavelengths())[0], 0.f) << row.name;
            // Light samples and densities from behind.
            const LightSampleContext ctx = context(behind, normalize(o->p - behind), false);
            // Behind one triangle of the two is not behind the other: only for the light whole.
            for (int k = 0; k < 20 && !row.name.starts_with("triangles"); ++k) {
                LightSample ls;
                EXPECT_FALSE(light_sample_li(light, ctx, wavelengths(), u(rng), u(rng), ls)) << row.name;
            }
            const Vec3 d = normalize(o->p - behind);
            const std::optional<Hit> hit = scene.intersect({behind, d, kInfinity});
            if (!hit) continue;  // the ray slipped past an edge
            ASSERT_EQ(hit->light, 0) << row.name;
            EXPECT_EQ(light_pdf_li(light, ctx, d, &*hit), 0.f) << row.name;
            EXPECT_EQ(scene.emitted(*hit, -d, wavelengths())[0], 0.f) << row.name;
            ++behind_checked;
        }
        EXPECT_GT(behind_checked, 150) << row.name;
    }
    EXPECT_EQ(rows_seen, 4);
}

TEST(LightContractNegativeControl, ChiSquareRejectsADensityOffByTenPercent) {
    // The planted bug: the sphere's density scaled by 1.1 (renormalised in the outside cell).
    for (const Row& row : rows()) {
        if (row.name != "sphere") continue;
        const Scene scene = row.make();
        const LightSampleContext ctx = context(row.ref, {0, 1, 0}, false);
        const spt_test::Chi2Result r =
            li_chi2(scene, row, ctx, [&](const Vec3& d) { return 1.1 * pdf_along(scene, ctx, d); }, 100000, 7);
        EXPECT_LT(r.p_value, kAlpha);
    }
}

/// ∫ over the light's points and directions of the emitted radiance (intensity for delta
/// lights), by Monte Carlo from sample_le: E[Le·|cos|/(pdf_pos·pdf_dir)].
double emitted_by_sample_le(const Light& light, int n) {
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        const auto o = light_sample_le(light, wavelengths(), u(rng), u(rng), u(rng), u(rng), u(rng), 0.f);
        if (!o) continue;
        // An infinite light's disk faces its direction.
        const double cos_o = o->delta_position || o->infinite ? 1.0 : std::fabs(dot(o->n, o->w));
        sum += o->Le[0] * cos_o / (o->pdf_pos * o->pdf_dir);
    }
    return sum / n;
}

TEST(LightContract, PowerIsTheIntegralOfWhatIsEmitted) {
    // power() = ∫∫ L cos dA dω (area), ∫ I dω (delta), up to the mean over 380–780 nm: with a
    // constant spectrum Le the power is the geometric integral times Le.
    for (const Row& row : rows()) {
        if (row.power_integral == -3) continue;
        const Scene scene = row.make();
        const Light& light = scene.lights[0];
        double expected = row.power_integral;
        if (row.name.starts_with("triangles")) {
            const double sides = row.name == "triangles" ? 2 : 1;
            expected = 0;
            for (const Triangle& t : scene.triangles)
                expected += sides * kPiD * 0.5 * length(cross(t.p1 - t.p0, t.p2 - t.p0)) * 1.5;
        }
        // Infinite lights: power() by the mean over wavelengths, sample_le's by the first.
        double expected_le = expected;
        if (row.power_integral == -4) {
            expected = infinite_power_by_directions(light, float(scene.bounds_radius), false);
            expected_le = infinite_power_by_directions(light, float(scene.bounds_radius), true);
        }
        // A portal's power() is the flux by a coarser midpoint rule (256² cells of its (u, v)):
        // within 0.5 %; its sample_le must give the flux itself.
        double power_tolerance = 1e-3;
        if (row.power_integral == -5) {
            expected = portal_flux_by_directions(std::get<PortalLight>(light), false);
            expected_le = portal_flux_by_directions(std::get<PortalLight>(light), true);
            power_tolerance = 5e-3;
        }
        if (row.name == "spot") {
            // ∫ falloff over the sphere by a fine midpoint rule in cos θ about the axis.
            const SpotLight& s = std::get<SpotLight>(light);
            double sum = 0;
            const int m = 200000;
            for (int i = 0; i < m; ++i) {
                const double c = -1 + 2 * (i + 0.5) / m;
                const Vec3 w = Frame(s.direction).to_world({float(std::sqrt(1 - c * c)), 0.f, float(c)});
                sum += s.falloff(w);
            }
            expected = 2 * kPiD * sum * 2 / m * 1.5;
        }
        EXPECT_NEAR(light_power(light), expected, power_tolerance * expected) << row.name;
        // The same integral through sample_le (its densities must be the ones it samples by).
        const double mc = emitted_by_sample_le(light, 200000);
        if (row.power_integral > -4) expected_le = expected;
        EXPECT_NEAR(mc, expected_le, 0.02 * expected_le) << row.name << " (sample_le)";
    }
}

TEST(LightContract, PowerIsTheMeanOfTheSpectralPowerOverTheVisible) {
    for (const Row& row : rows()) {
        const Scene scene = row.make();
        const Light& light = scene.lights[0];
        double sum = 0;
        for (int i = 0; i <= 40; ++i) {
            const float p = light_spectral_power(light, 380.f + 10.f * i);
            EXPECT_TRUE(std::isfinite(p) && p >= 0.f) << row.name;
            sum += p;
        }
        EXPECT_NEAR(sum / 41, light_power(light), 1e-5 * light_power(light)) << row.name;
        // Defined beyond the observer's range too (fluorescence excites from 300 nm).
        EXPECT_TRUE(std::isfinite(light_spectral_power(light, 300.f))) << row.name;
    }
}

/// A light's spectral power follows its spectrum: a point light of a Gaussian intensity.
TEST(LightContract, SpectralPowerFollowsTheSpectrum) {
    const Scene scene = load_scene_text(
        R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]}, "materials": {"m": {"kd": 0.5}},
            "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}],
            "lights": [{"type": "point", "position": [0, 2, 0],
                        "intensity": {"type": "gaussian", "center_nm": 365, "width_nm": 10}}]})",
        "test.json", "test", SpectralResolution{SpectralResolution::kExact}, {});
    const Light& light = scene.lights[0];
    EXPECT_NEAR(light_spectral_power(light, 365.f), 4 * kPiD, 1e-5);
    EXPECT_LT(light_spectral_power(light, 420.f), 1e-6 * light_spectral_power(light, 365.f));
}

TEST(LightContract, SampleLeAgreesWithPdfLe) {
    // Each origin's direction density is pdf_le_dir of its direction, and its point density
    // pdf_le_pos (area lights) or 1 (delta); the plane starts no subpath.
    for (const Row& row : rows()) {
        const Scene scene = row.make();
        const Light& light = scene.lights[0];
        if (row.name == "plane") {
            EXPECT_FALSE(light_can_start_subpath(light));
            EXPECT_FALSE(light_sample_le(light, wavelengths(), 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.f).has_value());
            continue;
        }
        ASSERT_TRUE(light_can_start_subpath(light)) << row.name;
        std::mt19937_64 rng(23);
        std::uniform_real_distribution<float> u(0.f, 1.f);
        spt_test::ConeHistogram h(Vec3(0, 1, 0), -1.0, 8, 8);
        const int n = 50000;
        Vec3 n_fixed;
        const bool fixed_normal = light_type(light) != LightType::area || row.flat;
        for (int i = 0; i < n; ++i) {
            const auto o = light_sample_le(light, wavelengths(), u(rng), u(rng), u(rng), u(rng), u(rng), 0.f);
            ASSERT_TRUE(o.has_value()) << row.name;
            ASSERT_NEAR(o->pdf_dir, light_pdf_le_dir(light, o->n, o->w), 1e-4 * o->pdf_dir + 1e-7) << row.name;
            if (light_type(light) == LightType::area) {
                ASSERT_NEAR(o->pdf_pos, light_pdf_le_pos(light), 1e-6 * o->pdf_pos) << row.name;
            }
            if (o->delta_position) {
                ASSERT_EQ(o->pdf_pos, 1.f) << row.name;
            }
            n_fixed = o->n;
            h.add(o->w);
        }
        if (!fixed_normal || !row.le_chi2) continue;  // a sphere's direction density depends on the point
        const std::vector<double> expected =
            h.expected([&](const Vec3& w) { return light_pdf_le_dir(light, n_fixed, w); }, n, 16);
        const spt_test::Chi2Result r = spt_test::chi2_test(h.observed(), expected);
        EXPECT_GT(r.p_value, kAlpha) << row.name << ": X² = " << r.statistic;
    }
}

}  // namespace

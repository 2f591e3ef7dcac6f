// Specular next-event estimation through smooth glass spheres and off reflecting ones
// (geometry/sphere_caustics.h, render/caustic_nee.h, render/reflection_nee.h): the 1-D chain
// solver finds every root and each root is a real chain (traced with Snell's law, or the
// mirror law, in 3-D), its Jacobian matches a finite difference, and the rendered caustic
// agrees with BSDF sampling alone within the measured noise (with planted bugs caught by the
// same tests).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "geometry/sphere_caustics.h"
#include "render/caustic_nee.h"
#include "render/reflection_nee.h"
#include "render/integrator.h"
#include "scene/scene.h"
#include "scene/scene_loader.h"
#include "test_scenes.h"

namespace spt {
namespace {

DVec3 random_outside(std::mt19937_64& gen, const DVec3& c, double r_min, double r_max) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (;;) {
        const DVec3 d(u(gen), u(gen), u(gen));
        const double l = length(d);
        if (l < 1e-3 || l > 1.0) continue;
        std::uniform_real_distribution<double> rr(r_min, r_max);
        return c + d * (rr(gen) / l);
    }
}

/// Distance of y from the ray o + t·w, t > 0 (infinite when y is behind).
double distance_from_ray(const DVec3& o, const DVec3& w, const DVec3& y) {
    const double t = dot(y - o, w);
    if (t <= 0.0) return INFINITY;
    return length(y - (o + w * t));
}

/// Forward roots of the chain by a dense scan of θ (sign changes of h refined by bisection).
std::vector<double> dense_roots(const SphereChain& chain, int cells) {
    std::vector<double> roots;
    auto h_at = [&](double t) { return chain.eval(std::sin(t), std::cos(t)); };
    double ta = -0.5 * kPiDouble;
    SphereChain::Eval ea = h_at(ta);
    for (int k = 1; k <= cells; ++k) {
        const double tb = -0.5 * kPiDouble + k * kPiDouble / cells;
        const SphereChain::Eval eb = h_at(tb);
        if ((ea.h < 0.0) != (eb.h < 0.0)) {
            double lo = ta, hi = tb, hlo = ea.h;
            for (int i = 0; i < 80; ++i) {
                const double mid = 0.5 * (lo + hi);
                const double hm = h_at(mid).h;
                if ((hm < 0.0) == (hlo < 0.0)) lo = mid, hlo = hm;
                else hi = mid;
            }
            const SphereChain::Eval e = h_at(0.5 * (lo + hi));
            if (e.along > 0.0 && std::fabs(e.h) < 1e-6) roots.push_back(0.5 * (lo + hi));
        }
        ta = tb, ea = eb;
    }
    return roots;
}

/// Roots of `dense` that the solver's `roots` lack. Each must lie within one solver cell of
/// another dense root (a fold: two roots merging, which the caller's MIS covers); an isolated
/// miss fails the test.
int count_missed_roots(const SphereChainRoot* roots, int n, const std::vector<double>& dense, int trial) {
    const double cell = kPiDouble / SphereChain::kCells;
    int missed = 0;
    for (std::size_t k = 0; k < dense.size(); ++k) {
        bool found = false;
        for (int i = 0; i < n; ++i) found |= std::fabs(roots[i].theta - dense[k]) < 1e-7;
        if (found) continue;
        bool near_other = false;
        for (std::size_t j = 0; j < dense.size(); ++j) near_other |= j != k && std::fabs(dense[j] - dense[k]) < cell;
        EXPECT_TRUE(near_other) << "trial " << trial << " missed an isolated root at θ = " << dense[k];
        ++missed;
    }
    return missed;
}


TEST(SphereCaustics, EveryRootIsAChainAndNoneIsMissedAwayFromFolds) {
    std::mt19937_64 gen(7);
    const DVec3 c(0.3, -0.2, 0.1);
    const double R = 0.4;
    int configurations = 0, roots_total = 0, missed_near_fold = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const double eta = std::uniform_real_distribution<double>(1.05, 2.4)(gen);
        const DVec3 x = random_outside(gen, c, 1.02 * R, 4.0 * R);
        const DVec3 y = random_outside(gen, c, 1.02 * R, 6.0 * R);
        const SphereChainNodes nodes(eta);
        const SphereChain chain(x, c, R, nodes, y);
        ASSERT_TRUE(chain.valid());
        SphereChainRoot roots[SphereChain::kMaxRoots];
        const int n = chain.solve(roots);
        ++configurations;
        roots_total += n;
        for (int i = 0; i < n; ++i) {
            DVec3 exit, w_exit;
            ASSERT_TRUE(trace_through_sphere(x, roots[i].wx, c, R, eta, exit, w_exit)) << trial;
            EXPECT_LT(distance_from_ray(exit, w_exit, y), 1e-6) << trial << " root " << i;
            EXPECT_LT(length(exit - roots[i].exit), 1e-9) << trial;
            EXPECT_LT(length(w_exit - roots[i].w_exit), 1e-9) << trial;
            EXPECT_NEAR(length(roots[i].entry - c), R, 1e-12);
            EXPECT_NEAR(length(roots[i].exit - c), R, 1e-12);
        }
        // Every root of the dense scan is found, except pairs closer than the solver's cell
        // (a fold: two roots merging), which the caller's MIS covers.
        const std::vector<double> dense = dense_roots(chain, 20000);
        missed_near_fold += count_missed_roots(roots, n, dense, trial);
        EXPECT_LE(n, static_cast<int>(dense.size())) << trial;
    }
    EXPECT_GT(roots_total, configurations / 4);  // the test exercises roots at all
    // Misses (all at folds) stay rare.
    EXPECT_LT(missed_near_fold, roots_total / 50) << roots_total;
}

/// |dω_x/dA_y| against a finite difference: perturb the direction leaving x in two orthogonal
/// directions by ε, trace each through the sphere to the plane through y with normal n_y, and
/// compare ε² (the solid angle) with the parallelogram's area.
TEST(SphereCaustics, JacobianMatchesAFiniteDifference) {
    std::mt19937_64 gen(11);
    const DVec3 c(0.0, 0.0, 0.0);
    const double R = 0.5;
    int checked = 0;
    for (int trial = 0; trial < 2000 && checked < 300; ++trial) {
        const double eta = std::uniform_real_distribution<double>(1.2, 1.9)(gen);
        const DVec3 x = random_outside(gen, c, 1.1 * R, 4.0 * R);
        const DVec3 y = random_outside(gen, c, 1.2 * R, 5.0 * R);
        const DVec3 n_y = normalize(random_outside(gen, DVec3(), 0.5, 1.0));
        const SphereChainNodes nodes(eta);
        const SphereChain chain(x, c, R, nodes, y);
        SphereChainRoot roots[SphereChain::kMaxRoots];
        const int n = chain.solve(roots);
        for (int i = 0; i < n; ++i) {
            const SphereChainRoot& r = roots[i];
            const double cos_y = std::fabs(dot(n_y, r.w_exit));
            if (cos_y < 0.2 || r.cos_in < 0.1) continue;  // grazing: the difference is poor there
            // Far from folds only: the finite difference of a near-singular map is not accurate.
            DVec3 s, t;
            tangent_basis(r.wx, s, t);
            const double eps = 1e-6;
            auto hit_plane = [&](const DVec3& w, DVec3& p) {
                DVec3 e, we;
                if (!trace_through_sphere(x, w, c, R, eta, e, we)) return false;
                const double tt = dot(y - e, n_y) / dot(we, n_y);
                p = e + we * tt;
                return true;
            };
            DVec3 p0, p1, p2, m1, m2;
            if (!hit_plane(r.wx, p0) || !hit_plane(normalize(r.wx + s * eps), p1) ||
                !hit_plane(normalize(r.wx + t * eps), p2) || !hit_plane(normalize(r.wx - s * eps), m1) ||
                !hit_plane(normalize(r.wx - t * eps), m2))
                continue;
            // Central differences: the parallelogram of the two derivative vectors.
            const double area = length(cross(p1 - m1, p2 - m2)) * 0.25;
            const double fd = eps * eps / area;  // dω/dA
            const double analytic = r.dw_dAperp * cos_y;
            // Near a fold the map's second derivative makes the ε-difference inaccurate: the
            // tolerance is the difference's own truncation error, estimated from the
            // asymmetry of the one-sided steps (their mismatch is O(ε·|d²y/dω²|)).
            const double asym = (length((p1 - p0) + (m1 - p0)) + length((p2 - p0) + (m2 - p0))) /
                                (length(p1 - m1) + length(p2 - m2));
            if (asym > 1e-3) continue;
            EXPECT_NEAR(analytic / fd, 1.0, 1e-4 + 20.0 * asym) << trial << " eta " << eta;
            ++checked;
        }
    }
    EXPECT_GE(checked, 100);
}

/// A diffuse floor under a clear glass ball lit by a small emitting sphere (or a quad), seen
/// from low down so that the caustic under the ball fills much of the image.
Scene caustic_scene(bool quad) {
    const std::string light =
        // The quad tilted by 37° about x, so that cos θ_y varies over the caustic's rays.
        quad ? R"({"type": "quad", "origin": [-0.1, 1.14, -0.08], "edge1": [0.2, 0, 0], "edge2": [0, 0.12, 0.16],
                   "emission": 60})"
             : R"({"type": "sphere", "center": [0.05, 1.2, 0], "radius": 0.1, "emission": 30})";
    const std::string text = R"({"camera": {"position": [0, 0.16, 1.4], "look_at": [0, 0.0, 0], "vfov_degrees": 28},
      "materials": {"floor": {"type": "diffuse", "kd": 0.8}, "glass": {"kt": 1.0, "ior": 1.5}},
      "shapes": [{"type": "plane", "normal": [0, 1, 0], "point": [0, 0, 0], "material": "floor"},
        {"type": "sphere", "center": [0, 0.36, 0], "radius": 0.3, "material": "glass"}, )" + light + "]}";
    return load_scene_text(text, "caustic.json", "caustic", {}, {});
}

TEST(SphereCaustics, SceneFindsItsGlassSphereAndLight) {
    const Scene scene = caustic_scene(false);
    ASSERT_TRUE(scene.effects.caustic_spheres);
    ASSERT_EQ(scene.sphere_chains.caustic_spheres.size(), 1u);
    EXPECT_EQ(scene.sphere_chains.caustic_spheres[0].sphere, 0);
    EXPECT_FLOAT_EQ(scene.sphere_chains.caustic_spheres[0].eta, 1.5f);
    // Built-in scenes: cornell (plane light) and cornell-point (a point light) have none.
    for (const char* name : {"cornell", "cornell-point"}) {
        std::optional<Scene> s = load_builtin_scene(name, {});
        ASSERT_TRUE(s.has_value());
        EXPECT_FALSE(s->effects.caustic_spheres) << name;
    }
    std::optional<Scene> s = load_builtin_scene("cornell-sphere", {});
    ASSERT_TRUE(s.has_value());
    EXPECT_TRUE(s->effects.caustic_spheres);
}

/// The image with specular next-event estimation + MIS against the same scene with the
/// caustic left to BSDF sampling (--caustic-nee off): equal means within the measured
/// standard errors, for a sphere light and a quad light; each planted bug (the BSDF side's
/// weight dropped: the caustic counted up to twice; cos θ_y dropped from the Jacobian) is
/// caught by the same comparison.
TEST(SphereCaustics, SpecularNextEventEstimationIsUnbiasedAndPlantedBugsAreCaught) {
    for (const bool quad : {false, true}) {
        const Scene scene = caustic_scene(quad);
        RenderSettings on = test::small_settings(24, 16, 1024, 1);
        RenderSettings off = test::small_settings(24, 16, 4096, 2);
        off.integrator.caustic_nee = false;
        const auto film_on = test::render_film(scene, on);
        const auto film_off = test::render_film(scene, off);
        EXPECT_EQ(test::count_bad_pixels(*film_on), 0);
        EXPECT_EQ(film_on->rejected_samples(), 0u);
        const auto all = [](int, int) { return true; };
        const test::Comparison c = test::compare(*film_on, *film_off, all);
        // The standard error of a difference of two independent image means.
        EXPECT_NEAR(c.mean_a, c.mean_b, 4.0 * c.se) << (quad ? "quad: " : "sphere: ") << test::describe(c);
        // The strategy pays: at equal samples (a quarter, so standard errors × 2) it is less noisy.
        EXPECT_LT(test::image_mean_y(*film_on).standard_error, 2.0 * test::image_mean_y(*film_off).standard_error);
        for (const CausticNeeBug bug : {CausticNeeBug::no_bsdf_side_weight, CausticNeeBug::no_cos_y}) {
            RenderSettings planted = test::small_settings(24, 16, 4096, 3);
            planted.integrator.caustic_nee_bug = bug;
            const test::Comparison b = test::compare(*test::render_film(scene, planted), *film_off, all);
            EXPECT_GT(std::fabs(b.mean_a - b.mean_b), 6.0 * b.se)
                << (quad ? "quad" : "sphere") << ", planted bug " << int(bug) << " not caught: " << test::describe(b);
        }
    }
}

TEST(SphereCaustics, FilmIsTheSameWhateverTheThreadCount) {
    std::optional<Scene> scene = load_builtin_scene("cornell-sphere", {});
    ASSERT_TRUE(scene.has_value());
    for (const SamplerKind sampler : {SamplerKind::independent, SamplerKind::sobol}) {
        RenderSettings rs = test::small_settings(32, 32, 8, 7, 1);
        rs.sampler = sampler;
        const auto one = test::render_film(*scene, rs);
        EXPECT_EQ(test::count_bad_pixels(*one), 0);
        EXPECT_EQ(one->rejected_samples(), 0u);
        for (const int threads : {2, 7}) {
            rs.threads = threads;
            EXPECT_EQ(test::count_differences(*one, *test::render_film(*scene, rs)), 0u) << threads << " threads";
        }
    }
}

// ---- The reflection chain x → mirror reflection off the sphere → y ----

TEST(SphereReflection, EveryRootReflectsToYAndNoneIsMissedAwayFromFolds) {
    std::mt19937_64 gen(17);
    const DVec3 c(0.3, -0.2, 0.1);
    const double R = 0.4;
    const SphereChainNodes nodes = SphereChainNodes::reflection();
    int roots_total = 0, missed_near_fold = 0, most = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const DVec3 x = random_outside(gen, c, 1.02 * R, 4.0 * R);
        const DVec3 y = random_outside(gen, c, 1.02 * R, 6.0 * R);
        const SphereChain chain(x, c, R, nodes, y);
        ASSERT_TRUE(chain.valid());
        SphereChainRoot roots[SphereChain::kMaxRoots];
        const int n = chain.solve(roots);
        roots_total += n;
        most = std::max(most, n);
        for (int i = 0; i < n; ++i) {
            // The found direction, mirrored off the sphere in 3-D, passes within 1e-6 of y.
            DVec3 p, w_out;
            ASSERT_TRUE(reflect_off_sphere(x, roots[i].wx, c, R, p, w_out)) << trial;
            EXPECT_LT(distance_from_ray(p, w_out, y), 1e-6) << trial << " root " << i;
            EXPECT_LT(length(p - roots[i].entry), 1e-9) << trial;
            EXPECT_LT(length(p - roots[i].exit), 1e-9) << trial;
            EXPECT_LT(length(w_out - roots[i].w_exit), 1e-9) << trial;
            // The mirror law's angles: cos θ in = cos θ out = the root's cos_in.
            const DVec3 normal = (p - c) * (1.0 / R);
            EXPECT_NEAR(-dot(roots[i].wx, normal), roots[i].cos_in, 1e-9) << trial;
            EXPECT_NEAR(dot(roots[i].w_exit, normal), roots[i].cos_in, 1e-9) << trial;
        }
        // Every root of a dense scan is found, except pairs closer than the solver's cell.
        const std::vector<double> dense = dense_roots(chain, 20000);
        EXPECT_LE(dense.size(), 4u) << trial;  // Alhazen's problem: at most four
        missed_near_fold += count_missed_roots(roots, n, dense, trial);
        EXPECT_LE(n, static_cast<int>(dense.size())) << trial;
    }
    EXPECT_GT(roots_total, 1000);
    EXPECT_LT(missed_near_fold, roots_total / 50 + 1) << roots_total;
    std::printf("reflection chain: %d roots in 3000 configurations (at most %d in one), %d missed at folds\n",
                roots_total, most, missed_near_fold);
}

/// |dω_x/dA_y| of the reflection chain against a finite difference (as for refraction), and
/// a planted bug (the in-plane factor dα/dθ dropped: the density per unit θ instead of α)
/// that the same comparison rejects.
TEST(SphereReflection, JacobianMatchesAFiniteDifferenceAndAPlantedBugFails) {
    std::mt19937_64 gen(23);
    const DVec3 c(0.0, 0.0, 0.0);
    const double R = 0.5;
    const SphereChainNodes nodes = SphereChainNodes::reflection();
    int checked = 0, planted_caught = 0;
    for (int trial = 0; trial < 4000 && checked < 300; ++trial) {
        const DVec3 x = random_outside(gen, c, 1.1 * R, 4.0 * R);
        const DVec3 y = random_outside(gen, c, 1.2 * R, 5.0 * R);
        const DVec3 n_y = normalize(random_outside(gen, DVec3(), 0.5, 1.0));
        const SphereChain chain(x, c, R, nodes, y);
        SphereChainRoot roots[SphereChain::kMaxRoots];
        const int n = chain.solve(roots);
        for (int i = 0; i < n; ++i) {
            const SphereChainRoot& r = roots[i];
            const double cos_y = std::fabs(dot(n_y, r.w_exit));
            if (cos_y < 0.2 || r.cos_in < 0.1) continue;  // grazing: the difference is poor there
            DVec3 s, t;
            tangent_basis(r.wx, s, t);
            const double eps = 1e-6;
            auto hit_plane = [&](const DVec3& w, DVec3& p) {
                DVec3 q, wq;
                if (!reflect_off_sphere(x, w, c, R, q, wq)) return false;
                p = q + wq * (dot(y - q, n_y) / dot(wq, n_y));
                return true;
            };
            DVec3 p0, p1, p2, m1, m2;
            if (!hit_plane(r.wx, p0) || !hit_plane(normalize(r.wx + s * eps), p1) ||
                !hit_plane(normalize(r.wx + t * eps), p2) || !hit_plane(normalize(r.wx - s * eps), m1) ||
                !hit_plane(normalize(r.wx - t * eps), m2))
                continue;
            const double area = length(cross(p1 - m1, p2 - m2)) * 0.25;
            const double fd = eps * eps / area;
            const double asym = (length((p1 - p0) + (m1 - p0)) + length((p2 - p0) + (m2 - p0))) /
                                (length(p1 - m1) + length(p2 - m2));
            if (asym > 1e-3) continue;
            const double tolerance = 1e-4 + 20.0 * asym;
            const double analytic = r.dw_dAperp * cos_y;
            EXPECT_NEAR(analytic / fd, 1.0, tolerance) << trial;
            const SphereChain::Eval e = chain.eval(r.sin_theta, r.cos_in);
            planted_caught += std::fabs(analytic / e.alpha_p / fd - 1.0) > tolerance;
            ++checked;
        }
    }
    EXPECT_GE(checked, 100);
    EXPECT_GE(planted_caught, checked * 95 / 100) << checked;
}

/// A shiny ball (plastic: kd + a mirror lobe ks; or clear glass: Fresnel reflection) over a
/// finite diffuse floor, lit by a small emitting sphere and a small tilted quad below the
/// floor's level beyond its edges: the floor's top sees no light directly, so the image
/// beside the lights themselves is mostly the reflection caustics (and, for plastic, the
/// light its diffuse underside passes on), and a bug in them moves the image mean.
Scene reflection_scene(bool glass) {
    const std::string ball = glass ? R"({"kt": 1.0, "ior": 1.5})" : R"({"kd": 0.3, "ks": 0.5})";
    const std::string text = R"({"camera": {"position": [0, 0.9, 1.5], "look_at": [0, 0.08, 0], "vfov_degrees": 28},
      "materials": {"floor": {"type": "diffuse", "kd": 0.8}, "ball": )" + ball + R"(},
      "shapes": [{"type": "quad", "origin": [-0.45, 0, 0.6], "edge1": [0.9, 0, 0], "edge2": [0, 0, -1.2],
                  "material": "floor"},
        {"type": "sphere", "center": [0, 0.35, 0], "radius": 0.3, "material": "ball"},
        {"type": "sphere", "center": [0.75, -0.12, 0.15], "radius": 0.06, "emission": 40},
        {"type": "quad", "origin": [-0.75, -0.2, -0.05], "edge1": [0, 0, 0.12], "edge2": [0.03, 0.12, 0],
         "emission": 40}]})";
    return load_scene_text(text, "reflection.json", "reflection", {}, {});
}

TEST(SphereReflection, SceneFindsItsReflectingSpheres) {
    const Scene plastic = reflection_scene(false);
    EXPECT_TRUE(plastic.effects.caustic_spheres);
    EXPECT_TRUE(plastic.sphere_chains.caustic_spheres.empty());
    ASSERT_EQ(plastic.sphere_chains.reflecting_spheres.size(), 1u);
    EXPECT_TRUE(plastic.sphere_chains.reflecting_spheres[0].has_kd);
    EXPECT_FALSE(plastic.sphere_chains.reflecting_spheres[0].has_kt);
    const Scene glass = reflection_scene(true);
    ASSERT_EQ(glass.sphere_chains.caustic_spheres.size(), 1u);
    ASSERT_EQ(glass.sphere_chains.reflecting_spheres.size(), 1u);
    EXPECT_TRUE(glass.sphere_chains.reflecting_spheres[0].has_kt);
    EXPECT_FLOAT_EQ(glass.sphere_chains.reflecting_spheres[0].eta, 1.5f);
    // A diffuse ball reflects nothing the strategy can sample: the scene keeps the old loop.
    const Scene diffuse = load_scene_text(R"({"camera": {"position": [0, 0.5, 2], "look_at": [0, 0, 0]},
      "materials": {"m": {"kd": 0.5}},
      "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.3, "material": "m"},
                 {"type": "sphere", "center": [0.6, 0.5, 0], "radius": 0.05, "emission": 10}]})",
                                          "diffuse.json", "diffuse", {}, {});
    EXPECT_FALSE(diffuse.effects.caustic_spheres);
    EXPECT_TRUE(diffuse.sphere_chains.reflecting_spheres.empty());
    std::optional<Scene> s = load_builtin_scene("cornell-sphere", {});
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(s->sphere_chains.reflecting_spheres.size(), 2u);  // the blue plastic ball and the glass ball
}

/// The image with specular next-event estimation off the ball + MIS against the same scene
/// with the reflections left to BSDF sampling (--caustic-nee off): equal means within the
/// measured standard errors. Each planted bug (the BSDF side's weight dropped, cos θ_y
/// dropped, the Fresnel reflectance taken from inside the ball) is caught against the
/// correct strategy's image, whose noise on the floor is far lower than BSDF sampling's.
TEST(SphereReflection, SpecularNextEventEstimationIsUnbiasedAndPlantedBugsAreCaught) {
    for (const bool glass : {false, true}) {
        const Scene scene = reflection_scene(glass);
        // Glass: at most two bounces, which keeps the reflection off the ball (floor, ball,
        // light) and drops the chains with internal reflections whose fireflies would
        // otherwise dominate the noise (and checks the strategy's depth limit).
        const int max_depth = glass ? 2 : IntegratorSettings::kUnbounded;
        RenderSettings on = test::small_settings(24, 16, 4096, 1);
        on.integrator.max_depth = max_depth;
        RenderSettings off = test::small_settings(24, 16, 4096, 2);
        off.integrator.caustic_nee = false;
        off.integrator.max_depth = max_depth;
        const auto film_on = test::render_film(scene, on);
        const auto film_off = test::render_film(scene, off);
        EXPECT_EQ(test::count_bad_pixels(*film_on), 0);
        EXPECT_EQ(film_on->rejected_samples(), 0u);
        const auto all = [](int, int) { return true; };
        const test::Comparison c = test::compare(*film_on, *film_off, all);
        EXPECT_NEAR(c.mean_a, c.mean_b, 4.0 * c.se) << (glass ? "glass: " : "plastic: ") << test::describe(c);
        // The floor below the ball's highlights (rows 7 and down of 16): the ball's own
        // pixels, where the camera sees the lights with the probability of the reflection's
        // lobe choice, are far noisier than the reflection caustic on the floor.
        const auto floor_rows = [](int, int y) { return y >= 7; };
        const std::vector<CausticNeeBug> bugs =
            glass ? std::vector<CausticNeeBug>{CausticNeeBug::wrong_reflectance}
                  : std::vector<CausticNeeBug>{CausticNeeBug::no_bsdf_side_weight, CausticNeeBug::no_cos_y};
        for (const CausticNeeBug bug : bugs) {
            RenderSettings planted = test::small_settings(24, 16, 4096, 3);
            planted.integrator.caustic_nee_bug = bug;
            planted.integrator.max_depth = max_depth;
            const test::Comparison b =
                test::compare(*test::render_film(scene, planted), *film_on, floor_rows);
            EXPECT_GT(std::fabs(b.mean_a - b.mean_b), 6.0 * b.se)
                << (glass ? "glass" : "plastic") << ", planted bug " << int(bug) << " not caught: " << test::describe(b);
            std::printf("%s, planted bug %d: %.1f standard errors\n", glass ? "glass" : "plastic", int(bug),
                        std::fabs(b.mean_a - b.mean_b) / b.se);
        }
    }
}

}  // namespace
}  // namespace spt

// Hard cases (issue 6, ROBUSTNESS.md §7): each case is a small scene file in tests/hard_cases/
// whose "description" states the expectation. Every test loads its file, renders it with a
// fixed seed on 2 threads and checks
//   - the global invariant: no sample rejected as NaN/Inf or negative, every pixel finite and
//     ≥ 0, every pixel with all its samples;
//   - the case's own expectation: a value within kZ = 5 measured standard errors, an exact
//     value (relative 1e-5, float32), an exact equality, or a bound.
//
// Statistics. σ is the pixel's measured standard error of Y (Film::pixel_y_standard_error).
// With kZ = 5 and at most ~600 pixels per check a correct renderer fails with probability
// below 600 · 5.7e-7 ≈ 3e-4 (Gaussian tail, union bound); every render is deterministic.
// "Exactly" for a pixel whose radiance is the same on every path (mirrors, convex furnaces,
// depth-capped furnaces without roulette): the film Y still carries the noise of wavelength
// sampling, so the scene is compared with a reference rendered with the same seed (same
// wavelengths, same pixel positions) whose radiance is 1 at every wavelength: the ratio is
// the path weight, exact to float rounding. One allowance, for scenes with a diffuse lobe: the
// renderer drops a cosine-hemisphere sample that lands exactly on the horizon (ROBUSTNESS 7.18:
// pdf 0, "the sample is dropped"). With the concentric mapping this happens when u1 or u2 is
// exactly 0 (a = 2u − 1 = −1), probability 6.8e-8 per diffuse bounce (measured over the whole
// 2^-24 grid), and that path ends early. Such pixels may fall short of the exact value by at
// most one path's share; nothing may ever exceed it.
//
// Expected values that vary across a pixel (a lit plane) are integrated over the pixel with
// the renderer's own camera model (Camera::generate_ray) on a fine grid, in double.
//
// Each test prints one "[hard case]" line with its measured margin (value ± σ, largest z).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdarg>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <future>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "core/rng.h"
#include "model/camera.h"
#include "model/bsdfs/fresnel.h"
#include "scene/scene_loader.h"
#include "spectral/cie.h"
#include "test_scenes.h"

namespace spt {
namespace {

using test::count_bad_pixels;
using test::image_mean_y;
using test::ImageMean;
using test::small_settings;

constexpr double kZ = 5.0;          // z-score bound
constexpr double kExactRel = 1e-5;  // "exact" in float32
constexpr double kPi = std::numbers::pi;

// ---------------------------------------------------------------------------------------
// Loading, rendering and the global invariant.

using test::environment_only;
std::string case_path(const std::string& name) { return test::hard_case_path(name); }
Scene load_case(const std::string& name) { return test::load_hard_case(name); }

/// The file's image size and spp, a fixed seed, 2 threads.
RenderSettings case_settings(const Scene& scene, std::uint64_t seed) {
    return small_settings(scene.width, scene.height, scene.spp, seed, 2);
}

std::unique_ptr<Film> render_case(const Scene& scene, const RenderSettings& rs, RenderStats* stats = nullptr) {
    return test::render_film(scene, rs, stats);
}

/// The invariant of every case: nothing rejected, every pixel finite and ≥ 0 in X, Y, Z, and
/// every pixel holding all of its samples.
void expect_clean(const Film& film, const RenderSettings& rs, const std::string& what) {
    EXPECT_EQ(film.rejected_nonfinite(), 0u) << what << ": NaN/Inf samples";
    EXPECT_EQ(film.rejected_negative(), 0u) << what << ": negative samples";
    EXPECT_EQ(count_bad_pixels(film), 0) << what << ": pixels that are not finite and >= 0";
    int short_pixels = 0;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x)
            if (film.sample_count(x, y) != std::uint32_t(rs.spp)) ++short_pixels;
    EXPECT_EQ(short_pixels, 0) << what << ": pixels without all their samples";
}

/// The scene with the background replaced by a constant (a reference with radiance c).
Scene with_background(Scene scene, double c) {
    scene.set_background(test::constant_spectrum(c));
    scene.finalize();
    return scene;
}

void report(const std::string& text) { std::printf("[hard case] %s\n", text.c_str()); }

/// printf-style formatting (the compiler checks the arguments against the format).
[[gnu::format(printf, 1, 2)]] std::string fmt(const char* format, ...) {
    char buf[1024];
    va_list args;
    va_start(args, format);
    std::vsnprintf(buf, sizeof buf, format, args);
    va_end(args);
    return buf;
}

// ---------------------------------------------------------------------------------------
// Per-pixel checks.

/// Largest |Y − expected(x, y)|/σ over the pixels for which `expected` has a value. A pixel
/// with σ = 0 must match exactly (relative 1e-6; absolute 0 for an expected 0).
struct ZCheck {
    double max_z = 0;
    int worst_x = -1, worst_y = -1;
    double worst_value = 0, worst_sigma = 0, worst_expected = 0;
    int checked = 0;
};
using ExpectedFn = std::function<std::optional<double>(int, int)>;

ZCheck max_z(const Film& film, const ExpectedFn& expected) {
    ZCheck r;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const std::optional<double> e = expected(x, y);
            if (!e) continue;
            ++r.checked;
            const double v = film.pixel_xyz(x, y).y;
            const double se = film.pixel_y_standard_error(x, y);
            double z;
            if (se > 0) z = std::fabs(v - *e) / se;
            else z = std::fabs(v - *e) <= 1e-6 * std::fabs(*e) ? 0.0 : std::numeric_limits<double>::infinity();
            if (r.worst_x < 0 || !(z <= r.max_z)) {
                r.max_z = z;
                r.worst_x = x, r.worst_y = y;
                r.worst_value = v, r.worst_sigma = se, r.worst_expected = *e;
            }
        }
    return r;
}

std::string describe(const ZCheck& r) {
    return fmt("%d pixels, max z = %.3g at (", r.checked, r.max_z) + std::to_string(r.worst_x) + ", " +
           std::to_string(r.worst_y) + fmt("): Y = %.7g ± %.3g, expected %.7g", r.worst_value, r.worst_sigma,
                                           r.worst_expected);
}

/// Ratio of the scene's Y to the reference's Y (same seed) against the expected path weight,
/// relative to it: the largest |error| over the pixels within kExactRel of exact, and the
/// pixels that fall short by more (paths ended by a dropped horizon sample).
struct RatioCheck {
    double max_rel = 0;  ///< over the pixels not short
    int worst_x = -1, worst_y = -1;
    double worst_ratio = 0;
    int checked = 0;
    int short_pixels = 0;
    double worst_shortfall = 0;  ///< largest relative shortfall
};
RatioCheck max_ratio_error(const Film& film, const Film& ref, const ExpectedFn& expected) {
    RatioCheck r;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const std::optional<double> e = expected(x, y);
            if (!e) continue;
            ++r.checked;
            const double ratio = film.pixel_xyz(x, y).y / ref.pixel_xyz(x, y).y;
            const double rel = (ratio - *e) / *e;
            if (rel < -kExactRel) {
                ++r.short_pixels;
                r.worst_shortfall = std::max(r.worst_shortfall, -rel);
                continue;
            }
            if (r.worst_x < 0 || !(std::fabs(rel) <= r.max_rel)) {
                r.max_rel = std::fabs(rel);
                r.worst_x = x, r.worst_y = y, r.worst_ratio = ratio;
            }
        }
    return r;
}

std::string describe(const RatioCheck& r) {
    std::string s = fmt("%d pixels, max relative error %.3g at (", r.checked, r.max_rel) + std::to_string(r.worst_x) +
                    ", " + std::to_string(r.worst_y) + fmt("): ratio %.9g", r.worst_ratio);
    if (r.short_pixels > 0) s += fmt("; %d pixel(s) short by up to %.3g", r.short_pixels, r.worst_shortfall);
    return s;
}

/// The exactness check. Without a diffuse lobe every path has the exact weight. With one, at
/// most one pixel may fall short, by at most one path's share (3/spp: a sample's Y weight is
/// within 3× the mean), as a dropped horizon sample would make it (see the header comment).
void expect_exact(const RatioCheck& r, bool diffuse, int spp) {
    EXPECT_LE(r.max_rel, kExactRel) << describe(r);
    if (!diffuse) {
        EXPECT_EQ(r.short_pixels, 0) << describe(r);
        return;
    }
    EXPECT_LE(r.short_pixels, 1) << describe(r);
    EXPECT_LE(r.worst_shortfall, 3.0 / spp) << describe(r);
}

/// Average of f over pixel (x, y): an n×n grid of ray positions through the pixel, in the
/// renderer's camera model.
double pixel_average(const Scene& scene, int width, int height, int x, int y,
                     const std::function<double(const Ray&)>& f, int n = 16) {
    const Camera camera(scene.camera, width, height);
    double sum = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            sum += f(camera.generate_ray(float(x) + (float(i) + 0.5f) / float(n),
                                         float(y) + (float(j) + 0.5f) / float(n)));
    return sum / (n * n);
}

/// Whether pred holds for all (1) / none (0) / some (-1) rays of an (n+1)×(n+1) grid that
/// includes the pixel's edges and corners.
int pixel_coverage(const Scene& scene, int width, int height, int x, int y,
                   const std::function<bool(const Ray&)>& pred, int n = 32) {
    const Camera camera(scene.camera, width, height);
    int yes = 0, total = 0;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i, ++total)
            yes += pred(camera.generate_ray(float(x) + std::min(float(i) / float(n), 0.99999994f),
                                            float(y) + std::min(float(j) / float(n), 0.99999994f)));
    return yes == total ? 1 : yes == 0 ? 0 : -1;
}

// Double-precision geometry for expected values.
struct D3 {
    double x, y, z;
};
D3 d3(const Vec3& v) { return {v.x, v.y, v.z}; }
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator*(D3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 unit(D3 a) { return a * (1.0 / std::sqrt(dot(a, a))); }

/// Hit of a ray with the plane dot(n, p) = offset (t > 0), or nullopt.
std::optional<D3> hit_plane(const Ray& ray, D3 n, double offset) {
    const D3 o = d3(ray.o), d = d3(ray.d);
    const double t = (offset - dot(n, o)) / dot(n, d);
    if (!(t > 0)) return std::nullopt;
    return o + d * t;
}

/// Smallest t > 0 where the ray meets the sphere, or nullopt.
std::optional<double> hit_sphere(const Ray& ray, D3 c, double r) {
    const D3 o = d3(ray.o) - c, d = d3(ray.d);
    const double b = dot(o, d) / dot(d, d);
    const D3 v = o - d * b;
    const double disc = (r * r - dot(v, v)) / dot(d, d);
    if (disc < 0) return std::nullopt;
    const double h = std::sqrt(disc);
    if (-b - h > 0) return -b - h;
    if (-b + h > 0) return -b + h;
    return std::nullopt;
}

/// Radiance of a Lambertian point p with normal n (albedo a) lit by a point light of
/// intensity I at L: (a/π)·I·cos/r², 0 from behind.
double lambert_point_light(D3 p, D3 n, double a, D3 light, double intensity) {
    const D3 w = light - p;
    const double r2 = dot(w, w);
    const double c = dot(w, n) / std::sqrt(r2);
    return c > 0 ? a / kPi * intensity * c / r2 : 0.0;
}

/// Unpolarised Fresnel reflectance in double (cos_i on the incident side, eta = n_t/n_i).
double fresnel(double cos_i, double eta) {
    const double sin2_t = (1 - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1) return 1;
    const double cos_t = std::sqrt(1 - sin2_t);
    const double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    const double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5 * (rp * rp + rs * rs);
}

/// Normalised unit vector from the numbers a scene file gives (as the loader does).
D3 unit_from(double x, double y, double z) { return unit({x, y, z}); }

/// XYZ of the constant spectrum 1 through the film's colour matching functions (the tables
/// are piecewise linear between 1-nm entries, so the trapezoid rule on them is exact).
Xyz xyz_of_constant_one() {
    const Observer& cie = Cie1931::get();
    Xyz s;
    for (int l = 360; l < 830; ++l) {
        const Xyz a = cie.cmf(float(l)), b = cie.cmf(float(l + 1));
        s.x += 0.5 * (a.x + b.x), s.y += 0.5 * (a.y + b.y), s.z += 0.5 * (a.z + b.z);
    }
    const double n = cie.y_integral();
    return {s.x / n, s.y / n, s.z / n};
}

/// Image mean of X, Y, Z with standard errors from the spread across pixels (valid when
/// every pixel has the same expectation, as in a furnace).
struct XyzMean {
    Xyz mean, se;
};
XyzMean image_mean_xyz_uniform(const Film& film) {
    const int n = film.width() * film.height();
    Xyz s, s2;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const Xyz c = film.pixel_xyz(x, y);
            s.x += c.x, s.y += c.y, s.z += c.z;
            s2.x += c.x * c.x, s2.y += c.y * c.y, s2.z += c.z * c.z;
        }
    auto se = [n](double sum, double sum2) {
        const double m = sum / n;
        return std::sqrt(std::max(0.0, (sum2 / n - m * m) * n / (n - 1)) / n);
    };
    return {{s.x / n, s.y / n, s.z / n}, {se(s.x, s2.x), se(s.y, s2.y), se(s.z, s2.z)}};
}

/// Runs f on another thread; a render that never ends stops the whole binary (instead of
/// hanging the suite).
template <typename F>
void run_with_watchdog(F f, std::chrono::seconds limit, const char* what) {
    auto done = std::async(std::launch::async, f);
    if (done.wait_for(limit) != std::future_status::ready) {
        std::fprintf(stderr, "FATAL: %s did not finish within %lld s\n", what, static_cast<long long>(limit.count()));
        std::_Exit(1);
    }
    done.get();
}

/// Every file of this suite carries a description of its case and expectation.
TEST(HardCase, EveryFileLoadsAndDescribesItsCase) {
    for (const char* name :
         {"glass_furnace", "glass_furnace_bk7", "glass_furnace_index4", "camera_inside_glass",
          "light_inside_glass", "sphere_tangent_plane", "coplanar_planes", "nearly_parallel_planes",
          "parallel_planes_grazing", "grazing_plane_environment", "cornell_point_scale_1e-4",
          "cornell_point_scale_1e4", "point_light_1e-6_above_plane", "point_light_on_plane",
          "glass_index_one", "bright_emitter", "zero_reflectance", "reflectance_sum_one",
          "mirror_sphere_environment", "diffuse_sphere_environment", "facing_mirrors",
          "degenerate_mesh", "degenerate_mesh_clean", "thin_glass_shell"}) {
        EXPECT_NO_THROW(load_case(name)) << name;
        std::FILE* f = std::fopen(case_path(name).c_str(), "rb");
        ASSERT_TRUE(f) << name;
        char head[64] = {};
        const std::size_t n = std::fread(head, 1, sizeof head - 1, f);
        std::fclose(f);
        EXPECT_NE(std::string(head, n).find("\"description\""), std::string::npos) << name;
    }
}

// ---------------------------------------------------------------------------------------
// Dielectric furnaces (ROBUSTNESS 7.13).

/// A furnace scene whose every pixel has expectation `expected`. Roulette on (the default
/// settings): the image mean within kZ·σ. Per pixel: if `exact_depth` > 0, with roulette off
/// and that depth cap, exactly `expected` relative to the bare environment; otherwise within
/// kZ·σ with roulette on. (Per-pixel z-scores are not used with roulette on when the exact
/// check exists: in a glass sphere a path is killed by roulette rarely, about once per few
/// hundred paths, so a pixel's measured σ misses that term whenever none of its 256 paths
/// was killed; over 40 seeds the η = 4 sphere then showed z up to 6.4 in 15 runs. The image
/// mean pools the kills and its σ is sound.)
void expect_uniform_furnace(const std::string& name, double expected, int exact_depth, std::uint64_t seed) {
    const Scene scene = load_case(name);
    const RenderSettings rs = case_settings(scene, seed);
    ASSERT_TRUE(rs.integrator.roulette);
    ASSERT_EQ(rs.integrator.max_depth, IntegratorSettings::kUnbounded);
    const auto film = render_case(scene, rs);
    expect_clean(*film, rs, name);
    const ImageMean m = image_mean_y(*film);
    EXPECT_NEAR(m.mean, expected, kZ * m.standard_error);
    EXPECT_LT(m.standard_error, 0.005 * expected) << "too noisy to detect a 2.5% bias";
    std::string line = name + fmt(": mean Y = %.6f ± %.6f (expected %g, z = %.2f)", m.mean, m.standard_error,
                                  expected, (m.mean - expected) / m.standard_error);
    if (exact_depth == 0) {
        const ZCheck z = max_z(*film, [&](int, int) { return expected; });
        EXPECT_LE(z.max_z, kZ) << describe(z);
        line += "; " + describe(z);
    } else {
        RenderSettings exact = rs;
        exact.integrator.roulette = false;
        exact.integrator.max_depth = exact_depth;
        const auto a = render_case(scene, exact);
        const auto ref = render_case(environment_only(with_background(scene, 1.0)), exact);
        expect_clean(*a, exact, name + " without roulette");
        const RatioCheck r = max_ratio_error(*a, *ref, [&](int, int) { return expected; });
        expect_exact(r, false, exact.spp);
        line += "; roulette off, depth " + std::to_string(exact_depth) + ": " + describe(r);
    }
    report(line);
}

TEST(HardCase, GlassFurnace) { expect_uniform_furnace("glass_furnace", 1.0, 10000, 101); }

TEST(HardCase, GlassFurnaceIndex4) { expect_uniform_furnace("glass_furnace_index4", 1.0, 10000, 103); }

/// Dispersive BK7: Y = 1 per pixel and the image keeps the chromaticity of the constant
/// spectrum (X and Z of 1 through the film's tables) — a path that lost energy at some
/// wavelengths would tint the sphere.
TEST(HardCase, GlassFurnaceBk7) {
    const Scene scene = load_case("glass_furnace_bk7");
    ASSERT_TRUE(scene.effects.dispersion);
    expect_uniform_furnace("glass_furnace_bk7", 1.0, 0, 102);
    const auto film = render_case(scene, case_settings(scene, 102));
    const XyzMean m = image_mean_xyz_uniform(*film);
    const Xyz one = xyz_of_constant_one();
    EXPECT_NEAR(one.x, 1.00008, 2e-5);
    EXPECT_NEAR(one.y, 1.0, 1e-6);
    EXPECT_NEAR(one.z, 1.00033, 2e-5);
    EXPECT_NEAR(m.mean.x, one.x, kZ * m.se.x);
    EXPECT_NEAR(m.mean.y, one.y, kZ * m.se.y);
    EXPECT_NEAR(m.mean.z, one.z, kZ * m.se.z);
    EXPECT_LT(m.se.z, 0.01);
    report(fmt("glass_furnace_bk7 chromaticity: mean X = %.5f ± %.5f (%.5f), Z = %.5f ± %.5f", m.mean.x, m.se.x,
               one.x, m.mean.z, m.se.z) +
           fmt(" (%.5f)", one.z));
}

/// Camera inside the glass, within 1/η of the centre: every path leaves with weight n² = 2.25.
TEST(HardCase, CameraInsideGlass) {
    const Scene scene = load_case("camera_inside_glass");
    const double r = std::sqrt(dot(d3(scene.camera.position), d3(scene.camera.position)));
    ASSERT_LT(r, 1.0 / 1.5) << "a camera beyond 1/eta would see directions trapped by TIR";
    expect_uniform_furnace("camera_inside_glass", 2.25, 10000, 104);
}

/// Emitter inside a glass sphere seen from afar: (1 − F(θ))/η² inside the apparent radius
/// 0.45 (θ the incidence angle, sin θ = impact parameter), exactly 0 outside.
TEST(HardCase, LightInsideGlass) {
    const Scene scene = load_case("light_inside_glass");
    const RenderSettings rs = case_settings(scene, 105);
    const auto film = render_case(scene, rs);
    expect_clean(*film, rs, "light_inside_glass");
    const double eta = 1.5, r_emitter = 0.3;
    auto impact = [](const Ray& ray) {  // distance of the ray's line from the centre
        const D3 o = d3(ray.o), d = unit(d3(ray.d));
        const D3 v = o - d * dot(o, d);
        return std::sqrt(dot(v, v));
    };
    auto radiance = [&](const Ray& ray) {
        const double b = impact(ray);
        if (b / eta >= r_emitter) return 0.0;  // the refracted chord passes outside the emitter
        return (1 - fresnel(std::sqrt(1 - b * b), eta)) / (eta * eta);
    };
    const int w = rs.width, h = rs.height, centre = w / 2;
    std::vector<int> kind(w);  // 1: entirely inside the apparent disc, 0: entirely outside
    for (int x = 0; x < w; ++x)
        kind[x] = pixel_coverage(scene, w, h, x, 0, [&](const Ray& ray) { return impact(ray) < eta * r_emitter; });
    int inside = 0, outside = 0;
    for (int x = 0; x < w; ++x) inside += kind[x] == 1, outside += kind[x] == 0;
    ASSERT_GE(inside, 15);
    ASSERT_GE(outside, 4);
    ASSERT_EQ(kind[centre], 1);
    ASSERT_EQ(kind[w - 2], 0) << "the pixel just beyond the apparent radius 0.45";
    const ZCheck z = max_z(*film, [&](int x, int) -> std::optional<double> {
        if (kind[x] != 1) return std::nullopt;
        return pixel_average(scene, w, h, x, 0, radiance);
    });
    EXPECT_LE(z.max_z, kZ) << describe(z);
    const double expected_centre = pixel_average(scene, w, h, centre, 0, radiance);
    EXPECT_NEAR(expected_centre, 0.96 / 2.25, 1e-5);
    const double v = film->pixel_xyz(centre, 0).y, se = film->pixel_y_standard_error(centre, 0);
    EXPECT_NEAR(v, 0.96 / 2.25, kZ * se);
    EXPECT_LT(se, 0.01);
    int nonzero_outside = 0;
    for (int x = 0; x < w; ++x) {
        const Xyz c = film->pixel_xyz(x, 0);
        if (kind[x] == 0 && (c.x != 0 || c.y != 0 || c.z != 0)) ++nonzero_outside;
    }
    EXPECT_EQ(nonzero_outside, 0) << "light reached pixels outside the apparent radius 0.45";
    const Xyz just_outside = film->pixel_xyz(w - 2, 0);
    report(fmt("light_inside_glass: centre Y = %.6f ± %.6f (expected %.6f, z = %.2f); pixel at 0.475..0.525: Y = %g",
               v, se, 0.96 / 2.25, (v - 0.96 / 2.25) / se, just_outside.y) +
           "; " + describe(z));
}

// ---------------------------------------------------------------------------------------
// Contact, coplanar and grazing geometry (ROBUSTNESS 7.4, 7.18).

/// Unit sphere on the plane, light at height 3: the floor strip ρ = 1.20 … 2.50.
TEST(HardCase, SphereTangentToPlane) {
    const Scene scene = load_case("sphere_tangent_plane");
    const RenderSettings rs = case_settings(scene, 106);
    const auto film = render_case(scene, rs);
    expect_clean(*film, rs, "sphere_tangent_plane");
    const D3 light{0, 3, 0}, centre{0, 1, 0};
    const double a = 0.5;
    auto floor_point = [&](const Ray& ray) -> std::optional<D3> {
        if (hit_sphere(ray, centre, 1.0)) return std::nullopt;  // the camera ray meets the black sphere
        return hit_plane(ray, {0, 1, 0}, 0.0);
    };
    auto shadowed = [&](D3 p) {  // does the segment p → light meet the sphere?
        const D3 d = light - p;
        const double t = std::clamp(dot(centre - p, d) / dot(d, d), 0.0, 1.0);
        const D3 q = p + d * t - centre;
        return dot(q, q) < 1.0;
    };
    auto radiance = [&](const Ray& ray) {
        const std::optional<D3> p = floor_point(ray);
        if (!p || shadowed(*p)) return 0.0;
        return lambert_point_light(*p, {0, 1, 0}, a, light, 1.0);
    };
    const int w = rs.width;
    std::vector<int> lit(w);
    for (int x = 0; x < w; ++x)
        lit[x] = pixel_coverage(scene, w, 1, x, 0, [&](const Ray& ray) {
            const std::optional<D3> p = floor_point(ray);
            return p && !shadowed(*p);
        });
    // The strip's first pixel is at ρ = 1.2 (shadow), the last at ρ = 2.5 (lit).
    auto rho_of = [&](int x) {
        const std::optional<D3> p = floor_point(Camera(scene.camera, w, 1).generate_ray(float(x) + 0.5f, 0.5f));
        return p ? std::hypot(p->x, p->z) : -1.0;
    };
    ASSERT_NEAR(rho_of(0), 1.2, 1e-5);
    ASSERT_NEAR(rho_of(w - 1), 2.5, 1e-5);
    ASSERT_EQ(lit[0], 0);
    ASSERT_EQ(lit[w - 1], 1);
    int shadow_pixels = 0, nonzero_shadow = 0;
    for (int x = 0; x < w; ++x) {
        if (lit[x] != 0) continue;
        ++shadow_pixels;
        const Xyz c = film->pixel_xyz(x, 0);
        if (c.x != 0 || c.y != 0 || c.z != 0) ++nonzero_shadow;
        EXPECT_LT(rho_of(x), std::sqrt(3.0)) << "pixel " << x;
    }
    EXPECT_EQ(shadow_pixels, 27);  // ρ = 1.20 … 1.72: every pixel centred below √3 = 1.7320508
    EXPECT_EQ(nonzero_shadow, 0) << "light inside the shadow cone (rho < sqrt 3)";
    const ZCheck z = max_z(*film, [&](int x, int) -> std::optional<double> {
        if (lit[x] != 1) return std::nullopt;
        return pixel_average(scene, w, 1, x, 0, radiance);
    });
    EXPECT_EQ(z.checked, 38);  // ρ = 1.74 … 2.50
    EXPECT_LE(z.max_z, kZ) << describe(z);
    const double e25 = a / kPi * 3 / std::pow(9 + 2.5 * 2.5, 1.5);
    EXPECT_NEAR(pixel_average(scene, w, 1, w - 1, 0, radiance), e25, 1e-6 * e25);
    const double v = film->pixel_xyz(w - 1, 0).y, se = film->pixel_y_standard_error(w - 1, 0);
    EXPECT_NEAR(v, e25, kZ * se);
    report(fmt("sphere_tangent_plane: rho = 1.2 Y = %g (exactly 0 expected; %d shadow pixels all 0); rho = 2.5 Y = "
               "%.7f ± %.2g (expected %.7f, ",
               film->pixel_xyz(0, 0).y, shadow_pixels, v, se, e25) +
           fmt("z = %.2f); ", (v - e25) / se) + describe(z));
}

/// Lit-plane cases: every pixel is the direct light of one plane, integrated over the pixel.
void expect_lit_plane(const std::string& name, D3 n, double offset, double albedo,
                      const std::vector<std::pair<D3, double>>& lights, std::uint64_t seed,
                      const Scene* override_scene = nullptr) {
    const Scene scene = override_scene ? *override_scene : load_case(name);
    const RenderSettings rs = case_settings(scene, seed);
    const auto film = render_case(scene, rs);
    expect_clean(*film, rs, name);
    auto radiance = [&](const Ray& ray) {
        const std::optional<D3> p = hit_plane(ray, n, offset);
        if (!p) return 0.0;
        const D3 nf = dot(d3(ray.d), n) < 0 ? n : n * -1.0;  // the side the camera sees
        double L = 0;
        for (const auto& [pos, intensity] : lights) L += lambert_point_light(*p, nf, albedo, pos, intensity);
        return L;
    };
    int hits = 0;
    const ZCheck z = max_z(*film, [&](int x, int y) -> std::optional<double> {
        const double e = pixel_average(scene, rs.width, rs.height, x, y, radiance);
        hits += e > 0;
        return e;
    });
    EXPECT_EQ(hits, rs.width * rs.height) << "every pixel should see the lit plane";
    EXPECT_LE(z.max_z, kZ) << describe(z);
    const ImageMean m = image_mean_y(*film);
    double expected_mean = 0;
    for (int y = 0; y < rs.height; ++y)
        for (int x = 0; x < rs.width; ++x) expected_mean += pixel_average(scene, rs.width, rs.height, x, y, radiance);
    expected_mean /= rs.width * rs.height;
    EXPECT_NEAR(m.mean, expected_mean, kZ * m.standard_error);
    report(name + fmt(": mean Y = %.6f ± %.2g (expected %.6f, z = %.2f); ", m.mean, m.standard_error, expected_mean,
                      (m.mean - expected_mean) / m.standard_error) +
           describe(z));
}

TEST(HardCase, CoplanarPlanes) {
    const D3 n = unit_from(0.1, 1, -0.2);
    expect_lit_plane("coplanar_planes", n, 0.0, 0.5, {{n, 1.0}}, 107);
}

/// Where the planes cross (x = 0) they are closer than float rounding, and either may be
/// reported as the nearest hit; whichever it is, its shadow ray must not be blocked by the twin.
/// Known failure when written: Scene::intersect computes t for axis-aligned planes in float
/// ((position − o)·(1/d), relative error ~1e-7) but for other planes in double, so within
/// |x| ≲ 0.07 of the crossing line the lower plane can win; its hit point lies under the other
/// plane and its shadow ray (offset only by its own, near-zero, rounding bound) is blocked: a
/// dark band, −2.3% on the image mean. With t in double for both, the wrong picks vanish (0 of
/// 200000 probe rays).
TEST(HardCase, NearlyParallelPlanes) {
    expect_lit_plane("nearly_parallel_planes", {0, 1, 0}, 0.0, 0.5, {{{0, 1, 0}, 1.0}}, 108);
}

/// Black plane over an emitting plane 1e-5 below it, at 89.9°: exactly 0. Control: without
/// the black plane, every pixel sees the emitter.
TEST(HardCase, ParallelPlanesAtGrazingAngle) {
    const Scene scene = load_case("parallel_planes_grazing");
    const D3 view = unit(d3(scene.camera.look_at) - d3(scene.camera.position));
    EXPECT_NEAR(std::acos(-view.y) * 180 / kPi, 89.9, 1e-4);
    const RenderSettings rs = case_settings(scene, 109);
    const auto film = render_case(scene, rs);
    expect_clean(*film, rs, "parallel_planes_grazing");
    int lower_plane_pixels = 0;
    for (int y = 0; y < rs.height; ++y)
        for (int x = 0; x < rs.width; ++x) {
            const Xyz c = film->pixel_xyz(x, y);
            lower_plane_pixels += c.x != 0 || c.y != 0 || c.z != 0;
        }
    EXPECT_EQ(lower_plane_pixels, 0) << "rays reached the emitting plane 1e-5 below the black one";
    // Negative control: the emitter is in view once the black plane is gone.
    Scene open = scene;
    open.planes.erase(open.planes.begin());
    open.finalize();
    const auto control = render_case(open, rs);
    const ZCheck z = max_z(*control, [](int, int) { return 1.0; });
    EXPECT_LE(z.max_z, kZ) << "control: " << describe(z);
    report(fmt("parallel_planes_grazing: %d of %d pixels non-zero (expected 0); control without the black plane: ",
               lower_plane_pixels, rs.width * rs.height) +
           describe(z));
}

/// Tilted diffuse plane in Le = 1 at 89.9°: exactly its albedo.
TEST(HardCase, GrazingPlaneInEnvironment) {
    const Scene scene = load_case("grazing_plane_environment");
    const D3 n = unit_from(0.2, 1, -0.1);
    const D3 view = unit(d3(scene.camera.look_at) - d3(scene.camera.position));
    EXPECT_NEAR(std::acos(-dot(view, n)) * 180 / kPi, 89.9, 1e-4);
    const RenderSettings rs = case_settings(scene, 110);
    const auto film = render_case(scene, rs);
    expect_clean(*film, rs, "grazing_plane_environment");
    const double offset = dot(n, {3, -2, 5});
    for (int y = 0; y < rs.height; ++y)
        for (int x = 0; x < rs.width; ++x)
            ASSERT_EQ(pixel_coverage(scene, rs.width, rs.height, x, y,
                                     [&](const Ray& ray) { return hit_plane(ray, n, offset).has_value(); }, 4),
                      1)
                << "pixel " << x << ", " << y << " should see only the plane";
    const double a = 0.7;
    const ZCheck z = max_z(*film, [&](int, int) { return a; });
    EXPECT_LE(z.max_z, kZ) << describe(z);
    const auto ref = render_case(environment_only(scene), rs);
    const RatioCheck r = max_ratio_error(*film, *ref, [&](int, int) { return a; });
    expect_exact(r, true, rs.spp);
    report("grazing_plane_environment: " + describe(z) + "; exact: " + describe(r));
}

// ---------------------------------------------------------------------------------------
// Scale (ROBUSTNESS 7.3).

/// The scaled Cornell box against the built-in cornell-point at scale 1, same seed and size:
/// per-pixel two-sample z ≤ kZ, image means within 1%.
void expect_same_as_cornell_point(const std::string& name) {
    const Scene scaled = load_case(name);
    const std::optional<Scene> unit_scene = load_builtin_scene("cornell-point", SpectralResolution{});
    ASSERT_TRUE(unit_scene);
    const RenderSettings rs = case_settings(scaled, 111);
    const auto a = render_case(scaled, rs);
    const auto b = render_case(*unit_scene, rs);
    expect_clean(*a, rs, name);
    expect_clean(*b, rs, "cornell-point");
    double worst = 0;
    int wx = -1, wy = -1, identical = 0, black_only_scaled = 0;
    for (int y = 0; y < rs.height; ++y)
        for (int x = 0; x < rs.width; ++x) {
            const double va = a->pixel_xyz(x, y).y, vb = b->pixel_xyz(x, y).y;
            const double s = std::hypot(a->pixel_y_standard_error(x, y), b->pixel_y_standard_error(x, y));
            const double z = s > 0 ? std::fabs(va - vb) / s : (va == vb ? 0 : std::numeric_limits<double>::infinity());
            identical += va == vb;
            black_only_scaled += va == 0 && vb > 0;
            if (!(z <= worst)) worst = z, wx = x, wy = y;
        }
    EXPECT_LE(worst, kZ) << name << ": pixel " << wx << ", " << wy << ": " << a->pixel_xyz(wx, wy).y << " vs "
                         << b->pixel_xyz(wx, wy).y;
    EXPECT_EQ(black_only_scaled, 0) << "black pixels (acne) at this scale";
    const ImageMean ma = image_mean_y(*a), mb = image_mean_y(*b);
    EXPECT_NEAR(ma.mean / mb.mean, 1.0, 0.01);
    EXPECT_GT(mb.mean, 0.05);
    report(name + fmt(": mean Y = %.6f vs %.6f at scale 1 (ratio %.6f, σ = %.2g); max pixel z = %.3g", ma.mean, mb.mean,
                      ma.mean / mb.mean, ma.standard_error, worst) +
           fmt("; %d of %d pixels bit-identical", identical, rs.width * rs.height));
}

TEST(HardCase, CornellPointScaledBy1em4) { expect_same_as_cornell_point("cornell_point_scale_1e-4"); }
TEST(HardCase, CornellPointScaledBy1e4) { expect_same_as_cornell_point("cornell_point_scale_1e4"); }

// ---------------------------------------------------------------------------------------
// Point-light singularities (ROBUSTNESS 7.17).

TEST(HardCase, PointLight1em6AbovePlane) {
    const Scene scene = load_case("point_light_1e-6_above_plane");
    const RenderSettings rs = case_settings(scene, 112);
    const auto film = render_case(scene, rs);
    expect_clean(*film, rs, "point_light_1e-6_above_plane");
    const Vec3 light_position = std::get<PointLight>(scene.lights.at(scene.point_light_indices.at(0))).position;
    const double h = light_position.y;  // 1e-6 as a float
    ASSERT_NEAR(h, 1e-6, 1e-13);
    const double foot = 0.5 / kPi / (h * h);
    EXPECT_NEAR(0.1591549 / (1e-6 * 1e-6), 1.591549e11, 1e5);
    const D3 light = d3(light_position);
    auto radiance = [&](const Ray& ray) {
        const std::optional<D3> p = hit_plane(ray, {0, 1, 0}, 0.0);
        return p ? lambert_point_light(*p, {0, 1, 0}, 0.5, light, 1.0) : 0.0;
    };
    const ZCheck z = max_z(*film, [&](int x, int y) -> std::optional<double> {
        const double e = pixel_average(scene, rs.width, rs.height, x, y, radiance);
        EXPECT_NEAR(e, foot, 1e-4 * foot) << "the footprint should be far below h";
        return e;
    });
    EXPECT_LE(z.max_z, kZ) << describe(z);
    double worst_rel = 0;
    for (int y = 0; y < rs.height; ++y)
        for (int x = 0; x < rs.width; ++x)
            worst_rel = std::max(worst_rel, std::fabs(film->pixel_xyz(x, y).y / foot - 1));
    EXPECT_LT(worst_rel, 0.01);
    const double v = film->pixel_xyz(1, 1).y, se = film->pixel_y_standard_error(1, 1);
    report(fmt("point_light_1e-6_above_plane: centre Y = %.6e ± %.2e (expected %.6e, z = %.2f), worst pixel %.3g%% off; ",
               v, se, foot, (v - foot) / se, 100 * worst_rel) +
           describe(z));
}

/// A light exactly on the plane adds nothing (cos = 0 everywhere, distance 0 at its foot)
/// and spoils nothing: the image is the other light's, and alone it is exactly 0.
TEST(HardCase, PointLightOnPlane) {
    const Scene scene = load_case("point_light_on_plane");
    ASSERT_EQ(scene.point_light_indices.size(), 2u);
    ASSERT_EQ(std::get<PointLight>(scene.lights.at(scene.point_light_indices[0])).position.y, 0.f);
    expect_lit_plane("point_light_on_plane", {0, 1, 0}, 0.0, 0.5, {{{0.3, 1, -0.2}, 2.0}}, 113, &scene);
    Scene alone = scene;
    alone.lights.erase(alone.lights.begin() + alone.point_light_indices.at(1));  // the other light
    alone.finalize();
    const RenderSettings rs = case_settings(alone, 114);
    const auto film = render_case(alone, rs);
    expect_clean(*film, rs, "point_light_on_plane (light on the plane alone)");
    int nonzero = 0;
    for (int y = 0; y < rs.height; ++y)
        for (int x = 0; x < rs.width; ++x) nonzero += film->pixel_xyz(x, y).y != 0;
    EXPECT_EQ(nonzero, 0) << "a light in the plane cannot light it";
    report(fmt("point_light_on_plane: the on-plane light alone lights %d pixels (expected 0)", nonzero));
}

// ---------------------------------------------------------------------------------------
// Index of refraction 1.0 (ROBUSTNESS 7.13).

TEST(HardCase, GlassOfIndexOneIsInvisible) {
    const Scene scene = load_case("glass_index_one");
    ASSERT_EQ(scene.spheres.size(), 1u);
    Scene without = scene;
    without.spheres.clear();
    without.finalize();
    const RenderSettings rs_a = case_settings(scene, 115), rs_b = case_settings(without, 116);
    const auto a = render_case(scene, rs_a);
    const auto b = render_case(without, rs_b);
    expect_clean(*a, rs_a, "glass_index_one");
    double worst = 0;
    int wx = -1, wy = -1;
    for (int y = 0; y < rs_a.height; ++y)
        for (int x = 0; x < rs_a.width; ++x) {
            const double s = std::hypot(a->pixel_y_standard_error(x, y), b->pixel_y_standard_error(x, y));
            const double z = std::fabs(a->pixel_xyz(x, y).y - b->pixel_xyz(x, y).y) / s;
            if (!(z <= worst)) worst = z, wx = x, wy = y;
        }
    EXPECT_LE(worst, kZ) << "pixel " << wx << ", " << wy;
    const ImageMean ma = image_mean_y(*a), mb = image_mean_y(*b);
    const double s = std::hypot(ma.standard_error, mb.standard_error);
    EXPECT_NEAR(ma.mean, mb.mean, kZ * s);
    EXPECT_LT(s, 0.01 * mb.mean) << "too noisy to see a visible sphere";
    report(fmt("glass_index_one: mean Y = %.5f vs %.5f without the sphere (difference %.2g σ, σ = %.2g); max pixel z = "
               "%.3g",
               ma.mean, mb.mean, (ma.mean - mb.mean) / s, s, worst));
}

// ---------------------------------------------------------------------------------------
// Emission and reflectance extremes (ROBUSTNESS 7.15).

/// Le = 1e6 in the closed furnace: 5e6, and the Le = 1 film times 1e6 (same seed: roulette
/// depends on the throughput only, so the paths are the same), standard errors included.
TEST(HardCase, EmitterAMillionTimesBrighter) {
    const Scene scene = load_case("bright_emitter");
    Scene unit_scene = scene;
    std::get<SphereLight>(unit_scene.lights.at(unit_scene.spheres.at(0).light)).Le = test::constant_spectrum(1.0);
    unit_scene.finalize();
    const RenderSettings rs = case_settings(scene, 117);
    const auto film = render_case(scene, rs);
    const auto unit_film = render_case(unit_scene, rs);
    expect_clean(*film, rs, "bright_emitter");
    double worst_ratio = 0, worst_se_ratio = 0;
    for (int y = 0; y < rs.height; ++y)
        for (int x = 0; x < rs.width; ++x) {
            worst_ratio = std::max(worst_ratio, std::fabs(film->pixel_xyz(x, y).y / unit_film->pixel_xyz(x, y).y / 1e6 - 1));
            worst_se_ratio = std::max(worst_se_ratio, std::fabs(film->pixel_y_standard_error(x, y) /
                                                                    unit_film->pixel_y_standard_error(x, y) / 1e6 -
                                                                1));
        }
    EXPECT_LE(worst_ratio, kExactRel);
    EXPECT_LE(worst_se_ratio, 1e-4);
    const ZCheck z = max_z(*film, [](int, int) { return 5e6; });
    EXPECT_LE(z.max_z, kZ) << describe(z);
    const ImageMean m = image_mean_y(*film), mu = image_mean_y(*unit_film);
    EXPECT_NEAR(m.mean, 5e6, kZ * m.standard_error);
    EXPECT_NEAR(m.standard_error / m.mean, mu.standard_error / mu.mean, 1e-4 * mu.standard_error / mu.mean);
    report(fmt("bright_emitter: mean Y = %.6g ± %.3g (expected 5e6, z = %.2f); relative error %.4g vs %.4g at Le = 1; ",
               m.mean, m.standard_error, (m.mean - 5e6) / m.standard_error, m.standard_error / m.mean,
               mu.standard_error / mu.mean) +
           fmt("film / (1e6 * film at Le = 1) - 1 at most %.2g; ", worst_ratio) + describe(z));
}

/// All reflectances 0: only the emitter shows; pixels that never see it are exactly 0.
TEST(HardCase, ZeroReflectanceShowsOnlyTheEmitter) {
    const Scene scene = load_case("zero_reflectance");
    for (const Material& m : scene.materials) EXPECT_FALSE(m.reflects()) << m.name;
    const RenderSettings rs = case_settings(scene, 118);
    const auto film = render_case(scene, rs);
    expect_clean(*film, rs, "zero_reflectance");
    auto sees_emitter = [&](const Ray& ray) {
        const std::optional<Hit> hit = scene.intersect(ray);
        return hit && hit->light >= 0;
    };
    std::vector<int> kind(rs.width * rs.height);
    int emitter = 0, black = 0, nonzero_black = 0, mixed_over = 0;
    for (int y = 0; y < rs.height; ++y)
        for (int x = 0; x < rs.width; ++x) {
            const int k = kind[y * rs.width + x] = pixel_coverage(scene, rs.width, rs.height, x, y, sees_emitter);
            const Xyz c = film->pixel_xyz(x, y);
            if (k == 1) ++emitter;
            if (k == 0) ++black, nonzero_black += c.x != 0 || c.y != 0 || c.z != 0;
            if (k == -1 && c.y > 2.0 + kZ * film->pixel_y_standard_error(x, y)) ++mixed_over;
        }
    EXPECT_GE(emitter, 20);
    EXPECT_GE(black, 100);
    EXPECT_EQ(nonzero_black, 0) << "light from surfaces whose reflectance is exactly 0";
    EXPECT_EQ(mixed_over, 0);
    const ZCheck z = max_z(*film, [&](int x, int y) -> std::optional<double> {
        if (kind[y * rs.width + x] != 1) return std::nullopt;
        return 2.0;
    });
    EXPECT_LE(z.max_z, kZ) << describe(z);
    report(fmt("zero_reflectance: %d pixels never see the emitter, %d of them non-zero (expected 0); emitter pixels: ",
               black, nonzero_black) +
           describe(z));
}

/// kd + ks = 0.5 + 0.5 = 1, Le = 1, depth 10: 11 (roulette on, within kZ·σ; off, exactly).
TEST(HardCase, ReflectancesSummingToExactlyOne) {
    const Scene scene = load_case("reflectance_sum_one");
    RenderSettings rs = case_settings(scene, 119);
    rs.integrator.max_depth = 10;
    rs.integrator.roulette = true;
    const auto film = render_case(scene, rs);
    expect_clean(*film, rs, "reflectance_sum_one");
    const ZCheck z = max_z(*film, [](int, int) { return 11.0; });
    EXPECT_LE(z.max_z, kZ) << describe(z);
    const ImageMean m = image_mean_y(*film);
    EXPECT_NEAR(m.mean, 11.0, kZ * m.standard_error);
    EXPECT_LT(m.standard_error, 0.05) << "too noisy to detect a 2% bias";
    // Roulette off: every path is worth exactly 11; the reference emits 1 and reflects nothing.
    // Exactness is a property of BSDF sampling alone (LightSampling::bsdf, the estimator
    // before next-event estimation for area lights): sampling the emitting wall as a light
    // gives each path its own value. The roulette-on check above uses the default (MIS).
    RenderSettings exact = rs;
    exact.integrator.roulette = false;
    exact.integrator.light_sampling = LightSampling::bsdf;
    Scene emission_only = scene;
    LobeMixBsdf& wall = std::get<LobeMixBsdf>(emission_only.materials.at(0).bsdf);
    wall.kd = test::constant_spectrum(0.0);
    wall.ks = test::constant_spectrum(0.0);
    emission_only.finalize();
    const auto a = render_case(scene, exact);
    const auto ref = render_case(emission_only, exact);
    expect_clean(*a, exact, "reflectance_sum_one without roulette");
    const RatioCheck r = max_ratio_error(*a, *ref, [](int, int) { return 11.0; });
    expect_exact(r, true, exact.spp);
    report(fmt("reflectance_sum_one: mean Y = %.5f ± %.4f (expected 11, z = %.2f); ", m.mean, m.standard_error,
               (m.mean - 11) / m.standard_error) +
           describe(z) + "; roulette off: " + describe(r));
}

// ---------------------------------------------------------------------------------------
// Mirrors and convex furnaces (ROBUSTNESS 7.14).

TEST(HardCase, MirrorSphereInEnvironmentIsExactlyOne) {
    const Scene scene = load_case("mirror_sphere_environment");
    const RenderSettings rs = case_settings(scene, 120);
    const auto film = render_case(scene, rs);
    const auto ref = render_case(environment_only(scene), rs);
    expect_clean(*film, rs, "mirror_sphere_environment");
    const RatioCheck r = max_ratio_error(*film, *ref, [](int, int) { return 1.0; });
    expect_exact(r, false, rs.spp);
    report("mirror_sphere_environment: " + describe(r));
}

TEST(HardCase, DiffuseSphereInEnvironmentIsExactlyItsAlbedo) {
    const Scene scene = load_case("diffuse_sphere_environment");
    const RenderSettings rs = case_settings(scene, 121);
    const auto film = render_case(scene, rs);
    const auto ref = render_case(environment_only(scene), rs);
    expect_clean(*film, rs, "diffuse_sphere_environment");
    std::vector<int> kind(rs.width * rs.height);
    int on = 0, off = 0;
    for (int y = 0; y < rs.height; ++y)
        for (int x = 0; x < rs.width; ++x) {
            const int k = kind[y * rs.width + x] = pixel_coverage(
                scene, rs.width, rs.height, x, y, [](const Ray& ray) { return hit_sphere(ray, {0, 0, 0}, 1.0).has_value(); });
            on += k == 1, off += k == 0;
        }
    EXPECT_GE(on, 12);
    EXPECT_GE(off, 40);
    const RatioCheck r = max_ratio_error(*film, *ref, [&](int x, int y) -> std::optional<double> {
        const int k = kind[y * rs.width + x];
        if (k == -1) return std::nullopt;
        return k == 1 ? 0.6 : 1.0;
    });
    expect_exact(r, true, rs.spp);
    const ZCheck z = max_z(*film, [&](int x, int y) -> std::optional<double> {
        if (kind[y * rs.width + x] != 1) return std::nullopt;
        return 0.6;
    });
    EXPECT_LE(z.max_z, kZ) << describe(z);
    report(fmt("diffuse_sphere_environment: %d pixels on the sphere, %d off; ", on, off) + describe(r) + "; " +
           describe(z));
}

/// Lossless facing mirrors: roulette (survival capped at 0.95) ends every path, about
/// roulette_depth + 19 = 22 rays each; with roulette off the depth cap ends them. Image 0.
TEST(HardCase, FacingMirrorsEnd) {
    const Scene scene = load_case("facing_mirrors");
    const RenderSettings rs = case_settings(scene, 122);
    ASSERT_TRUE(rs.integrator.roulette);
    ASSERT_EQ(rs.integrator.max_depth, IntegratorSettings::kUnbounded);
    std::unique_ptr<Film> film;
    RenderStats stats;
    run_with_watchdog([&] { film = render_case(scene, rs, &stats); }, std::chrono::seconds(60),
                      "facing mirrors with roulette");
    expect_clean(*film, rs, "facing_mirrors");
    int nonzero = 0;
    for (int y = 0; y < rs.height; ++y)
        for (int x = 0; x < rs.width; ++x) nonzero += film->pixel_xyz(x, y).y != 0;
    EXPECT_EQ(nonzero, 0);
    const double paths = double(rs.width) * rs.height * rs.spp;
    ASSERT_EQ(stats.paths, std::uint64_t(paths));
    const double mean_rays = double(stats.rays) / paths;
    const double sigma = std::sqrt(0.95) / 0.05 / std::sqrt(paths);
    EXPECT_NEAR(mean_rays, 22.0, kZ * sigma);
    RenderSettings capped = rs;
    capped.integrator.roulette = false;
    capped.integrator.max_depth = 50;
    RenderStats capped_stats;
    std::unique_ptr<Film> capped_film;
    run_with_watchdog([&] { capped_film = render_case(scene, capped, &capped_stats); }, std::chrono::seconds(60),
                      "facing mirrors with a depth cap");
    EXPECT_EQ(capped_stats.rays, capped_stats.paths * 51u);
    int capped_nonzero = 0;
    for (int y = 0; y < rs.height; ++y)
        for (int x = 0; x < rs.width; ++x) capped_nonzero += capped_film->pixel_xyz(x, y).y != 0;
    EXPECT_EQ(capped_nonzero, 0);
    report(fmt("facing_mirrors: %d non-zero pixels (expected 0); %.3f rays per path (expected 22 ± %.2f); depth cap 50: "
               "%.1f rays per path",
               nonzero, mean_rays, sigma, double(capped_stats.rays) / double(capped_stats.paths)));
}

// ---------------------------------------------------------------------------------------
// Meshes (degenerate and sliver triangles).

TEST(HardCase, DegenerateTrianglesAreNeverHit) {
    const Scene scene = load_case("degenerate_mesh");
    const Scene clean = load_case("degenerate_mesh_clean");
    ASSERT_EQ(clean.triangles.size(), 105u);
    ASSERT_EQ(scene.triangles.size(), clean.triangles.size()) << "zero-area faces were kept";
    for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
        const Triangle &t = scene.triangles[i], &c = clean.triangles[i];
        EXPECT_FALSE(t.is_degenerate());
        for (int k = 0; k < 3; ++k) {
            const Vec3& p = k == 0 ? t.p0 : k == 1 ? t.p1 : t.p2;
            const Vec3& q = k == 0 ? c.p0 : k == 1 ? c.p1 : c.p2;
            EXPECT_TRUE(p.x == q.x && p.y == q.y && p.z == q.z) << "triangle " << i;
        }
    }
    const RenderSettings rs = case_settings(scene, 123);
    const auto film = render_case(scene, rs);
    const auto ref = render_case(clean, rs);
    expect_clean(*film, rs, "degenerate_mesh");
    EXPECT_TRUE(film->xyz_sums() == ref->xyz_sums()) << "the films differ";
    // The mesh is in view: the image differs from the wall alone.
    Scene wall = scene;
    wall.triangles.clear();
    wall.finalize();
    const auto wall_film = render_case(wall, rs);
    int differing = 0;
    for (int y = 0; y < rs.height; ++y)
        for (int x = 0; x < rs.width; ++x) differing += film->pixel_xyz(x, y).y != wall_film->pixel_xyz(x, y).y;
    EXPECT_GT(differing, 20);
    report(fmt("degenerate_mesh: %g triangles loaded (105 expected), film bit-identical to the clean mesh: %s; %d pixels "
               "show the mesh",
               double(scene.triangles.size()), film->xyz_sums() == ref->xyz_sums() ? "yes" : "no", differing));
}

// ---------------------------------------------------------------------------------------
// Thin glass shell (ROBUSTNESS 7.4).

/// Lambertian surface of albedo a under a flat dielectric layer of index n, in a uniform
/// environment 1: the surface's radiance inside the glass, L_d = a(1 − F̄e)/(1 − a·F̄i), with
/// F̄e the cosine-weighted mean external reflectance and F̄i = 1 − (1 − F̄e)/n² the internal one
/// (total internal reflection included).
double layered_inner_radiance(double a, double n) {
    const int steps = 200000;
    double fe = 0;
    for (int i = 0; i < steps; ++i) {
        const double mu = (i + 0.5) / steps;
        fe += fresnel(mu, n) * mu;
    }
    fe *= 2.0 / steps;
    const double fi = 1 - (1 - fe) / (n * n);
    return a * (1 - fe) / (1 - a * fi);
}

TEST(HardCase, ThinGlassShellAroundDiffuseSphere) {
    const Scene scene = load_case("thin_glass_shell");
    ASSERT_EQ(scene.spheres.size(), 2u);
    const int white = scene.spheres[0].material, glass = scene.spheres[1].material;
    const float r_shell = scene.spheres[1].radius;
    // Geometry: every ray refracted into the shell hits the inner sphere next.
    int refracted = 0, reached_inner = 0;
    Rng rng(7, 7, 7);
    for (int i = 0; i < 20000; ++i) {
        const float rad = 0.9999f * std::sqrt(rng.uniform()), phi = 2 * float(kPi) * rng.uniform();
        const Vec3 target(rad * std::cos(phi), rad * std::sin(phi), 0.f);
        const Vec3 o = scene.camera.position;
        const std::optional<Hit> hit = scene.intersect({o, normalize(target - o), kInfinity});
        ASSERT_TRUE(hit);
        ASSERT_EQ(hit->material, glass);
        const std::optional<Vec3> wt = refract(normalize(o - hit->p), hit->n, 1.5f);
        ASSERT_TRUE(wt);
        ++refracted;
        const std::optional<Hit> next = scene.intersect(spawn_ray(*hit, *wt));
        reached_inner += next && next->material == white && next->t < 1e-3f;
    }
    EXPECT_EQ(reached_inner, refracted);
    // Rendering: finite, and the sphere seen through the glass as a Lambertian under a flat
    // layer (the layer is 4e-5 thick on a radius of 1).
    const RenderSettings rs = case_settings(scene, 124);
    const auto film = render_case(scene, rs);
    expect_clean(*film, rs, "thin_glass_shell");
    const double n = 1.5, a = 0.5;
    const double Ld = layered_inner_radiance(a, n);
    auto radiance = [&](const Ray& ray) {
        const std::optional<double> t = hit_sphere(ray, {0, 0, 0}, r_shell);
        if (!t) return 1.0;
        const D3 p = d3(ray.o) + d3(ray.d) * *t;
        const double cos_i = -dot(unit(p), unit(d3(ray.d)));
        const double F = fresnel(cos_i, n);
        return F + (1 - F) * Ld / (n * n);
    };
    std::vector<int> kind(rs.width * rs.height);
    for (int y = 0; y < rs.height; ++y)
        for (int x = 0; x < rs.width; ++x)
            kind[y * rs.width + x] = pixel_coverage(scene, rs.width, rs.height, x, y, [&](const Ray& ray) {
                return hit_sphere(ray, {0, 0, 0}, 1.0).has_value();
            });
    // Loose bound against the sphere without its shell (exactly 0.5 on the sphere): visible,
    // neither black nor leaking the environment (1).
    Scene bare = scene;
    bare.spheres.pop_back();
    bare.finalize();
    const auto bare_film = render_case(bare, rs);
    double shell_sum = 0, bare_sum = 0;
    int on = 0;
    for (int y = 0; y < rs.height; ++y)
        for (int x = 0; x < rs.width; ++x)
            if (kind[y * rs.width + x] == 1) {
                ++on;
                shell_sum += film->pixel_xyz(x, y).y;
                bare_sum += bare_film->pixel_xyz(x, y).y;
            }
    ASSERT_GE(on, 40);
    const double ratio = shell_sum / bare_sum;
    EXPECT_GT(ratio, 0.4) << "the sphere inside the shell is (nearly) black";
    EXPECT_LT(ratio, 1.0) << "the shell does not darken the sphere (light leaks in)";
    // The flat-layer prediction, per pixel and summed over the sphere's pixels (each pixel's
    // noise is large: a path either escapes the layer or is absorbed).
    double sum_v = 0, sum_e = 0, sum_var = 0;
    const ZCheck z = max_z(*film, [&](int x, int y) -> std::optional<double> {
        if (kind[y * rs.width + x] == -1) return std::nullopt;
        const double e = pixel_average(scene, rs.width, rs.height, x, y, radiance);
        if (kind[y * rs.width + x] == 1) {
            sum_v += film->pixel_xyz(x, y).y, sum_e += e;
            sum_var += std::pow(film->pixel_y_standard_error(x, y), 2);
        }
        return e;
    });
    EXPECT_LE(z.max_z, kZ) << describe(z);
    const double sphere_mean = sum_v / on, sphere_expected = sum_e / on, sphere_se = std::sqrt(sum_var) / on;
    EXPECT_NEAR(sphere_mean, sphere_expected, kZ * sphere_se);
    EXPECT_LT(sphere_se, 0.01 * sphere_expected);
    const int cx = rs.width / 2, cy = rs.height / 2;
    const double v = film->pixel_xyz(cx, cy).y, se = film->pixel_y_standard_error(cx, cy);
    const double e = pixel_average(scene, rs.width, rs.height, cx, cy, radiance);
    report(fmt("thin_glass_shell: %d/%d refracted rays hit the inner sphere; sphere pixels %.4f of the bare sphere's; ",
               reached_inner, refracted, ratio) +
           fmt("pixel (8, 8) Y = %.5f ± %.2g vs flat layer %.5f (z = %.2f, L_d = %.5f); ", v, se, e, (v - e) / se, Ld) +
           describe(z) +
           fmt("; sphere pixels: mean Y = %.5f ± %.2g vs flat layer %.5f (z = %.2f)", sphere_mean, sphere_se,
               sphere_expected, (sphere_mean - sphere_expected) / sphere_se));
}

}  // namespace
}  // namespace spt

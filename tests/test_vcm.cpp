// Bidirectional path tracing with vertex merging (the vcm integrator, bdpt.h MergeContext,
// vertex_merging.h): pass wavelengths and radii, analytic furnaces, agreement with the path
// tracer and bdpt, the caustic seen in a mirror that only merging can render, determinism
// and robustness. (The photon grid and MergePass are in test_photon_grid.cpp.)
//
// Statistics. In vcm every pixel of a pass shares the pass's wavelengths and photons, so
// pixels are correlated within a pass. A pixel's σ is its measured standard error over the
// passes (one sample per pass: independent light subpaths, and wavelengths from a rotated
// golden-ratio sequence, which only makes that σ conservative). A mean over pixels takes its
// σ from the spread of the per-pass means (PassImages, from the film after every pass),
// never from the pixels' σ as if independent: in the furnace that naive σ is 2–4× too small.
// Checks are |difference| ≤ kZ = 5 σ. Each test prints one "[vcm]" line with its numbers.
//
// Planted bugs, each tried in the renderer and reverted (baseline in brackets):
//   - merge contribution × 1.5 (Bdpt::merge): furnace Y = 1 gives 1.238 (z = +40; [1.0000 ±
//     0.0018 at 1024 passes]), Y = 5 gives 5.668 (z = +24), mirror caustic 0.365 for 0.237
//     (z = +18); cornell-point only z = +2.0 (merging is a small share there at r = 0.02);
//   - merge terms dropped from other_strategies (connections and merges both weighted as if
//     alone): furnaces 1.96 and 7.22 (z = +46, +40), mirror caustic 0.0005 (z = −55);
//   - eta × 2 in MergePass::build: MergePassIndexesDiffuseSurfaceVertices, furnaces 0.689 and
//     4.005 (z = −94, −56), mirror caustic 0.122 (z = −25);
//   - Bdpt::camera_merge_sum always counting the reference connection (wrong when the camera
//     vertex before the merge is specular, as behind the mirror): mirror caustic 0.072
//     (z = −37); only that test sees it;
//   - the camera side of a merge's MIS sum dropped (camera_merge_sum without camera_sum):
//     furnaces 1.0246 and 5.439 (z = +18, +17), cornell-point z = +4.2;
//   - the light side dropped (make_photon's light sum = 0): furnaces 1.368 and 8.70 (z = +135,
//     +59), cornell-point z = +9.0;
//   - merges weighted with the merge point's density from the normal instead of the other
//     side's direction: test_bidirectional_materials.cpp (rough glass +32 %);
//   - the light phase's eta × 2 (renderer.cpp pass_eta, the splats' MIS weights): furnace
//     Y = 1 gives 0.9838 (z = −9.1 at 1024 passes; at 256 passes it was only −4.7);
//   - a merge's depth counted one lower in Bdpt::merge: MaxDepthCountsMergesLikeConnections
//     (z = +26 at depth 1);
//   - PhotonGrid without its shared-bucket check (double visits): the grid tests and the
//     furnace Y = 1 (z = +5.2 at 256 passes; a pixel at z = 12).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdarg>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>

#include "model/camera.h"
#include "render/vertex_merging.h"
#include "scene/builtin_scenes.h"
#include "scene/scene_loader.h"
#include "chi2.h"
#include "test_scenes.h"
#include "vcm_passes.h"

namespace spt {
namespace {

using test::closed_sphere_scene;
using test::compare;
using test::Comparison;
using test::constant_spectrum;
using test::describe;
using test::diffuse_material;
using test::glass_material;
using test::image_mean_y;
using test::ImageMean;
using test::max_pixel_z;
using test::mirror_material;
using test::PassImages;
using test::render_passes;
using test::render_film;
using test::small_settings;

RenderSettings with(IntegratorKind kind, int width, int height, int spp, std::uint64_t seed, float radius = 0.f) {
    RenderSettings rs = small_settings(width, height, spp, seed, 2);
    rs.integrator.kind = kind;
    rs.integrator.merge_radius = radius;
    return rs;
}

Scene builtin(const std::string& name) {
    std::optional<Scene> scene = load_builtin_scene(name, {});
    EXPECT_TRUE(scene.has_value()) << name;
    return std::move(*scene);
}


constexpr double kZ = 5.0;

void report(const char* format, ...) __attribute__((format(printf, 1, 2)));
void report(const char* format, ...) {
    va_list args;
    va_start(args, format);
    std::printf("[vcm] ");
    std::vprintf(format, args);
    std::printf("\n");
    va_end(args);
}

// ---- pass_wavelengths and merge_radius ----

TEST(VcmPass, WavelengthsAreDeterministicPerSeedAndPass) {
    for (std::uint64_t seed : {0ull, 1ull, 0xdeadbeefull})
        for (int pass : {0, 1, 17, 1000}) {
            const SampledWavelengths a = pass_wavelengths(seed, pass), b = pass_wavelengths(seed, pass);
            EXPECT_EQ(a.lambda, b.lambda);
            EXPECT_EQ(a.pdf, b.pdf);
        }
    // Different seeds rotate the sequence: pass 0 differs between seeds, and so does every pass.
    int same = 0;
    for (int pass = 0; pass < 100; ++pass) same += pass_wavelengths(1, pass).lambda == pass_wavelengths(2, pass).lambda;
    EXPECT_EQ(same, 0);
    EXPECT_NE(pass_wavelengths(1, 0).lambda[0], pass_wavelengths(2, 0).lambda[0]);
    // Consecutive passes differ.
    EXPECT_NE(pass_wavelengths(1, 0).lambda[0], pass_wavelengths(1, 1).lambda[0]);
}

/// Index of the u-bin of a hero wavelength: the hero is sample_visible_wavelength(u), which
/// increases with u, so the bin edges are the images of k/bins.
int hero_bin(float lambda, const std::vector<float>& edges) {
    return static_cast<int>(std::upper_bound(edges.begin(), edges.end(), lambda) - edges.begin()) - 1;
}

/// The hero's u must be uniform: over the passes of one seed (the golden-ratio sequence) and,
/// for a fixed pass, over seeds (the seed's offset: this is what makes each pass unbiased).
TEST(VcmPass, HeroIsUniformOverPassesAndOverSeeds) {
    constexpr int kBins = 50, kPerBin = 100, kN = kBins * kPerBin;
    std::vector<float> edges(kBins + 1);
    for (int k = 0; k <= kBins; ++k) edges[k] = k == kBins ? 1e9f : sample_visible_wavelength(float(k) / kBins);
    edges[0] = 0.f;
    for (int mode = 0; mode < 2; ++mode)
        for (int which : {0, 5}) {
            std::vector<double> observed(kBins, 0.0), expected(kBins, double(kPerBin));
            for (int i = 0; i < kN; ++i) {
                const SampledWavelengths w =
                    mode == 0 ? pass_wavelengths(std::uint64_t(which) + 3, i) : pass_wavelengths(std::uint64_t(i), which);
                const int b = hero_bin(w.lambda[0], edges);
                ASSERT_GE(b, 0);
                ASSERT_LT(b, kBins);
                observed[b] += 1;
            }
            const spt_test::Chi2Result r = spt_test::chi2_test(observed, expected);
            report("hero uniformity (%s %d): X² = %.1f, dof %d, p = %.3g", mode == 0 ? "passes of seed" : "seeds at pass",
                   mode == 0 ? which + 3 : which, r.statistic, r.dof, r.p_value);
            EXPECT_GT(r.p_value, 1e-4) << (mode == 0 ? "over passes" : "over seeds");
        }
}

TEST(VcmPass, MergeRadiusShrinksAsPassToMinusOneEighth) {
    EXPECT_EQ(merge_radius(0.4f, 0), 0.4f);
    EXPECT_FLOAT_EQ(merge_radius(0.4f, 255), 0.2f);  // 256^(−1/8) = 1/2
    EXPECT_FLOAT_EQ(merge_radius(1.f, 65535), 0.25f);
    for (int k : {1, 2, 9, 99, 12345})
        EXPECT_NEAR(merge_radius(0.03f, k), 0.03 * std::pow(k + 1.0, -0.125), 1e-6 * 0.03) << k;
}

/// Median over a 16×16 grid of camera hits of the photons within `radius` for one light pass
/// of `paths` subpaths (own Rng stream, not the pilot's).
float median_photons(const Scene& scene, const RenderSettings& rs, int paths, float radius) {
    const Camera camera(scene.camera, rs.width, rs.height);
    const LightSampler lights(scene);
    const BdptContext ctx{scene, camera, lights, rs.integrator, rs.width};
    const SampledWavelengths lambda = pass_wavelengths(rs.seed, 0);
    std::vector<LightSubpathBatch> batches(1);
    PathStats stats;
    for (int i = 0; i < paths; ++i) {
        Rng rng(77, static_cast<std::uint64_t>(i), 3);
        trace_light_subpath(ctx, lambda, 0.f, rng, stats, batches[0].vertices, batches[0].splats);
        batches[0].ends.push_back(static_cast<std::uint32_t>(batches[0].vertices.size()));
    }
    MergePass pass;
    pass.build(batches, scene, radius, 0.f);
    std::vector<float> counts;
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 16; ++i)
            if (const auto hit = scene.intersect(camera.generate_ray((i + 0.5f) * rs.width / 16.f,
                                                                     (j + 0.5f) * rs.height / 16.f))) {
                int n = 0;
                pass.grid().query(hit->p, [&](std::uint32_t, float) { ++n; });
                counts.push_back(static_cast<float>(n));
            }
    std::nth_element(counts.begin(), counts.begin() + static_cast<std::ptrdiff_t>(counts.size() / 2), counts.end());
    return counts[counts.size() / 2];
}

/// The default radius (vertex_merging.h): five pixel footprints, at most 1 % of the scene's
/// bounding radius, and shrunk where photons are dense so that a merge expects about 16.
///   - glass-spheres at 512² and 1024² (sparse photons, footprints below the cap): the radius
///     halves when the resolution doubles;
///   - cornell-point at 1024² (a closed box, dense photons; footprints below the cap): a pass
///     of N = 1024² subpaths would put a median of ~16 photons in the radius. Checked with
///     N/16 subpaths of another stream in a disk of 4× the radius (same expected count):
///     measured 19, allowed 8–32 (the pilot's noise, a density not uniform over the disk);
///     twice that disk holds far more (the density rule, not the footprint, set the radius);
///   - at 16×16 five footprints would be 40 % of the box: the 1 % cap holds.
TEST(VcmPass, DefaultRadiusFollowsFootprintsPhotonDensityAndCap) {
    auto radius_of = [](const Scene& scene, int size) {
        RenderSettings rs = small_settings(size, size, 1, 5);
        const Camera camera(scene.camera, rs.width, rs.height);
        const LightSampler lights(scene);
        return std::pair{default_merge_radius({scene, camera, lights, rs.integrator, rs.width}, rs),
                         lights.scene_radius()};
    };
    const Scene spheres = builtin("glass-spheres");
    const float r512 = radius_of(spheres, 512).first, r1024 = radius_of(spheres, 1024).first;
    report("radius glass-spheres: %g at 512², %g at 1024²", r512, r1024);
    EXPECT_NEAR(r1024, 0.5f * r512, 0.02f * r512);

    const Scene box = builtin("cornell-point");
    const auto [r_box, box_radius] = radius_of(box, 1024);
    const RenderSettings rs = small_settings(1024, 1024, 1, 5);
    const float median = median_photons(box, rs, 65536, 4.f * r_box);
    const float median_twice = median_photons(box, rs, 65536, 8.f * r_box);
    report("radius cornell-point 1024²: %g (cap %g); median photons per merge %g (%g in twice the radius)", r_box,
           0.01f * box_radius, median, median_twice);
    EXPECT_LT(r_box, 0.01f * box_radius);
    EXPECT_GE(median, 8.f);
    EXPECT_LE(median, 32.f);
    EXPECT_GT(median_twice, 32.f);

    const auto [r16, cap_radius] = radius_of(box, 16);
    EXPECT_LE(r16, 0.01f * cap_radius * (1 + 1e-6f));
    EXPECT_GE(r16, 0.005f * cap_radius) << "capped, not shrunk further by the pilot";
}

// ---- Furnaces ----
//
// Closed Lambertian sphere: radiance is uniform and known. On a sphere the area inside a ball
// of radius r centred on the surface is exactly π r² (Archimedes), so merging's density
// estimate has no blur bias here, for any r below the sphere's diameter; r = 0.3 makes
// merging a large share of the MIS (eta = π r² × 144 paths ≈ 41). Statistics: each pixel's σ
// is its measured standard error over the passes; the image mean's σ is the spread of the
// per-pass image means (pixels of one pass share wavelengths and photons), measured
// 0.0018 (Y = 1, 1024 passes: enough to see the light phase's eta) and 0.022 (Y = 5, 256
// passes); measured 1.00000 ± 0.0018 and 4.990 ± 0.022, worst pixels z = 2.7 and 3.4.

void expect_furnace(const Scene& scene, double exact, std::uint64_t seed, int passes, double max_sigma) {
    const PassImages p = render_passes(scene, with(IntegratorKind::vcm, 12, 12, passes, seed, 0.3f));
    EXPECT_EQ(p.film->rejected_samples(), 0u);
    const ImageMean m = p.region([](int, int) { return true; });
    const auto z = max_pixel_z(*p.film, exact);
    report("furnace %.0f: mean %.5f ± %.5f (z = %.2f), %s", exact, m.mean, m.standard_error,
           (m.mean - exact) / m.standard_error, describe(z).c_str());
    EXPECT_NEAR(m.mean, exact, kZ * m.standard_error);
    EXPECT_LT(m.standard_error, max_sigma);
    EXPECT_LE(z.max_z, kZ) << describe(z);
}

TEST(Vcm, FurnacePointLightAtCentreGivesOne) {
    Scene scene = closed_sphere_scene(diffuse_material(0.5));
    scene.add_point_light({0, 0, 0}, constant_spectrum(std::numbers::pi));
    scene.finalize();
    expect_furnace(scene, 1.0, 11, 1024, 0.003);
}

TEST(Vcm, FurnaceEmissiveAlbedo08GivesFive) {
    Scene scene = closed_sphere_scene(diffuse_material(0.8), 1.0);
    scene.finalize();
    expect_furnace(scene, 5.0, 13, 256, 0.04);
}

// ---- Agreement with the other integrators ----

/// cornell: the only emitter is the infinite ceiling, which light subpaths cannot start on,
/// so vcm has no photons and no light subpaths; its camera subpaths (with the pass's shared
/// wavelengths) must still agree with the path tracer pixel by pixel.
TEST(Vcm, AgreesWithPathTracerOnCornell) {
    const Scene scene = builtin("cornell");
    const auto path = render_film(scene, small_settings(24, 24, 128, 3));
    const PassImages vcm = render_passes(scene, with(IntegratorKind::vcm, 24, 24, 128, 4));
    EXPECT_EQ(vcm.film->rejected_samples(), 0u);
    const Comparison c = compare(*path, *vcm.film, [](int, int) { return true; });
    const ImageMean a = image_mean_y(*path), b = vcm.region([](int, int) { return true; });
    report("cornell vs path: %s; vcm mean %.4f ± %.4f (passes)", describe(c).c_str(), b.mean, b.standard_error);
    EXPECT_LE(c.max_z, kZ) << describe(c);
    EXPECT_NEAR(a.mean, b.mean, kZ * std::hypot(a.standard_error, b.standard_error));
}

/// cornell-point: bdpt renders the glass sphere's caustic by light tracing and connections,
/// vcm also by merging. r = 0.02 is about a third of a pixel's footprint on the floor at
/// 24×24 (≈ 0.06), so the blur of the caustic's edge is well inside a pixel; measured max
/// |z| = 3.5 over the 576 pixels, image means 0.5202 (bdpt) vs 0.5230 ± 0.0029 (z = 0.96).
TEST(Vcm, AgreesWithBdptOnCornellPoint) {
    const Scene scene = builtin("cornell-point");
    const auto bdpt = render_film(scene, with(IntegratorKind::bdpt, 24, 24, 128, 3));
    const PassImages vcm = render_passes(scene, with(IntegratorKind::vcm, 24, 24, 128, 4, 0.02f));
    EXPECT_EQ(vcm.film->rejected_samples(), 0u);
    EXPECT_EQ(bdpt->rejected_samples(), 0u);
    const Comparison c = compare(*bdpt, *vcm.film, [](int, int) { return true; });
    const ImageMean a = image_mean_y(*bdpt), b = vcm.region([](int, int) { return true; });
    const double sigma = std::hypot(a.standard_error, b.standard_error);
    report("cornell-point vs bdpt: %s; means %.4f vs %.4f ± %.4f (z = %.2f)", describe(c).c_str(), a.mean, b.mean,
           sigma, (b.mean - a.mean) / sigma);
    EXPECT_LE(c.max_z, kZ) << describe(c);
    EXPECT_NEAR(a.mean, b.mean, kZ * sigma);
}
// Mirror scene.
constexpr float kMirrorX = 0.f;
const Vec3 kGlassCentre(1.5f, 0.5f, 0.f), kLight(1.7f, 1.4f, 0.f);
constexpr float kGlassRadius = 0.3f;
constexpr float kCausticX = 1.389f;

Scene mirror_scene(bool unfolded) {
    Scene s;
    const int floor = s.add_material(diffuse_material(0.5));
    const int glass = s.add_material(glass_material(1.5));
    s.planes.push_back({{0, 1, 0}, 0.f, floor});
    s.spheres.push_back({kGlassCentre, kGlassRadius, glass});
    s.add_point_light(kLight, constant_spectrum(1.0));
    if (unfolded) {
        s.spheres.push_back({{-kGlassCentre.x, kGlassCentre.y, kGlassCentre.z}, kGlassRadius, glass});
        s.add_point_light({-kLight.x, kLight.y, kLight.z}, constant_spectrum(1.0));
    } else {
        const int mirror = s.add_material(mirror_material(1.0));
        s.planes.push_back({{1, 0, 0}, kMirrorX, mirror});
    }
    s.camera = {{3.2f, 2.2f, 0.f}, {-kCausticX, 0.f, 0.f}, {0, 1, 0}, 4.f};
    s.finalize();
    return s;
}


/// Pixels whose 9×9 grid of rays (edges included) all land on the floor of the unfolded scene
/// within `radius` of the virtual caustic's centre (−kCausticX, 0, 0), none on a sphere.
std::vector<char> floor_region(const Scene& unfolded, int width, int height, float radius) {
    const Camera camera(unfolded.camera, width, height);
    std::vector<char> in(std::size_t(width) * height, 0);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            bool all = true;
            for (int j = 0; j <= 8 && all; ++j)
                for (int i = 0; i <= 8 && all; ++i) {
                    const std::optional<Hit> hit = unfolded.intersect(
                        camera.generate_ray(x + std::min(i / 8.f, 0.9999f), y + std::min(j / 8.f, 0.9999f)));
                    all = hit && hit->n.y > 0.99f && std::fabs(hit->p.y) < 1e-4f &&
                          std::hypot(hit->p.x + kCausticX, hit->p.z) < radius;
                }
            in[std::size_t(y) * width + x] = all;
        }
    return in;
}

/// The caustic only vertex merging can render: a point light above a glass ball focuses light
/// on a diffuse floor, and the camera sees that floor only in a perfect mirror (the plane
/// x = 0): the path light → glass → glass → floor → mirror → camera has a diffuse vertex
/// between specular ones and a point light, so no connection strategy samples it (bdpt gives
/// 0 there) and merging at the floor vertex is its only estimator.
///
/// Reference: by the method of images, a mirror of reflectance 1 at x = 0 makes the radiance
/// in x > 0 that of the unfolded scene (everything mirrored to x < 0 added, mirror removed),
/// so the camera, unchanged, must see in the unfolded scene exactly the same image, pixel for
/// pixel: there the caustic (of the mirrored light through the mirrored ball) is seen directly,
/// which bdpt renders by light tracing. Compared over the pixels that see the floor within
/// 0.3 of the caustic's centre (the caustic is ~0.15 across, inside the ball's shadow):
/// merging blurs by r = 0.02 but conserves the flux, and the region's edge lies in the flat
/// shadow, so the region mean is unbiased to well below its σ. Measured: 670 pixels, vcm
/// 0.2435 ± 0.0036 vs 0.2374 ± 0.0043 (z = 1.1); core 1.175 ± 0.018 vs 1.144 ± 0.022
/// (z = 1.1); bdpt through the mirror 0.0005. Per-pixel z is not used: in the shadow both
/// estimators' pixels are dominated by rare paths (skewed; a pixel that missed them has a
/// small σ too).
TEST(Vcm, RendersCausticSeenInAMirror) {
    constexpr int kSize = 32;
    const Scene mirrored = mirror_scene(false), unfolded = mirror_scene(true);
    const std::vector<char> region = floor_region(unfolded, kSize, kSize, 0.3f);
    auto in = [&](int x, int y) { return region[std::size_t(y) * kSize + x] != 0; };
    const auto reference = render_film(unfolded, with(IntegratorKind::bdpt, kSize, kSize, 256, 3));
    const auto bdpt = render_film(mirrored, with(IntegratorKind::bdpt, kSize, kSize, 16, 5));
    const PassImages vcm = render_passes(mirrored, with(IntegratorKind::vcm, kSize, kSize, 256, 4, 0.02f));
    EXPECT_EQ(vcm.film->rejected_samples(), 0u);

    const ImageMean ref = test::region_mean_y(*reference, in), lost = test::region_mean_y(*bdpt, in);
    const ImageMean got = vcm.region(in);
    const double sigma = std::hypot(ref.standard_error, got.standard_error);
    int pixels = 0;
    for (char c : region) pixels += c;
    report("mirror caustic over %d pixels: vcm %.4f ± %.4f, direct view (bdpt) %.4f ± %.4f: z = %.2f; bdpt through "
           "the mirror %.4f", pixels, got.mean, got.standard_error, ref.mean, ref.standard_error,
           (got.mean - ref.mean) / sigma, lost.mean);
    EXPECT_GT(pixels, 100);
    EXPECT_NEAR(got.mean, ref.mean, kZ * sigma);
    EXPECT_LT(got.standard_error, 0.03 * got.mean);
    // Without merging the caustic is missing: bdpt through the mirror sees only the shadow.
    EXPECT_LT(lost.mean, 0.2 * ref.mean);

    // The caustic itself (within 0.12 of its centre: its bright core and edge) agrees too.
    const std::vector<char> core = floor_region(unfolded, kSize, kSize, 0.12f);
    auto in_core = [&](int x, int y) { return core[std::size_t(y) * kSize + x] != 0; };
    const ImageMean ref_core = test::region_mean_y(*reference, in_core), got_core = vcm.region(in_core);
    const double sigma_core = std::hypot(ref_core.standard_error, got_core.standard_error);
    report("mirror caustic core: vcm %.4f ± %.4f, direct view %.4f ± %.4f: z = %.2f", got_core.mean,
           got_core.standard_error, ref_core.mean, ref_core.standard_error, (got_core.mean - ref_core.mean) / sigma_core);
    EXPECT_NEAR(got_core.mean, ref_core.mean, kZ * sigma_core);
    EXPECT_GT(ref_core.mean, 1.0);
}

// ---- Determinism and robustness ----

/// The light phase is split into tasks of 4096 subpaths and the camera phase into tiles; the
/// photons are gathered and the splats merged in task order: 1, 2 and 7 threads give
/// bit-identical films. 72×64 = 4608 light subpaths per pass: two light tasks.
TEST(Vcm, DeterministicForAnyThreadCount) {
    const Scene scene = builtin("cornell-point");
    RenderSettings rs = with(IntegratorKind::vcm, 72, 64, 2, 9, 0.05f);
    rs.threads = 1;
    rs.tile = {8, 8};
    const auto one = render_film(scene, rs);
    ASSERT_TRUE(one->has_splats());
    for (int threads : {2, 7}) {
        rs.threads = threads;
        const auto many = render_film(scene, rs);
        EXPECT_EQ(one->save_state(), many->save_state()) << threads << " threads";
    }
}

/// Resuming (RenderSettings::first_sample) continues the pass sequence: pass k keeps its
/// radius r0·(k + 1)^(−1/8), its wavelengths and its light subpaths' random numbers, so
/// 2 + 3 passes into one film equal 5 passes straight, bit for bit.
TEST(Vcm, ResumedRenderEqualsStraightRun) {
    const Scene scene = builtin("cornell-point");
    RenderSettings rs = with(IntegratorKind::vcm, 20, 16, 5, 31, 0.1f);
    const auto straight = render_film(scene, rs);
    Film resumed(rs.width, rs.height);
    rs.spp = 2;
    render(scene, rs, resumed);
    rs.spp = 5;
    rs.first_sample = 2;
    render(scene, rs, resumed);
    EXPECT_EQ(straight->save_state(), resumed.save_state());
}

/// max_depth counts a merge (s, t) as the connection (s, t − 1) it replaces: in the furnace
/// with the point light, depth 1 is exactly single scattering (Y = 0.5) and depth 2 adds the
/// second bounce (0.75). Merging at r = 0.3 is a large share of both (see the furnaces), so a
/// merge allowed one bounce too many moves the mean by tens of σ. Measured 0.5021 ± 0.0022
/// and 0.7518 ± 0.0024 (σ from the per-pass means, 512 passes); with the merge's depth
/// counted one lower (planted: s + t − 4), 0.5580 and 0.7897 (z = +26, +16).
TEST(Vcm, MaxDepthCountsMergesLikeConnections) {
    Scene scene = closed_sphere_scene(diffuse_material(0.5));
    scene.add_point_light({0, 0, 0}, constant_spectrum(std::numbers::pi));
    scene.finalize();
    for (const auto& [depth, exact] : {std::pair{1, 0.5}, std::pair{2, 0.75}}) {
        RenderSettings rs = with(IntegratorKind::vcm, 12, 12, 512, 41, 0.3f);
        rs.integrator.max_depth = depth;
        const PassImages p = render_passes(scene, rs);
        const ImageMean m = p.region([](int, int) { return true; });
        report("furnace depth %d: %.5f ± %.5f for %.2f (z = %.2f)", depth, m.mean, m.standard_error, exact,
               (m.mean - exact) / m.standard_error);
        EXPECT_NEAR(m.mean, exact, kZ * m.standard_error) << "max_depth " << depth;
        EXPECT_LT(m.standard_error, 0.01 * exact);
    }
}

/// No sample or splat is ever rejected (NaN, Inf or negative) and every pixel is finite and
/// ≥ 0: built-in scenes at the default radius and at a tiny one, and hard cases (dispersive
/// glass, light inside glass, lights on and just above a plane, facing mirrors, thin glass).
TEST(Vcm, NoRejectedSamplesOnBuiltinsAndHardCases) {
    auto check = [](const Scene& scene, const std::string& what, int w, int h, int spp, float radius) {
        const auto film = render_film(scene, with(IntegratorKind::vcm, w, h, spp, 21, radius));
        EXPECT_EQ(film->rejected_samples(), 0u) << what;
        EXPECT_EQ(test::count_bad_pixels(*film), 0) << what;
    };
    for (const char* name : {"cornell", "cornell-point"}) {
        check(builtin(name), name, 16, 16, 8, 0.f);
        check(builtin(name), std::string(name) + " r = 1e-4", 16, 16, 8, 1e-4f);
    }
    for (const char* name : {"glass_furnace_bk7", "light_inside_glass", "point_light_on_plane",
                             "point_light_1e-6_above_plane", "facing_mirrors", "thin_glass_shell",
                             "cornell_point_scale_1e-4", "cornell_point_scale_1e4"})
        check(test::load_hard_case(name), name, 12, 12, 8, 0.f);
}
}  // namespace
}  // namespace spt

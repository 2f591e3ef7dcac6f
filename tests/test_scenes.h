// Small helpers for render-level tests: analytic test scenes (closed-sphere furnaces, a lit
// plane, glass spheres in an environment) and statistics over a film (per-pixel z-scores,
// image means with their standard error).
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "model/material.h"
#include "render/film.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "scene/scene_loader.h"

namespace spt::test {

/// A scene from JSON text with exact spectra, as if read from the file `name`.json.
inline Scene load_exact_scene(const std::string& text, const std::string& name) {
    return load_scene_text(text, name + ".json", name, SpectralResolution{SpectralResolution::kExact}, {});
}
/// The loader's message for the scene text, or "(no error)".
inline std::string scene_error(const std::string& text, const std::string& name) {
    try {
        load_exact_scene(text, name);
    } catch (const LocatedError& e) {
        return e.what();
    }
    return "(no error)";
}

inline Spectrum constant_spectrum(double value, SpectralResolution res = {}) {
    return Spectrum(SpectrumSource::constant(value), res);
}

/// Lambertian material with reflectance `albedo`. Emission is not a material property: an
/// emitting shape carries an emitter (add_constant_emitter).
inline Material diffuse_material(double albedo) {
    Material m;
    m.name = "diffuse";
    m.bsdf = DiffuseBsdf{constant_spectrum(albedo)};
    m.flags = bsdf_flags(m.bsdf);
    return m;
}

/// A material with no lobe at all (reflects nothing): the surface of a pure emitter.
inline Material black_material() {
    Material m;
    m.name = "black";
    m.bsdf = DiffuseBsdf{};
    m.flags = bsdf_flags(m.bsdf);
    return m;
}

/// Adds an emitter of constant radiance `radiance` (both sides) for a shape of the given kind
/// and returns the index to store in that shape's `light` (a quad's or a mesh's triangles
/// share it). A zero radiance adds nothing and returns −1 (no emitter), as the loader does.
inline int add_constant_emitter(Scene& scene, ShapeKind kind, double radiance) {
    if (radiance == 0.0) return -1;
    return scene.add_emitter(kind, constant_spectrum(radiance));
}

/// The diffuse reflectance of a material of either kind (a loaded kd/ks/kt material with only
/// kd becomes a DiffuseBsdf, any other a LobeMixBsdf).
inline const Spectrum& kd_of(const Material& m) {
    if (const DiffuseBsdf* d = std::get_if<DiffuseBsdf>(&m.bsdf)) return d->kd;
    return std::get<LobeMixBsdf>(m.bsdf).kd;
}

inline Material mirror_material(double ks = 1.0) {
    Material m;
    m.name = "mirror";
    LobeMixBsdf b;
    b.ks = constant_spectrum(ks);
    m.bsdf = std::move(b);
    m.flags = bsdf_flags(m.bsdf);
    return m;
}

/// Clear glass (kt = 1) with a constant index of refraction.
inline Material glass_material(double eta) {
    Material m;
    m.name = "glass";
    LobeMixBsdf b;
    b.kt = constant_spectrum(1.0);
    b.eta = constant_spectrum(eta);
    m.bsdf = std::move(b);
    m.flags = bsdf_flags(m.bsdf);
    return m;
}

/// Path of a scene file in tests/hard_cases/, and the scene loaded from it (default bins).
inline std::string hard_case_path(const std::string& name) {
    return std::string(SPT_TEST_DIR) + "/hard_cases/" + name + ".json";
}
inline Scene load_hard_case(const std::string& name) {
    return load_scene_file(hard_case_path(name), SpectralResolution{});
}

/// The scene without shapes and lights: its pixels see the bare environment (radiance =
/// background).
inline Scene environment_only(Scene scene) {
    const Spectrum background =
        scene.infinite_light_indices.empty()
            ? Spectrum()
            : std::get<EnvironmentLight>(scene.lights[static_cast<std::size_t>(scene.infinite_light_indices[0])]).Le;
    scene.spheres.clear();
    scene.planes.clear();
    scene.triangles.clear();
    scene.lights.clear();  // point lights and the shapes' emitters
    scene.set_background(background);
    scene.finalize();
    return scene;
}

/// The kd/ks/kt parameters of a material as a lobe mix (a diffuse material is the mix with
/// only kd), for tests that check each lobe.
inline LobeMixBsdf lobes_of(const Material& m) {
    if (const DiffuseBsdf* d = std::get_if<DiffuseBsdf>(&m.bsdf))
        return LobeMixBsdf{d->kd, constant_spectrum(0.0), constant_spectrum(0.0), constant_spectrum(1.5)};
    return std::get<LobeMixBsdf>(m.bsdf);
}

/// Samples the material's BSDF for radiance (camera paths), as the path tracer does.
inline std::optional<BsdfSample> sample_radiance(const Material& m, const Vec3& wo, const Vec3& n,
                                                 SampledWavelengths& lambda, float u_lobe, float u1, float u2) {
    return bsdf_sample(m.bsdf, wo, n, lambda, u_lobe, u1, u2, TransportMode::radiance);
}

/// Schott BK7 (Sellmeier coefficients of ROBUSTNESS.md §4): a dispersive glass.
inline Material bk7_material(SpectralResolution res = {}) {
    Material m;
    m.name = "bk7";
    LobeMixBsdf b;
    b.kt = constant_spectrum(1.0);
    b.eta = Spectrum(SpectrumSource::sellmeier(1.03961212, 0.231792344, 1.01046945, 0.00600069867,
                                               0.0200179144, 103.560653),
                     res);
    m.bsdf = std::move(b);
    m.flags = bsdf_flags(m.bsdf);
    return m;
}

/// Camera inside a closed unit sphere at the origin whose inner surface is `material`,
/// emitting the constant radiance `emission` from both sides (0: no emitter); the camera sits
/// off-centre so that rays do not all meet the wall at normal incidence.
inline Scene closed_sphere_scene(Material material, double emission = 0.0) {
    Scene scene;
    scene.name = "closed sphere";
    scene.camera = {{0.3f, -0.2f, 0.1f}, {-0.2f, 0.1f, -1.f}, {0, 1, 0}, 70.f};
    const int m = scene.add_material(std::move(material));
    Sphere wall{{0, 0, 0}, 1.f, m};
    wall.light = add_constant_emitter(scene, ShapeKind::sphere, emission);
    scene.spheres.push_back(wall);
    return scene;
}

/// Diffuse plane y = height (normal +y) with albedo `albedo`, and a point light of constant
/// intensity at (0, height + h, 0). The camera looks straight down at (x, height, z) from
/// `camera_height` above the plane with a tiny field of view, so each pixel's footprint is
/// a point for all practical purposes (footprint ~ 2·camera_height·tan(vfov/2)).
inline Scene lit_plane_scene(double albedo, double intensity, float h, float x, float z,
                             float height = 0.f, float camera_height = 1.f,
                             float vfov_degrees = 1e-4f) {
    Scene scene;
    scene.name = "lit plane";
    const int m = scene.add_material(diffuse_material(albedo));
    scene.planes.push_back({{0, 1, 0}, height, m});
    scene.add_point_light({0, height + h, 0}, constant_spectrum(intensity));
    scene.camera = {{x, height + camera_height, z}, {x, height, z}, {0, 0, -1}, vfov_degrees};
    return scene;
}

/// Irradiance-based radiance of a Lambertian plane lit by a point light at height h, at
/// horizontal distance rho from the light's foot: (a/π)·I·cosθ/r² = (a/π)·I·h/(h²+ρ²)^{3/2}.
inline double lit_plane_radiance(double albedo, double intensity, double h, double rho) {
    return albedo / std::numbers::pi * intensity * h / std::pow(h * h + rho * rho, 1.5);
}

inline RenderSettings small_settings(int width, int height, int spp, std::uint64_t seed = 1,
                                     int threads = 2) {
    RenderSettings s;
    s.width = width;
    s.height = height;
    s.spp = spp;
    s.seed = seed;
    s.threads = threads;
    return s;
}

/// Renders into a new film (Film holds atomics, so it lives behind a pointer).
inline std::unique_ptr<Film> render_film(const Scene& scene, const RenderSettings& settings,
                                         RenderStats* stats = nullptr) {
    auto film = std::make_unique<Film>(settings.width, settings.height);
    const RenderStats st = render(scene, settings, *film);
    if (stats) *stats = st;
    return film;
}

/// Bit-exact equality of the XYZ sums (memcmp, so −0 vs +0 and NaN payloads count) and of the
/// per-pixel sample counts. Returns the number of differing doubles.
inline std::size_t count_differences(const Film& a, const Film& b) {
    const std::vector<double>& x = a.xyz_sums();
    const std::vector<double>& y = b.xyz_sums();
    if (x.size() != y.size()) return std::max(x.size(), y.size());
    std::size_t diff = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
        if (std::memcmp(&x[i], &y[i], sizeof(double)) != 0) ++diff;
    for (int py = 0; py < a.height(); ++py)
        for (int px = 0; px < a.width(); ++px)
            if (a.sample_count(px, py) != b.sample_count(px, py)) ++diff;
    return diff;
}

/// Mean Y over all pixels and its standard error (pixels are independent: errors add in
/// quadrature).
struct ImageMean {
    double mean = 0, standard_error = 0;
};
/// Mean Y over the pixels where include(x, y) holds and its standard error, the pixels taken
/// as independent (true for path tracing and bdpt, whose samples draw their own wavelengths;
/// not within a vcm pass).
template <typename Mask>
ImageMean region_mean_y(const Film& film, Mask include) {
    double sum = 0, var = 0;
    int n = 0;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x)
            if (include(x, y)) {
                sum += film.pixel_xyz(x, y).y;
                var += std::pow(film.pixel_y_standard_error(x, y), 2);
                ++n;
            }
    return {sum / n, std::sqrt(var) / n};
}
inline ImageMean image_mean_y(const Film& film) {
    return region_mean_y(film, [](int, int) { return true; });
}

/// Largest |Y − expected|/σ over the pixels (σ the pixel's measured standard error). A pixel
/// with σ = 0 must match exactly (relative 1e-6), else it counts as infinitely far.
struct ZReport {
    double max_z = 0;
    int worst_x = -1, worst_y = -1;
    double worst_value = 0, worst_sigma = 0;
};
inline ZReport max_pixel_z(const Film& film, double expected) {
    ZReport r;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const double v = film.pixel_xyz(x, y).y;
            const double se = film.pixel_y_standard_error(x, y);
            double z;
            if (se > 0) z = std::fabs(v - expected) / se;
            else z = std::fabs(v - expected) <= 1e-6 * std::fabs(expected) ? 0.0 : std::numeric_limits<double>::infinity();
            if (!(z <= r.max_z)) r = {z, x, y, v, se};
        }
    return r;
}

inline std::string describe(const ZReport& r) {
    return "worst pixel (" + std::to_string(r.worst_x) + ", " + std::to_string(r.worst_y) +
           "): Y = " + std::to_string(r.worst_value) + " ± " + std::to_string(r.worst_sigma) +
           ", z = " + std::to_string(r.max_z);
}

/// Every pixel finite and ≥ 0 in X, Y and Z; returns the number of offending pixels.
inline int count_bad_pixels(const Film& film) {
    int bad = 0;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const Xyz c = film.pixel_xyz(x, y);
            for (double v : {c.x, c.y, c.z})
                if (!std::isfinite(v) || v < 0) {
                    ++bad;
                    break;
                }
        }
    return bad;
}

/// Per-pixel comparison of two independent renders: z = |a − b|/√(σa² + σb²).
struct Comparison {
    double max_z = 0;
    int worst_x = -1, worst_y = -1;
    double mean_a = 0, mean_b = 0, se = 0;  ///< over the compared pixels
    int pixels = 0;
};
template <typename Mask>
inline Comparison compare(const Film& a, const Film& b, Mask include) {
    Comparison c;
    double var = 0;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            if (!include(x, y)) continue;
            const double va = a.pixel_xyz(x, y).y, vb = b.pixel_xyz(x, y).y;
            const double sa = a.pixel_y_standard_error(x, y), sb = b.pixel_y_standard_error(x, y);
            const double s2 = sa * sa + sb * sb;
            const double z = s2 > 0 ? std::fabs(va - vb) / std::sqrt(s2) : (va == vb ? 0.0 : 1e30);
            if (z > c.max_z) c.max_z = z, c.worst_x = x, c.worst_y = y;
            c.mean_a += va, c.mean_b += vb, var += s2;
            ++c.pixels;
        }
    c.mean_a /= c.pixels, c.mean_b /= c.pixels, c.se = std::sqrt(var) / c.pixels;
    return c;
}
inline std::string describe(const Comparison& c) {
    return "worst pixel (" + std::to_string(c.worst_x) + ", " + std::to_string(c.worst_y) +
           ") z = " + std::to_string(c.max_z) + "; means " + std::to_string(c.mean_a) + " vs " +
           std::to_string(c.mean_b) + " ± " + std::to_string(c.se) + " over " + std::to_string(c.pixels) + " pixels";
}

/// bdpt against the path tracer on `scene`, independent seeds (path at twice bdpt's spp):
/// every pixel within 5σ and the image means within 5 standard errors. Returns the path film
/// (for further comparisons).
inline std::unique_ptr<Film> expect_bdpt_matches_path(const Scene& scene, std::uint64_t seed) {
    auto path = render_film(scene, small_settings(24, 24, 1024, seed));
    RenderSettings rs = small_settings(24, 24, 512, seed + 1);
    rs.integrator.kind = IntegratorKind::bdpt;
    const auto bdpt = render_film(scene, rs);
    EXPECT_EQ(bdpt->rejected_samples(), 0u);
    const Comparison c = compare(*path, *bdpt, [](int, int) { return true; });
    EXPECT_LE(c.max_z, 5.0) << describe(c);
    EXPECT_NEAR(c.mean_a, c.mean_b, 5.0 * c.se) << describe(c);
    return path;
}

}  // namespace spt::test

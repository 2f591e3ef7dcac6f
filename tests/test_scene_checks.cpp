// Scene-level invariants: a Cornell box scaled by 1e-3 or 1e3 renders the same image (no
// self-intersection acne, no light leaks at any scale), and invalid materials are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <variant>

#include "render/renderer.h"
#include "scene/builtin_scenes.h"

namespace {

using namespace spt;

/// cornell-point with every length multiplied by s; the point light's intensity grows by s²
/// so that irradiance, and therefore the image, stays the same.
Scene scaled_cornell_point(float s) {
    Scene scene = *make_builtin_scene("cornell-point", SpectralResolution{});
    for (Plane& p : scene.planes) p.offset *= s;
    for (Sphere& sp : scene.spheres) sp.center *= s, sp.radius *= s;
    scene.camera.position *= s;
    scene.camera.look_at *= s;
    for (Light& light : scene.lights) {
        PointLight* l = std::get_if<PointLight>(&light);
        if (!l) continue;
        l->position *= s;
        l->intensity = Spectrum(SpectrumSource::blackbody(6500, 3.0 * double(s) * s, 560), SpectralResolution{});
    }
    scene.finalize();
    return scene;
}

std::unique_ptr<Film> render_small(const Scene& scene) {
    RenderSettings rs;
    rs.width = rs.height = 24;
    rs.spp = 64;
    rs.seed = 3;
    auto film = std::make_unique<Film>(rs.width, rs.height);
    render(scene, rs, *film);
    return film;
}

TEST(SceneScale, CornellScaledBy1e3And1eMinus3RendersTheSameImage) {
    const auto reference_film = render_small(scaled_cornell_point(1.f));
    const Film& reference = *reference_film;
    for (float s : {1e-3f, 1e3f}) {
        const auto film_ptr = render_small(scaled_cornell_point(s));
        const Film& film = *film_ptr;
        EXPECT_EQ(film.rejected_samples(), 0u);
        // Same seeds, same paths up to rounding: pixels agree far within their noise. A leak or
        // acne changes whole regions by many standard errors.
        int outliers = 0;
        double sum_ref = 0, sum = 0;
        for (int y = 0; y < film.height(); ++y)
            for (int x = 0; x < film.width(); ++x) {
                const double a = reference.pixel_xyz(x, y).y, b = film.pixel_xyz(x, y).y;
                const double sigma = std::hypot(reference.pixel_y_standard_error(x, y),
                                                film.pixel_y_standard_error(x, y));
                if (std::fabs(a - b) > 4 * sigma + 1e-6) ++outliers;
                sum_ref += a, sum += b;
            }
        EXPECT_LE(outliers, 2) << "scale " << s;
        EXPECT_NEAR(sum / sum_ref, 1.0, 0.01) << "scale " << s;
    }
}

TEST(SceneValidation, ReflectanceAboveOneAtSomeWavelengthIsRefused) {
    Scene scene = *make_builtin_scene("cornell", SpectralResolution{});
    // Blue plastic kd peaks at 0.8 near 460 nm; a mirror coat of 0.25 pushes it over 1 there.
    for (Material& m : scene.materials)
        if (m.name == "blue plastic")
            std::get<LobeMixBsdf>(m.bsdf).ks = Spectrum(SpectrumSource::constant(0.25), SpectralResolution{});
    try {
        scene.finalize();
        FAIL() << "kd + ks > 1 was accepted";
    } catch (const SceneError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("blue plastic"), std::string::npos) << msg;
        EXPECT_NE(msg.find("kd + ks + kt"), std::string::npos) << msg;
        EXPECT_NE(msg.find(" nm"), std::string::npos) << msg;
    }
}

TEST(SceneValidation, ReflectanceSumExactlyOneIsAccepted) {
    Scene scene = *make_builtin_scene("cornell", SpectralResolution{});
    // Gray is loaded as a DiffuseBsdf (kd 0.75 only); the coat makes it a lobe mix.
    for (Material& m : scene.materials)
        if (m.name == "gray") {
            LobeMixBsdf coated;
            coated.kd = std::get<DiffuseBsdf>(m.bsdf).kd;
            coated.ks = Spectrum(SpectrumSource::constant(0.25), SpectralResolution{});
            m.bsdf = coated;
        }
    EXPECT_NO_THROW(scene.finalize());
}

TEST(SceneValidation, NonPositiveRadiusAndBadIndexAreRefused) {
    Scene scene = *make_builtin_scene("cornell", SpectralResolution{});
    scene.spheres[0].radius = 0.f;
    EXPECT_THROW(scene.finalize(), SceneError);
    scene = *make_builtin_scene("cornell", SpectralResolution{});
    for (Material& m : scene.materials)
        if (m.name == "glass") std::get<LobeMixBsdf>(m.bsdf).eta = Spectrum(SpectrumSource::constant(0.9), SpectralResolution{});
    EXPECT_THROW(scene.finalize(), SceneError);
}

}  // namespace

// The two canonical Cornell boxes of DESIGN.md written in C++, exactly as the program defined
// them before scenes became files: the reference that scenes/cornell*.json must reproduce
// bit for bit (test_scene_loader.cpp). Materials are written as the loader builds them: a
// material with only kd is a DiffuseBsdf, the others a LobeMixBsdf; the ceiling's emission is
// an emitter attached to the plane, whose material reflects nothing.
#pragma once
#include <optional>
#include <string>

#include "scene/scene.h"

namespace spt::test {

namespace cornell_detail {

inline Material diffuse(std::string name, const Spectrum& kd) {
    Material m;
    m.name = std::move(name);
    m.bsdf = DiffuseBsdf{kd};
    return m;
}

/// Shared by both boxes: walls, the plastic and the glass sphere, and the camera.
inline Scene make_cornell_common(std::string name, SpectralResolution res, bool ceiling_light) {
    using Src = SpectrumSource;
    const Spectrum gray(Src::constant(0.75), res);
    const Spectrum red(Src::sigmoid(600, 12, 0.65, 0.05), res);
    const Spectrum green(Src::gaussian(540, 40, 0.55, 0.05), res);
    const Spectrum blue(Src::gaussian(460, 35, 0.75, 0.05), res);

    Scene scene;
    scene.name = std::move(name);
    scene.camera = {{0, 0, 3.5f}, {0, 0, 0}, {0, 1, 0}, 40.f};
    const int m_red = scene.add_material(diffuse("red", red));
    const int m_green = scene.add_material(diffuse("green", green));
    const int m_gray = scene.add_material(diffuse("gray", gray));

    int m_ceiling = m_gray;
    int ceiling_emitter = -1;
    if (ceiling_light) {
        m_ceiling = scene.add_material(diffuse("light", Spectrum()));  // reflects nothing
        ceiling_emitter = scene.add_emitter(ShapeKind::plane, Spectrum(Src::blackbody(6500, 4.0, 560), res));
    }
    Material plastic;
    plastic.name = "blue plastic";
    LobeMixBsdf plastic_lobes;
    plastic_lobes.kd = blue;
    plastic_lobes.ks = Spectrum(Src::constant(0.15), res);
    plastic.bsdf = plastic_lobes;
    const int m_plastic = scene.add_material(plastic);
    Material glass;
    glass.name = "glass";
    LobeMixBsdf glass_lobes;
    glass_lobes.kt = Spectrum(Src::constant(1.0), res);
    glass_lobes.eta = Spectrum(Src::constant(1.5), res);
    glass.bsdf = glass_lobes;
    const int m_glass = scene.add_material(glass);

    // Planes as dot(n, p) = offset with n facing into the box.
    scene.planes = {
        {{1, 0, 0}, -1.f, m_red},       // left wall, x = -1
        {{-1, 0, 0}, -1.f, m_green},    // right wall, x = +1
        {{0, 1, 0}, -1.f, m_gray},      // floor, y = -1
        {{0, 0, 1}, -1.f, m_gray},      // back wall, z = -1
        {{0, -1, 0}, -1.f, m_ceiling, ceiling_emitter},  // ceiling, y = +1 (emitting in "cornell")
    };
    scene.spheres = {
        {{-0.45f, -0.6f, -0.3f}, 0.4f, m_plastic},
        {{0.45f, -0.6f, 0.25f}, 0.4f, m_glass},
    };
    return scene;
}

}  // namespace cornell_detail

inline std::optional<Scene> make_cornell_reference(const std::string& name, SpectralResolution res) {
    using namespace cornell_detail;
    std::optional<Scene> scene;
    if (name == "cornell") {
        scene = make_cornell_common(name, res, true);
    } else if (name == "cornell-point") {
        scene = make_cornell_common(name, res, false);
        scene->add_point_light({0, 0.5f, 0}, Spectrum(SpectrumSource::blackbody(6500, 3.0, 560), res));
    }
    if (scene) scene->finalize();
    return scene;
}

}  // namespace spt::test

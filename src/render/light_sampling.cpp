#include "render/light_sampling.h"


namespace spt {

LightSampler::LightSampler(const Scene& scene)
    : m_scene(scene), m_radius(scene.bounds_radius) {
    std::vector<float> power(scene.lights.size(), 0.f);
    for (std::size_t i = 0; i < scene.lights.size(); ++i)
        if (light_can_start_subpath(scene.lights[i])) power[i] = light_power(scene.lights[i]);
    m_choice.build(power);
}

std::optional<LightOrigin> LightSampler::sample(const SampledWavelengths& lambda, float u_light, float u1,
                                                float u2, float u_side, float u3, float u4, float time) const {
    if (m_choice.empty()) return std::nullopt;
    float choice = 0.f;
    const int index = m_choice.sample(u_light, choice);
    const Light& light = m_scene.lights[static_cast<std::size_t>(index)];
    std::optional<LightOrigin> o = light_sample_le(light, lambda, u1, u2, u_side, u3, u4, time);
    if (!o) return o;
    o->light = index;
    if (o->infinite) {
        // Measured by direction: the choice goes with the direction's density.
        o->pdf_dir *= choice;
        // Upstream of the disk lies only what is unbounded: a plane there hides the light.
        const Ray upstream{o->p, -o->w, kInfinity};
        for (const Plane& plane : m_scene.planes) o->blocked |= plane.intersect_t(upstream) < kInfinity;
        return o;
    }
    o->pdf_pos *= choice;
    // An emission texture: its radiance at the point (uniform by area, so the densities stay).
    if (m_scene.light_textured(index)) o->Le = m_scene.light_point_emission(index, o->p, o->triangle, lambda);
    return o;
}

float LightSampler::infinite_pdf(int light, const Vec3& d) const {
    const float choice = m_choice.probability(light);
    if (choice == 0.f) return 0.f;
    return choice * light_pdf_le_dir(m_scene.lights[static_cast<std::size_t>(light)], Vec3(), d);
}

float LightSampler::infinite_position_pdf(int light, const Vec3& p, const Vec3& d) const {
    return visit_light_of<kInfiniteLights>(m_scene.lights[static_cast<std::size_t>(light)],
                                           [&](const auto& l) { return l.pdf_le_pos(p, d); });
}

float LightSampler::origin_pdf(const Hit& hit) const {
    if (hit.light < 0) return 0.f;
    const float choice = m_choice.probability(hit.light);
    if (choice == 0.f) return 0.f;  // emitting planes cannot start subpaths
    return choice * light_pdf_le_pos(m_scene.lights[static_cast<std::size_t>(hit.light)]);
}

}  // namespace spt

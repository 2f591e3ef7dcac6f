#include "render/light_sampling.h"

#include <algorithm>

#include "core/frame.h"
#include "core/sampling.h"

namespace spt {

LightSampler::LightSampler(const Scene& scene)
    : m_scene(scene), m_center(scene.bounds_center), m_radius(scene.bounds_radius) {
    std::vector<float> power(scene.lights.size(), 0.f);
    for (std::size_t i = 0; i < scene.lights.size(); ++i)
        if (!std::holds_alternative<PlaneLight>(scene.lights[i])) power[i] = light_power(scene.lights[i]);
    m_choice.build(power);
    m_environment_choice = m_choice.probability(scene.environment_index);
}

std::optional<LightOrigin> LightSampler::sample(const SampledWavelengths& lambda, float u_light, float u1,
                                                float u2, float u_side, float u3, float u4, float time) const {
    if (m_choice.empty()) return std::nullopt;
    float choice = 0.f;
    const int index = m_choice.sample(u_light, choice);
    const Light& light = m_scene.lights[static_cast<std::size_t>(index)];
    if (const EnvironmentLight* env = std::get_if<EnvironmentLight>(&light)) {
        // Direction, then a point on the disk of radius R facing it, one radius upstream.
        LightOrigin o;
        o.environment = true;
        o.w = sample_uniform_sphere(u1, u2);
        const Frame frame(o.w);
        const float r = m_radius * std::sqrt(u3), phi = 2.f * kPi * u4;
        o.p = m_center - o.w * m_radius + frame.s * (r * std::cos(phi)) + frame.t * (r * std::sin(phi));
        o.p_err = Vec3(0, 0, 0);
        o.Le = env->Le.sample(lambda);
        o.pdf_pos = 1.f / (kPi * m_radius * m_radius);
        o.pdf_dir = choice * (0.25f * kInvPi);
        o.light = index;
        // Upstream of the disk lies only what is unbounded: a plane there hides the environment.
        const Ray upstream{o.p, -o.w, kInfinity};
        for (const Plane& plane : m_scene.planes) o.blocked |= plane.intersect_t(upstream) < kInfinity;
        return o;
    }
    if (const PointLight* point = std::get_if<PointLight>(&light)) {
        LightOrigin o = point->sample_le(lambda, u1, u2);
        o.p = point->position_at(time);
        o.pdf_pos *= choice;
        o.light = index;
        return o;
    }
    if (const SpotLight* spot = std::get_if<SpotLight>(&light)) {
        LightOrigin o = spot->sample_le(lambda, u1, u2);
        o.pdf_pos *= choice;
        o.light = index;
        return o;
    }
    // An area light (planes are never chosen: they cannot start a subpath).
    std::optional<LightOrigin> o = std::visit(
        [&](const auto& l) -> std::optional<LightOrigin> {
            if constexpr (requires { l.sample_le(lambda, u1, u2, u_side, u3, u4); })
                return l.sample_le(lambda, u1, u2, u_side, u3, u4);
            else return std::nullopt;
        },
        light);
    if (!o) return o;
    o->pdf_pos *= choice;
    o->light = index;
    // An emission texture: its radiance at the point (uniform by area, so the densities stay).
    if (m_scene.light_textured(index)) o->Le = m_scene.light_point_emission(index, o->p, o->triangle, lambda);
    return o;
}

float LightSampler::environment_position_pdf(const Vec3& p, const Vec3& d) const {
    if (!has_environment()) return 0.f;
    const Vec3 v = p - m_center;
    const float along = dot(v, d);
    if (along < -m_radius || length_squared(v - d * along) > m_radius * m_radius) return 0.f;
    return 1.f / (kPi * m_radius * m_radius);
}

float LightSampler::origin_pdf(const Hit& hit) const {
    if (hit.light < 0) return 0.f;
    const float choice = m_choice.probability(hit.light);
    if (choice == 0.f) return 0.f;  // emitting planes cannot start subpaths
    return std::visit(
        [&](const auto& l) -> float {
            if constexpr (requires { l.pdf_le_pos(); }) return choice * l.pdf_le_pos();
            else return 0.f;
        },
        m_scene.lights[static_cast<std::size_t>(hit.light)]);
}

}  // namespace spt

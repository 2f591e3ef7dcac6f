#include "render/light_sampling.h"

#include <algorithm>

#include "core/frame.h"
#include "core/sampling.h"
#include "geometry/aabb.h"

namespace spt {

namespace {

/// Mean of a spectrum over 380–780 nm (41 samples): the "power" used to choose lights.
float mean_value(const Spectrum& s) {
    double sum = 0;
    for (int i = 0; i <= 40; ++i) sum += s.eval(380.f + 10.f * static_cast<float>(i));
    return static_cast<float>(sum / 41.0);
}

float triangle_area(const Triangle& t) { return 0.5f * length(cross(t.p1 - t.p0, t.p2 - t.p0)); }

/// Box around what the environment's light subpaths should reach: the finite shapes, the camera
/// and the point lights. Planes are unbounded (see the header).
Aabb scene_bounds(const Scene& scene) {
    Aabb box;
    for (const Sphere& s : scene.spheres) {
        const Vec3 r(s.radius, s.radius, s.radius);
        box.expand(s.center - r);
        box.expand(s.center + r);
    }
    for (const Triangle& t : scene.triangles) box.expand(t.p0), box.expand(t.p1), box.expand(t.p2);
    for (const PointLight& l : scene.point_lights) box.expand(l.position);
    box.expand(scene.camera.position);
    return box;
}

}  // namespace

LightSampler::LightSampler(const Scene& scene) : m_scene(scene) {
    std::vector<float> power;
    for (int i = 0; i < static_cast<int>(scene.point_lights.size()); ++i) {
        const float p = 4.f * kPi * mean_value(scene.point_lights[i].intensity);
        if (p > 0.f) m_lights.push_back({Kind::point, i}), power.push_back(p);
    }
    std::vector<float> material_le(scene.materials.size(), 0.f);
    for (std::size_t m = 0; m < scene.materials.size(); ++m)
        if (scene.materials[m].is_emissive()) material_le[m] = mean_value(scene.materials[m].emission);
    for (int i = 0; i < static_cast<int>(scene.spheres.size()); ++i) {
        const Sphere& s = scene.spheres[i];
        const float area = 4.f * kPi * s.radius * s.radius;
        const float p = 2.f * kPi * area * material_le[s.material];
        if (p > 0.f) m_lights.push_back({Kind::sphere, i}), power.push_back(p);
    }
    for (int i = 0; i < static_cast<int>(scene.triangles.size()); ++i) {
        const Triangle& t = scene.triangles[i];
        const float p = 2.f * kPi * triangle_area(t) * material_le[t.material];
        if (p > 0.f) m_lights.push_back({Kind::triangle, i}), power.push_back(p);
    }
    for (int i = 0; i < static_cast<int>(scene.planes.size()); ++i)
        if (scene.materials[scene.planes[i].material].is_emissive()) m_emissive_planes.push_back(i);
    const Aabb box = scene_bounds(scene);
    m_center = box.centroid();
    m_radius = 0.5f * length(box.hi - box.lo);
    // A lone camera (only planes around it): any radius is correct (see the header).
    if (!(m_radius > 0.f)) m_radius = 1.f;
    if (scene.effects.background) {
        const float p = 4.f * kPi * (kPi * m_radius * m_radius) * mean_value(scene.background);
        if (p > 0.f) m_lights.push_back({Kind::environment, -1}), power.push_back(p);
    }

    double total = 0;
    for (float p : power) total += p;
    m_material_area_pdf.assign(scene.materials.size(), 0.f);
    if (!(total > 0)) {
        m_lights.clear();
        return;
    }
    double running = 0;
    for (float p : power) {
        running += p;
        m_cdf.push_back(static_cast<float>(running / total));
        m_choice.push_back(static_cast<float>(p / total));
    }
    m_cdf.back() = 1.f;
    if (!m_lights.empty() && m_lights.back().kind == Kind::environment) m_environment_choice = m_choice.back();
    for (std::size_t m = 0; m < scene.materials.size(); ++m)
        m_material_area_pdf[m] = static_cast<float>(2.0 * kPi * material_le[m] / total);
}

std::optional<LightOrigin> LightSampler::sample(const SampledWavelengths& lambda, float u_light,
                                                float u1, float u2, float u_side, float u3,
                                                float u4) const {
    if (m_lights.empty()) return std::nullopt;
    const auto it = std::upper_bound(m_cdf.begin(), m_cdf.end(), u_light);
    const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(it - m_cdf.begin()), m_lights.size() - 1);
    const Entry& e = m_lights[k];
    LightOrigin o;
    if (e.kind == Kind::environment) {
        // Direction, then a point on the disk of radius R facing it, one radius upstream.
        o.environment = true;
        o.w = sample_uniform_sphere(u1, u2);
        const Frame frame(o.w);
        const float r = m_radius * std::sqrt(u3), phi = 2.f * kPi * u4;
        o.p = m_center - o.w * m_radius + frame.s * (r * std::cos(phi)) + frame.t * (r * std::sin(phi));
        o.p_err = Vec3(0, 0, 0);
        o.Le = m_scene.background.sample(lambda);
        o.pdf_pos = 1.f / (kPi * m_radius * m_radius);
        o.pdf_dir = m_choice[k] * (0.25f * kInvPi);
        // Upstream of the disk lies only what is unbounded: a plane there hides the environment.
        const Ray upstream{o.p, -o.w, kInfinity};
        for (const Plane& plane : m_scene.planes) o.blocked |= plane.intersect_t(upstream) < kInfinity;
        return o;
    }
    if (e.kind == Kind::point) {
        const PointLight& light = m_scene.point_lights[e.index];
        o.p = light.position;
        o.p_err = Vec3(0, 0, 0);
        o.w = sample_uniform_sphere(u1, u2);
        o.Le = light.intensity.sample(lambda);
        o.pdf_pos = m_choice[k];
        o.pdf_dir = 1.f / (4.f * kPi);
        o.delta_position = true;
        return o;
    }
    int material;
    float area;
    if (e.kind == Kind::sphere) {
        const Sphere& s = m_scene.spheres[e.index];
        o.n = sample_uniform_sphere(u1, u2);
        o.p = s.center + o.n * s.radius;
        o.p_err = (abs(s.center) + Vec3(s.radius, s.radius, s.radius)) * gamma_bound(6);
        material = s.material;
        area = 4.f * kPi * s.radius * s.radius;
    } else {
        const Triangle& t = m_scene.triangles[e.index];
        // Uniform barycentrics (square-root warp).
        const float su = std::sqrt(u1);
        const float b0 = 1.f - su, b1 = u2 * su, b2 = 1.f - b0 - b1;
        o.p = t.p0 * b0 + t.p1 * b1 + t.p2 * b2;
        o.p_err = (abs(t.p0 * b0) + abs(t.p1 * b1) + abs(t.p2 * b2)) * gamma_bound(7) +
                  rounded_point_error(o.p);
        o.n = normalize(cross(t.p1 - t.p0, t.p2 - t.p0));
        material = t.material;
        area = triangle_area(t);
    }
    // Both sides emit: pick one, then a cosine-weighted direction on it.
    const Vec3 side = u_side < 0.5f ? o.n : -o.n;
    const Vec3 local = sample_cosine_hemisphere(u3, u4);
    if (!(local.z > 0.f)) return std::nullopt;
    o.w = Frame(side).to_world(local);
    o.Le = m_scene.materials[material].emission.sample(lambda);
    o.pdf_pos = m_choice[k] / area;
    o.pdf_dir = 0.5f * local.z * kInvPi;
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
    if (m_lights.empty()) return 0.f;
    const float pdf = m_material_area_pdf[hit.material];
    if (pdf == 0.f) return 0.f;
    // An emitting plane may share its material with sampled shapes: test whether the point
    // lies on one of those planes (hits on planes are snapped onto them).
    for (int i : m_emissive_planes) {
        const Plane& plane = m_scene.planes[i];
        if (plane.material != hit.material) continue;
        const float residual = std::fabs(dot(plane.normal, hit.p) - plane.offset);
        if (residual <= 1e-5f * (1.f + std::fabs(plane.offset) + max_component(abs(hit.p)))) return 0.f;
    }
    return pdf;
}

}  // namespace spt

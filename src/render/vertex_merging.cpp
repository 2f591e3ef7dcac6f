#include "render/vertex_merging.h"

#include <algorithm>
#include <cmath>

namespace spt {

void MergePass::build(std::vector<LightSubpathBatch>& batches, const Scene& scene, float radius, float eta) {
    m_vertices.clear();
    m_begin.assign(1, 0);
    m_photons.clear();
    for (LightSubpathBatch& b : batches) {
        const auto offset = static_cast<std::uint32_t>(m_vertices.size());
        m_vertices.insert(m_vertices.end(), b.vertices.begin(), b.vertices.end());
        std::uint32_t begin = offset;
        for (const std::uint32_t end : b.ends) {
            for (std::uint32_t v = begin + 1; v < offset + end; ++v) {
                const BdptVertex& x = m_vertices[v];
                if (x.type == BdptVertexType::surface && !x.infinite &&
                    scene.materials[x.hit.material].has_diffuse())
                    m_photons.push_back({v, begin});
            }
            begin = offset + end;
            m_begin.push_back(begin);
        }
        b = {};
    }
    std::vector<Vec3> points(m_photons.size());
    for (std::size_t i = 0; i < points.size(); ++i) points[i] = m_vertices[m_photons[i].vertex].p();
    m_grid.build(points, radius);
    m_eta = eta;
}

float default_merge_radius(const Scene& scene, const Camera& camera, int width, int height, float scene_radius) {
    constexpr int kGrid = 16;
    std::vector<float> distances;
    for (int j = 0; j < kGrid; ++j)
        for (int i = 0; i < kGrid; ++i) {
            const Ray ray = camera.generate_ray((static_cast<float>(i) + 0.5f) * static_cast<float>(width) / kGrid,
                                                (static_cast<float>(j) + 0.5f) * static_cast<float>(height) / kGrid);
            if (const std::optional<Hit> hit = scene.intersect(ray)) distances.push_back(hit->t);
        }
    if (distances.empty()) return 0.003f * scene_radius;
    std::nth_element(distances.begin(), distances.begin() + static_cast<std::ptrdiff_t>(distances.size() / 2),
                     distances.end());
    const float median = distances[distances.size() / 2];
    const float cx = 0.5f * static_cast<float>(width), cy = 0.5f * static_cast<float>(height);
    const float pixel_angle = length(camera.generate_ray(cx + 1.f, cy).d - camera.generate_ray(cx, cy).d);
    return 5.f * median * pixel_angle;
}

float merge_radius(float r0, int pass) { return r0 * std::pow(static_cast<float>(pass + 1), -0.125f); }

SampledWavelengths pass_wavelengths(std::uint64_t seed, int pass) {
    const double offset = static_cast<double>(mix64(seed ^ 0x5bd1e995u) >> 11) * 0x1.0p-53;
    double u = offset + 0.6180339887498949 * static_cast<double>(pass);
    u -= std::floor(u);
    return SampledWavelengths::sample(static_cast<float>(std::min(u, 0x1.fffffep-1)));
}

}  // namespace spt

#include "render/vertex_merging.h"

#include <algorithm>
#include <cmath>

namespace spt {

void MergePass::build(std::vector<LightSubpathBatch>& batches, const Scene& scene, float radius, float eta) {
    m_vertices.clear();
    m_begin.assign(1, 0);
    std::vector<MergeContext::Photon> photons;
    for (LightSubpathBatch& b : batches) {
        const auto offset = static_cast<std::uint32_t>(m_vertices.size());
        m_vertices.insert(m_vertices.end(), b.vertices.begin(), b.vertices.end());
        std::uint32_t begin = offset;
        for (const std::uint32_t end : b.ends) {
            // From the second bounce of light on (light index ≥ 2; see Bdpt::other_strategies).
            for (std::uint32_t v = begin + 2; v < offset + end; ++v) {
                const BdptVertex& x = m_vertices[v];
                if (x.type == BdptVertexType::surface && !x.infinite && scene.materials[x.hit.material].has_non_delta())
                    photons.push_back(make_photon(scene, &m_vertices[begin], static_cast<int>(v - begin) + 1, eta));
            }
            begin = offset + end;
            m_begin.push_back(begin);
        }
        b = {};
    }
    std::vector<Vec3> points(photons.size());
    for (std::size_t i = 0; i < points.size(); ++i) points[i] = photons[i].p;
    m_grid.build(points, radius);
    m_photons.resize(photons.size());
    for (std::size_t j = 0; j < photons.size(); ++j) m_photons[j] = photons[m_grid.order()[j]];
    m_eta = eta;
}

float default_merge_radius(const BdptContext& ctx, const RenderSettings& settings) {
    constexpr int kGrid = 16;
    constexpr float kFootprints = 5.f, kPhotonsPerMerge = 16.f;
    constexpr std::uint64_t kPilotStream = 0x2545f4914f6cdd1dull;
    const int width = settings.width, height = settings.height;
    std::vector<Vec3> hits;
    std::vector<float> distances;
    for (int j = 0; j < kGrid; ++j)
        for (int i = 0; i < kGrid; ++i) {
            const Ray ray = ctx.camera.generate_ray((static_cast<float>(i) + 0.5f) * static_cast<float>(width) / kGrid,
                                                    (static_cast<float>(j) + 0.5f) * static_cast<float>(height) / kGrid);
            if (const std::optional<Hit> hit = ctx.scene.intersect(ray)) {
                distances.push_back(hit->t);
                hits.push_back(hit->p);
            }
        }
    if (distances.empty()) return 0.003f * ctx.lights.scene_radius();
    std::nth_element(distances.begin(), distances.begin() + static_cast<std::ptrdiff_t>(distances.size() / 2),
                     distances.end());
    const float median = distances[distances.size() / 2];
    const float cx = 0.5f * static_cast<float>(width), cy = 0.5f * static_cast<float>(height);
    const float pixel_angle = length(ctx.camera.generate_ray(cx + 1.f, cy).d - ctx.camera.generate_ray(cx, cy).d);
    // At most 1 % of the scene's radius: at low resolutions five footprints are a coarse blur.
    const float radius = std::min(kFootprints * median * pixel_angle, 0.01f * ctx.lights.scene_radius());

    // Pilot: the photons of (up to 65536 subpaths of) one light phase, counted around the
    // camera hits and scaled to the N = width·height subpaths of a pass.
    const int n = std::min(width * height, 65536);
    const float scale = static_cast<float>(width) * static_cast<float>(height) / static_cast<float>(n);
    const SampledWavelengths lambda = pass_wavelengths(settings.seed, 0);
    std::vector<LightSubpathBatch> batches(1);
    PathStats stats;
    for (int i = 0; i < n; ++i) {
        Rng rng(settings.seed ^ kPilotStream, static_cast<std::uint64_t>(i), 0);
        batches[0].trace(ctx, lambda, 0.f, rng, stats);
        batches[0].splats.clear();  // the pilot only counts photons
    }
    MergePass pilot;
    pilot.build(batches, ctx.scene, radius, 0.f);
    std::vector<float> counts;
    for (const Vec3& p : hits) {
        int count = 0;
        pilot.grid().query(p, [&](std::uint32_t, float) { ++count; });
        counts.push_back(scale * static_cast<float>(count));
    }
    std::nth_element(counts.begin(), counts.begin() + static_cast<std::ptrdiff_t>(counts.size() / 2), counts.end());
    const float median_count = counts[counts.size() / 2];
    return median_count > kPhotonsPerMerge ? radius * std::sqrt(kPhotonsPerMerge / median_count) : radius;
}

float merge_radius(float r0, int pass) { return r0 * std::pow(static_cast<float>(pass + 1), -0.125f); }

SampledWavelengths pass_wavelengths(std::uint64_t seed, int pass) {
    const double offset = static_cast<double>(mix64(seed ^ 0x5bd1e995u) >> 11) * 0x1.0p-53;
    double u = offset + 0.6180339887498949 * static_cast<double>(pass);
    u -= std::floor(u);
    return SampledWavelengths::sample(static_cast<float>(std::min(u, 0x1.fffffep-1)));
}

}  // namespace spt

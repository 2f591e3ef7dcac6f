// What a path brings to the guiding field in a training iteration (Müller et al. 2017, §4):
// at each vertex whose direction was drawn from a density (not a delta lobe), the radiance
// that arrived along that direction, over its density. That radiance is known only when the
// path ends: everything the path gathered after the vertex, divided by the throughput it
// had leaving the vertex. So the recorder keeps, per vertex, the throughput and the radiance
// gathered so far, and records the differences at the end.
//
// The radiance counted here differs from the image's in one way: emission that the path
// finds counts whole, not MIS-weighted against next-event estimation, so the field learns
// where the lights are as well as where indirect light comes from (kept by the kernel as
// `guide_radiance`).
#pragma once
#include <array>

#include "render/guiding/guide_bands.h"
#include "render/guiding/guided_bounce.h"
#include "render/guiding/guiding_field.h"

namespace spt {

class GuideRecorder {
public:
    /// A vertex at leaf `leaf` that continued along wi with density `pdf`, the path's
    /// throughput after the bounce (before roulette: a path ended by roulette then records 0,
    /// one that survives its radiance over the survival probability; both unbiased) and its
    /// guide radiance until then. Paths deeper than kMostVertices record their first ones.
    /// A vertex sampled from the guide mixture also gives `densities` and the throughput
    /// before the bounce, for the second moments that choose α (guiding_field.h).
    void add(int leaf, const Vec3& wi, float pdf, const SampledSpectrum& beta, const SampledSpectrum& radiance,
             const GuidedDensities* densities = nullptr, const SampledSpectrum& beta_before = SampledSpectrum(0.f)) {
        if (m_count >= kMostVertices) return;
        m_vertices[static_cast<std::size_t>(m_count++)] = {leaf, wi, pdf, beta, radiance, beta_before,
                                                           densities ? *densities : GuidedDensities{},
                                                           densities != nullptr};
    }

    /// Records every vertex into the field, the path's guide radiance at its end being
    /// `radiance`, at wavelengths `lambda` (those with pdf 0 were terminated and record nothing).
    void finish(GuidingField& field, const SampledSpectrum& radiance, const SampledWavelengths& lambda) const {
        for (int i = 0; i < m_count; ++i) {
            const Vertex& v = m_vertices[static_cast<std::size_t>(i)];
            const SquarePoint s = direction_to_square(v.wi);
            float sum = 0.f;
            int live = 0;
            for (int j = 0; j < kLambdaCount; ++j) {
                if (!(lambda.pdf[static_cast<std::size_t>(j)] > 0.f)) continue;
                const float li = v.beta[j] > 0.f ? (radiance[j] - v.radiance[j]) / v.beta[j] : 0.f;
                ++live;
                if (field.channels() == 1) sum += li;
                else field.record(v.leaf, s, guide_band(lambda.lambda[static_cast<std::size_t>(j)]), li / v.pdf);
            }
            if (field.channels() == 1 && live > 0) field.record(v.leaf, s, 0, sum / float(live) / v.pdf);
            field.count(v.leaf);
            if (v.guided && live > 0) {
                // The vertex's contribution over the throughput it was reached with.
                float x = 0.f;
                for (int j = 0; j < kLambdaCount; ++j)
                    if (lambda.pdf[static_cast<std::size_t>(j)] > 0.f && v.beta_before[j] > 0.f)
                        x += (radiance[j] - v.radiance[j]) / v.beta_before[j];
                field.record_moments(v.leaf, x / float(live), v.pdf, v.densities.guide, v.densities.bsdf);
            }
        }
    }

private:
    static constexpr int kMostVertices = 32;
    struct Vertex {
        int leaf;
        Vec3 wi;
        float pdf;
        SampledSpectrum beta, radiance, beta_before;
        GuidedDensities densities;
        bool guided;
    };
    std::array<Vertex, kMostVertices> m_vertices;
    int m_count = 0;
};

}  // namespace spt

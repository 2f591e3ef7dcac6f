// Next-event estimation's choice of one light (other than the point and spot lights, which
// are all sampled): by power (Scene::area_light_choice*, one table for every point) or by the
// light BVH (render/light_bvh.h: by likely contribution at the shading point). The BVH is
// used only when IntegratorSettings::light_selection asks for it and there are at least two
// lights to choose from; with one light both give it probability 1, and taking the power
// table then keeps such scenes' images and random numbers exactly as they are.
//
// The probability reported with a light is that of the whole light: for a triangle of a mesh
// light the BVH's probability of the triangle times total_area / its area, with the point
// sampled on that triangle (light_sample_li_on) at the light's own density. The emission
// weights ask probability() for the same number.
#pragma once
#include "model/lights/light.h"
#include "model/lights/light_distribution.h"
#include "render/integrator.h"
#include "scene/scene.h"

namespace spt {

struct NeeLightChoice {
    const LightDistribution* power = nullptr;
    const LightBvh* bvh = nullptr;  ///< nullptr: by power
    bool with_planes = false;

    NeeLightChoice(const Scene& scene, const IntegratorSettings& settings)
        : power(settings.sample_planes ? &scene.area_light_choice_with_planes : &scene.area_light_choice),
          bvh(settings.light_selection == LightSelection::bvh && power->size() > 1 ? &scene.light_bvh : nullptr),
          with_planes(settings.sample_planes) {}

    bool empty() const { return power->empty(); }

    /// A light for ctx with u in [0, 1): its index in Scene::lights (−1: none can light ctx),
    /// its choice probability, and the triangle to sample on it (−1: the light samples itself).
    [[gnu::always_inline]] int sample(const LightSampleContext& ctx, float u, float& choice, int& triangle) const {
        if (!bvh) [[likely]] {
            triangle = -1;
            return power->sample(u, choice);
        }
        return sample_bvh(ctx, u, choice, triangle);
    }

    /// The probability with which sample() chooses light `index` at ctx, for emission from it
    /// found at `hit` (nullptr: an escaped ray).
    [[gnu::always_inline]] float probability(const LightSampleContext& ctx, int index, const Hit* hit) const {
        if (!bvh) [[likely]] return power->probability(index);
        return probability_bvh(ctx, index, hit);
    }

private:
    [[gnu::noinline]] int sample_bvh(const LightSampleContext& ctx, float u, float& choice, int& triangle) const {
        float prob = 0.f;
        const int pick = bvh->sample(ctx, u, with_planes, prob);
        if (pick == -1) {
            triangle = -1;
            return -1;
        }
        const int light = bvh->light_of(pick, triangle);
        choice = pick >= 0 ? prob * bvh->entries()[static_cast<std::size_t>(pick)].area_ratio : prob;
        return light;
    }
    [[gnu::noinline]] float probability_bvh(const LightSampleContext& ctx, int index, const Hit* hit) const {
        const int scene_triangle =
            hit && hit->prim.kind() == ShapeKind::triangle ? static_cast<int>(hit->prim.index()) : -1;
        return bvh->light_choice(ctx, index, scene_triangle, with_planes);
    }
};

/// sample_li of light `light`, on its triangle `triangle` when ≥ 0 (a mesh light's, chosen by
/// the BVH), in place as light_sample_li.
[[gnu::always_inline]] inline bool light_sample_li_on(const Light& light, int triangle, const LightSampleContext& ctx,
                                                      const SampledWavelengths& lambda, float u1, float u2,
                                                      LightSample& ls) {
    if (triangle < 0) [[likely]] return light_sample_li(light, ctx, lambda, u1, u2, ls);
    return std::get_if<TriangleMeshLight>(&light)->sample_li_on(static_cast<std::uint32_t>(triangle), ctx, lambda, u1,
                                                                  u2, ls);
}

}  // namespace spt

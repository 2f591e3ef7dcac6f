// The closed set of lights and the contract each type fulfils. Adding a light is one header
// in this folder and one entry in `Light`. An area light belongs to its shape: the shape
// records the light's index (Hit::light), so a path that hits an emitter finds it directly.
//
///  power()                        mean emitted power over 380–780 nm (up to a common
///                                 scale): lights are chosen in proportion to it.
///  sample_li(ctx, λ, u1, u2)      a direction towards the light from a reference point:
///                                 {wi, L arriving along −wi, pdf in solid angle (1 for
///                                 a delta light), the light point for the shadow ray};
///                                 nullopt when nothing can arrive.
///  pdf_li(ctx, hit)               the solid-angle density with which sample_li would
///                                 produce the direction of a ray from ctx that found
///                                 the light at `hit` (or escaped, for the environment).
///  emitted(λ)                     radiance leaving the light's surface (area emitters
///                                 emit the same from both sides).
///  sample_le(...) / pdf_le_pos()  origin of a light subpath (bidirectional integrators:
///                                 render/light_sampling.h); not every light can start one.
#pragma once
#include <optional>
#include <type_traits>
#include <variant>

#include "geometry/ray.h"
#include "model/lights/environment_light.h"
#include "model/lights/plane_light.h"
#include "model/lights/point_light.h"
#include "model/lights/quad_light.h"
#include "model/lights/quadric_light.h"
#include "model/lights/sphere_light.h"
#include "model/lights/spot_light.h"
#include "model/lights/triangle_mesh_light.h"

namespace spt {

using Light =
    std::variant<PointLight, SphereLight, QuadLight, TriangleMeshLight, QuadricLight, PlaneLight, EnvironmentLight,
                 SpotLight>;

inline bool is_delta_light(const Light& light) {
    return std::holds_alternative<PointLight>(light) || std::holds_alternative<SpotLight>(light);
}

inline float light_power(const Light& light) {
    return std::visit([](const auto& l) { return l.power(); }, light);
}

inline std::optional<LightSample> light_sample_li(const Light& light, const LightSampleContext& ctx,
                                                  const SampledWavelengths& lambda, float u1, float u2) {
    return std::visit(
        [&](const auto& l) -> std::optional<LightSample> {
            using T = std::decay_t<decltype(l)>;
            if constexpr (std::is_same_v<T, PointLight> || std::is_same_v<T, SpotLight>) return l.sample_li(ctx, lambda);
            else return l.sample_li(ctx, lambda, u1, u2);
        },
        light);
}

/// pdf_li for a ray from ctx along wi that reached the light at `hit` (nullptr: the ray
/// escaped, which only the environment answers).
inline float light_pdf_li(const Light& light, const LightSampleContext& ctx, const Vec3& wi, const Hit* hit) {
    return std::visit(
        [&](const auto& l) -> float {
            using T = std::decay_t<decltype(l)>;
            if constexpr (std::is_same_v<T, PointLight> || std::is_same_v<T, SpotLight>) return 0.f;
            else if constexpr (std::is_same_v<T, PlaneLight> || std::is_same_v<T, EnvironmentLight>)
                return l.pdf_li(ctx, wi);
            else return hit ? l.pdf_li(ctx, hit->p, hit->n) : 0.f;
        },
        light);
}

/// Radiance leaving an area light or arriving from the environment (0 for point lights).
/// A chain of index tests, inlined (as bsdf.h's visit_bsdf): std::visit compiled to an
/// out-of-line call through a table, which the path loop made at every emitter it hit.
template <std::size_t I = 0>
[[gnu::always_inline]] inline SampledSpectrum light_emitted(const Light& light, const SampledWavelengths& lambda) {
    if constexpr (I + 1 < std::variant_size_v<Light>) {
        if (light.index() != I) return light_emitted<I + 1>(light, lambda);
    }
    using T = std::variant_alternative_t<I, Light>;
    if constexpr (std::is_same_v<T, PointLight> || std::is_same_v<T, SpotLight>) return SampledSpectrum(0.f);
    else return std::get_if<I>(&light)->Le.sample(lambda);
}

}  // namespace spt

// The closed set of lights and the one contract every type fulfils. Adding a light is one
// header in this folder and one entry in `Light` (docs/DESIGN.md: "How to add a light").
// Integrators reach lights only through the functions below, which dispatch on the type; no
// file under render/ names a concrete light. An area light belongs to its shape: the shape
// records the light's index (Hit::light), so a path that hits an emitter finds it directly.
//
// Every light has:
///  type                           LightType (light_sample.h): delta_position (point, spot),
///                                 delta_direction (none yet), area (a surface rays hit:
///                                 quad, sphere, triangles, quadrics, the infinite plane),
///                                 infinite (what escaping rays see: the environment,
///                                 the sky and the sun's disc).
///  power()                        mean emitted power over 380–780 nm (up to a common
///                                 scale): lights are chosen in proportion to it.
///  spectral_power(λ)              the power per nm at λ on power()'s scale (power() is its
///                                 mean over 380–780 nm at 10 nm steps), for any λ: what
///                                 fluorescent materials sample excitation by. Lights whose
///                                 spectrum varies over their extent (maps, the sky, the
///                                 sun's disc, portals) give power() at every λ: flat.
///  sample_li(ctx, λ, u1, u2, ls)  a direction towards the light from the reference point
///                                 ctx, written into `ls`, a default LightSample (in place:
///                                 an optional's copy of the sample, read back as wide loads
///                                 of fields just written one by one, stalled on store
///                                 forwarding): wi, L arriving along −wi, the solid-angle
///                                 density pdf of wi (1 for a delta light, with delta set),
///                                 the light point for the shadow ray; false when nothing can
///                                 arrive (a point on the back of a one-sided light is no
///                                 sample).
// Non-delta lights have:
///  pdf_li(...)                    the solid-angle density with which sample_li would
///                                 produce a direction wi from ctx (0 where it returns no
///                                 sample, as behind a one-sided light): (ctx, p, n) for a ray
///                                 that found the light at the point p (normal n), (ctx, wi)
///                                 for the infinite plane and the environment (light_pdf_li
///                                 picks the form).
// Area lights (type area) have:
///  L(p, n, w, λ)                  radiance leaving the surface at p (normal n: the shape's
///                                 own, Hit::n) along w, and
///  two_sided                      whether both sides emit it; if not, only the front (the
///                                 side n points to) does, and sample_li, pdf_li, sample_le,
///                                 pdf_le_dir and power() all see only the front
///                                 (area_emission.h). A `static constexpr` member for types
///                                 that are always two-sided (the sphere, the plane: no test
///                                 per hit), a `bool` member for those a scene may make
///                                 one-sided (quads, triangles, quadrics).
///  closed (optional)              the surface encloses a volume: from outside only its
///                                 outside is seen (the sphere).
///  sample_area_facing(c, R, u1, u2, y, n, pdf) / pdf_area_facing(c, R, y) (optional)
///                                 a point y by area density for a chain of specular bounces
///                                 that ends on a ball of centre c and radius R (caustic
///                                 next-event estimation, render/caustic_nee.h): lights
///                                 without it are not sampled by that strategy.
// Infinite lights (none, one or several in a scene: an escaped ray sees their sum) have:
///  arriving(d, λ)                 radiance arriving along an escaped ray of direction d;
///  center, radius                 the scene's bounding sphere (Scene::finalize sets them),
///                                 whose disks light subpaths from infinity start on.
// Delta-position lights have:
///  position_at(time)              where the light is at shutter time `time`;
///  I_max(λ), falloff(w)           the radiant intensity along unit w is I_max(λ)·falloff(w),
///                                 falloff in [0, 1] (a point light: 1).
// Lights that can start a light subpath (bidirectional integrators; all but the infinite
// plane, which has no finite area) have:
///  sample_le(λ, u1, u2, u_side, u3, u4, time)
///                                 a LightOrigin: point, direction, emitted quantity and
///                                 densities (render/light_sampling.h adds the light choice);
///  pdf_le_dir(n, w)               the solid-angle density of sample_le's direction w from
///                                 a point of normal n;
///  pdf_le_pos()                   area lights: the area density of sample_le's point;
///                                 infinite lights: pdf_le_pos(p, d), the planar density of
///                                 the disk point whose ray along d reaches p (their origins
///                                 are marked LightOrigin::infinite).
//
// tests/test_light_contract.cpp checks every type against this contract.
#pragma once
#include <cstddef>
#include <initializer_list>
#include <optional>
#include <utility>
#include <type_traits>
#include <variant>

#include "geometry/ray.h"
#include "model/lights/area_emission.h"
#include "model/lights/environment_light.h"
#include "model/lights/environment_map_light.h"
#include "model/lights/plane_light.h"
#include "model/lights/point_light.h"
#include "model/lights/portal_light.h"
#include "model/lights/quad_light.h"
#include "model/lights/quadric_light.h"
#include "model/lights/sky_light.h"
#include "model/lights/sphere_light.h"
#include "model/lights/spot_light.h"
#include "model/lights/sun_light.h"
#include "model/lights/triangle_mesh_light.h"

namespace spt {

using Light =
    std::variant<PointLight, SphereLight, QuadLight, TriangleMeshLight, QuadricLight, PlaneLight, EnvironmentLight,
                 SpotLight, EnvironmentMapLight, PortalLight, SkyLight, SunLight>;

/// A set of LightTypes, for visit_light_of.
constexpr unsigned light_types(std::initializer_list<LightType> types) {
    unsigned mask = 0;
    for (LightType t : types) mask |= 1u << static_cast<unsigned>(t);
    return mask;
}
inline constexpr unsigned kDeltaPositionLights = light_types({LightType::delta_position});
inline constexpr unsigned kInfiniteLights = light_types({LightType::infinite});
inline constexpr unsigned kAreaLights = light_types({LightType::area});
inline constexpr unsigned kAnyLight = ~0u;

namespace detail {
template <unsigned kTypes, std::size_t I>
constexpr bool light_in() {
    using T = std::variant_alternative_t<I, Light>;
    return ((kTypes >> static_cast<unsigned>(T::type)) & 1u) != 0;
}
template <unsigned kTypes, std::size_t I>
constexpr bool any_light_from() {
    if constexpr (I >= std::variant_size_v<Light>) return false;
    else return light_in<kTypes, I>() || any_light_from<kTypes, I + 1>();
}
}  // namespace detail

/// f(the light as its type), for a light whose type is one of kTypes (the caller knows: the
/// others are not tested for). A chain of index tests, inlined (as bsdf.h's visit_bsdf):
/// std::visit compiles to an out-of-line call through a table; a set with one member costs
/// no test at all. `light` may be const or not (then f may change it).
template <unsigned kTypes = kAnyLight, std::size_t I = 0, class LightRef, class F>
    requires std::is_same_v<std::remove_const_t<LightRef>, Light>
[[gnu::always_inline]] inline decltype(auto) visit_light_of(LightRef& light, F&& f) {
    if constexpr (!detail::light_in<kTypes, I>()) {
        return visit_light_of<kTypes, I + 1>(light, std::forward<F>(f));
    } else {
        if constexpr (detail::any_light_from<kTypes, I + 1>())
            if (light.index() != I) return visit_light_of<kTypes, I + 1>(light, std::forward<F>(f));
        return f(*std::get_if<I>(&light));
    }
}

inline LightType light_type(const Light& light) {
    return std::visit([](const auto& l) { return std::decay_t<decltype(l)>::type; }, light);
}

inline bool is_delta_light(const Light& light) {
    const LightType t = light_type(light);
    return t == LightType::delta_position || t == LightType::delta_direction;
}

inline float light_power(const Light& light) {
    return std::visit([](const auto& l) { return l.power(); }, light);
}

inline float light_spectral_power(const Light& light, float lambda_nm) {
    return std::visit([&](const auto& l) { return l.spectral_power(lambda_nm); }, light);
}

/// sample_li of the contract, in place: `ls` is a default LightSample.
[[gnu::always_inline]] inline bool light_sample_li(const Light& light, const LightSampleContext& ctx,
                                                   const SampledWavelengths& lambda, float u1, float u2,
                                                   LightSample& ls) {
    return visit_light_of(light, [&](const auto& l) { return l.sample_li(ctx, lambda, u1, u2, ls); });
}

/// sample_li as a value, for callers off the path loop.
inline std::optional<LightSample> light_sample_li(const Light& light, const LightSampleContext& ctx,
                                                  const SampledWavelengths& lambda, float u1, float u2) {
    LightSample ls;
    if (!light_sample_li(light, ctx, lambda, u1, u2, ls)) return std::nullopt;
    return ls;
}

/// pdf_li for a ray from ctx along wi that reached the light at `hit` (nullptr: the ray
/// escaped, which only infinite lights answer); 0 for delta lights.
inline float light_pdf_li(const Light& light, const LightSampleContext& ctx, const Vec3& wi, const Hit* hit) {
    return std::visit(
        [&](const auto& l) -> float {
            using T = std::decay_t<decltype(l)>;
            if constexpr (T::type == LightType::delta_position || T::type == LightType::delta_direction) return 0.f;
            else if constexpr (requires { l.pdf_li(ctx, wi); }) return l.pdf_li(ctx, wi);
            else return hit ? l.pdf_li(ctx, hit->p, hit->n) : 0.f;
        },
        light);
}

/// Radiance leaving an area light at p (the shape's normal n) along w: L of the contract.
/// For an area light only (what Hit::light names).
[[gnu::always_inline]] inline SampledSpectrum light_emitted(const Light& area_light, const Vec3& p, const Vec3& n,
                                                            const Vec3& w, const SampledWavelengths& lambda) {
    return visit_light_of<kAreaLights>(area_light, [&](const auto& l) { return l.L(p, n, w, lambda); });
}

/// Whether an area light emits along w at a point of normal n (its emitting sides).
[[gnu::always_inline]] inline bool light_emits_towards(const Light& area_light, const Vec3& n, const Vec3& w) {
    return visit_light_of<kAreaLights>(area_light, [&](const auto& l) { return emits_towards(l.two_sided, n, w); });
}

/// Whether a scene may make the light one-sided (it has a `bool two_sided`).
inline bool light_can_be_one_sided(const Light& light) {
    return std::visit([](const auto& l) { return requires(std::decay_t<decltype(l)> & m) { m.two_sided = false; }; },
                      light);
}

/// Makes the light one-sided (only its front emits); light_can_be_one_sided must hold.
inline void light_make_one_sided(Light& light) {
    std::visit(
        [](auto& l) {
            if constexpr (requires { l.two_sided = false; }) l.two_sided = false;
        },
        light);
}

/// Radiance arriving along an escaped ray of direction d, from an infinite light.
[[gnu::always_inline]] inline SampledSpectrum light_arriving(const Light& infinite_light, const Vec3& d,
                                                             const SampledWavelengths& lambda) {
    return visit_light_of<kInfiniteLights>(infinite_light, [&](const auto& l) { return l.arriving(d, lambda); });
}

/// Whether the light is a closed surface (seen from outside, only its outside).
inline bool light_is_closed(const Light& light) {
    return std::visit([](const auto& l) { return requires { requires std::decay_t<decltype(l)>::closed; }; }, light);
}

/// Whether the light has sample_area_facing (the caustic chains can sample it).
inline bool light_has_area_facing(const Light& light) {
    return std::visit(
        [](const auto& l) {
            return requires(Vec3 & v, float& f) { l.sample_area_facing(v, 0.f, 0.f, 0.f, v, v, f); };
        },
        light);
}

/// sample_area_facing of the contract; false for lights without it.
inline bool light_sample_area_facing(const Light& light, const Vec3& c, float R, float u1, float u2, Vec3& y,
                                     Vec3& n, float& pdf_area) {
    return std::visit(
        [&](const auto& l) {
            if constexpr (requires { l.sample_area_facing(c, R, u1, u2, y, n, pdf_area); })
                return l.sample_area_facing(c, R, u1, u2, y, n, pdf_area);
            else return false;
        },
        light);
}
/// pdf_area_facing of the contract; 0 for lights without it.
inline float light_pdf_area_facing(const Light& light, const Vec3& c, float R, const Vec3& y) {
    return std::visit(
        [&](const auto& l) {
            if constexpr (requires { l.pdf_area_facing(c, R, y); }) return l.pdf_area_facing(c, R, y);
            else return 0.f;
        },
        light);
}

/// Whether the light can start a light subpath (has sample_le).
inline bool light_can_start_subpath(const Light& light) {
    return std::visit(
        [](const auto& l) {
            return requires(const SampledWavelengths& lambda) { l.sample_le(lambda, 0.f, 0.f, 0.f, 0.f, 0.f, 0.f); };
        },
        light);
}

/// sample_le of the contract (the light's choice not included); nullopt for lights that
/// cannot start a subpath.
inline std::optional<LightOrigin> light_sample_le(const Light& light, const SampledWavelengths& lambda, float u1,
                                                  float u2, float u_side, float u3, float u4, float time) {
    return std::visit(
        [&](const auto& l) -> std::optional<LightOrigin> {
            if constexpr (requires { l.sample_le(lambda, u1, u2, u_side, u3, u4, time); })
                return l.sample_le(lambda, u1, u2, u_side, u3, u4, time);
            else return std::nullopt;
        },
        light);
}

/// Area density of an area light's sample_le point (0 for the other lights and the plane).
inline float light_pdf_le_pos(const Light& light) {
    return std::visit(
        [](const auto& l) -> float {
            if constexpr (requires { l.pdf_le_pos(); }) return l.pdf_le_pos();
            else return 0.f;
        },
        light);
}

/// Solid-angle density of sample_le's direction w from a light point of normal n (0 for
/// lights that cannot start a subpath).
inline float light_pdf_le_dir(const Light& light, const Vec3& n, const Vec3& w) {
    return std::visit(
        [&](const auto& l) -> float {
            if constexpr (requires { l.pdf_le_dir(n, w); }) return l.pdf_le_dir(n, w);
            else return 0.f;
        },
        light);
}

/// Where a delta-position light is at `time`.
[[gnu::always_inline]] inline Vec3 light_position_at(const Light& delta_light, float time) {
    return visit_light_of<kDeltaPositionLights>(delta_light, [&](const auto& l) { return l.position_at(time); });
}
/// A delta-position light's I_max(λ) and falloff(w) (its intensity along w is their product).
inline SampledSpectrum light_I_max(const Light& delta_light, const SampledWavelengths& lambda) {
    return visit_light_of<kDeltaPositionLights>(delta_light, [&](const auto& l) { return l.I_max(lambda); });
}
inline float light_falloff(const Light& delta_light, const Vec3& w) {
    return visit_light_of<kDeltaPositionLights>(delta_light, [&](const auto& l) { return l.falloff(w); });
}

}  // namespace spt

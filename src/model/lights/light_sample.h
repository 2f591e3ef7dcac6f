// What the light types answer with (the contract is in light.h).
#pragma once
#include <cstdint>

#include "core/vec3.h"
#include "spectral/sampled.h"

namespace spt {

/// What a light is, for the integrators: a point of space (point, spot), a direction (none
/// yet: a distant light), a surface that rays can hit (area lights, the infinite plane), or
/// what escaping rays see (the environment).
enum class LightType { delta_position, delta_direction, area, infinite };

/// The shading point a light is sampled from.
struct LightSampleContext {
    Vec3 p, p_err;
    Vec3 n;   ///< geometric normal (rays leave along it)
    Vec3 ns;  ///< shading normal turned to the side light is gathered on (wo's side)
    /// The BSDF there transmits through a non-delta lobe: light from both sides matters.
    bool both_sides = false;
};

/// A direction towards a light, sampled from a reference point (next-event estimation).
struct LightSample {
    Vec3 wi;             ///< unit, from the reference point towards the light
    SampledSpectrum L;   ///< radiance arriving along −wi (for a point light: I/r²)
    float pdf = 0.f;     ///< solid-angle density of wi (1 for a delta light)
    Vec3 p, p_err, n;    ///< the point on the light, its error bound and normal (zero: none)
    bool infinite = false;  ///< an infinite light: nothing to reach, only the way out to check
    /// An infinite plane: the shadow ray leaves along wi and must be clear for this distance
    /// (p is not needed); 0 for the other lights.
    float plane_distance = 0.f;
    /// An infinite plane's sample that crosses no other infinite plane on its way (the
    /// sampler drew it from the directions they leave open): the shadow ray may skip planes.
    bool past_planes = false;
    bool delta = false;     ///< a point light (no MIS: no other strategy finds it)
    /// A sphere of the scene that cannot occlude the point (the light's own sphere, when the
    /// point is on the side facing the reference point), or −1: the shadow ray may skip it.
    int unoccluding_sphere = -1;
    /// The light is flat (a quad): its own shapes cannot occlude the point, which lies in
    /// their plane, from a reference point off that plane.
    bool planar = false;
    /// The triangle of a mesh light the point is on (its index in the light's list, for an
    /// emission texture's (u, v)); 0 for the other lights.
    std::uint32_t triangle = 0;
};

/// A light subpath's origin (bidirectional integrators): the point, the first direction, the
/// emitted quantity and the densities that produced them.
struct LightOrigin {
    Vec3 p, p_err;
    Vec3 n;              ///< surface normal (zero for point and infinite lights)
    Vec3 w;              ///< emission direction (unit)
    SampledSpectrum Le;  ///< radiance (area, infinite) or intensity (point) along w
    /// Area density of the point, light choice included (1·choice if delta). Infinite
    /// lights: the planar density of the disk point, without the choice.
    float pdf_pos = 0;
    /// Solid-angle density of w. Infinite lights: with the choice probability.
    float pdf_dir = 0;
    bool delta_position = false;
    bool infinite = false;  ///< an infinite light: p is on its disk, w the direction it arrives in
    bool blocked = false;   ///< infinite: an infinite plane cuts the ray upstream of p
    int light = -1;            ///< index in Scene::lights
    std::uint32_t triangle = 0;  ///< as LightSample::triangle
};

/// Mean of a spectrum over 380–780 nm (41 samples): the "power" lights are chosen by.
template <typename SpectrumT>
float mean_over_visible(const SpectrumT& s) {
    double sum = 0;
    for (int i = 0; i <= 40; ++i) sum += s.eval(380.f + 10.f * static_cast<float>(i));
    return static_cast<float>(sum / 41.0);
}

}  // namespace spt

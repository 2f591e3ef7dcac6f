// Participating media for bidirectional path tracing (bdpt.h): free flight along a subpath's
// rays and transmittance along its connections, through homogeneous media and the shapes
// that only bound them (no surface), tracking the medium as the path tracer does
// (volumetric_path.h; the crossing step is surfaceless_crossing.h's): a subpath goes on in
// the medium it scattered in, and at a surface it reflects back into the medium it arrived
// in. Heterogeneous media are refused (integrator_choice.cpp): delta tracking's distance
// densities, which the MIS weights need, have no closed form.
//
// Densities (for the MIS weights): a scattering point at distance t of a segment through a
// homogeneous medium is drawn with the hero's density σt(λ0)·T(λ0, t) (per unit length), a
// surface behind media is reached with the hero's probability T(λ0) of passing them. Both
// multiply the solid-angle density of the ray's direction when it is turned into an area
// (volume) density: T on the segment's two ends alike (the same for either direction), σt(λ0)
// at a medium vertex in place of a surface's |cos|.
//
// Chromatic media (σt differs between the path's wavelengths): a segment of the path through
// such a medium keeps only the hero wavelength (SampledWavelengths::terminate_secondary, as a
// dispersive refraction does). This is a property of the path, whichever strategy made it (a
// sampled segment or a connection), so every strategy of a path agrees on it; the
// companions' free-flight ratios T(λ)/T(λ0) never arise, at the price of colour noise.
#pragma once
#include <optional>

#include "core/rng.h"
#include "render/integrator.h"

namespace spt {

/// What free flight along a ray found: a scattering point in a medium, a surface, or nothing.
struct FreeFlight {
    std::optional<Hit> hit;  ///< the surface reached (unset: escaped, or scattered)
    bool scattered = false;  ///< a real scattering event at p in `medium`
    Vec3 p;
    int medium = -1;              ///< at the scattering point, or where the ray met `hit`
    SampledSpectrum weight{1.f};  ///< throughput factor: the flight's value over its hero density
    float T_hero = 1.f;           ///< the hero's transmittance up to the event
    float sigma_t_hero = 0.f;     ///< σt(λ0) at the scattering point
    bool chromatic = false;       ///< crossed a medium whose σt differs between the wavelengths
};

/// Free flight along `ray` (unit direction, up to ray.t_max) from `medium`, through shapes
/// without a surface, at the scene's time 0 (media are never in motion-blurred scenes).
/// Distances are drawn with the hero's σt; a scattering event weighs σs(λ)·T(λ)/(σt(λ0)·T(λ0)),
/// passing T(λ)/T(λ0).
FreeFlight free_flight(const Scene& scene, Ray ray, int medium, const SampledWavelengths& lambda, Rng& rng,
                       PathStats& stats);

/// Transmittance of the straight segment `ray` from `medium` (0 when a surface blocks it),
/// and whether it crossed a chromatic medium (FreeFlight::chromatic).
struct Transmittance {
    SampledSpectrum T{1.f};
    bool chromatic = false;
};
Transmittance connection_transmittance(const Scene& scene, Ray ray, int medium, const SampledWavelengths& lambda,
                                       PathStats& stats);

/// The medium at `p` (a light subpath's first medium), tracked along the straight line from
/// the camera's origin `eye` (in the camera's medium) through the shapes without a surface
/// between. Only those bound media: a surface on the line (opaque, glass) may stand in a
/// medium without naming it as its exterior, so its declared sides are not taken (a light
/// inside a closed surface holding a medium is thus taken to be in the medium around it).
int medium_at(const Scene& scene, const Vec3& eye, const Vec3& p, PathStats& stats);

/// Whether σt differs between the path's wavelengths (of those it still carries).
bool is_chromatic(const SampledSpectrum& sigma_t, const SampledWavelengths& lambda);

}  // namespace spt

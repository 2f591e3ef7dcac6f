// Path tracing in scenes with participating media (pbrt-v4's VolPathIntegrator; Miller,
// Georgiev & Jarosz 2019, "A null-scattering path integral formulation of light transport").
// The renderer sends a path here only when the scene has media, so scenes without them run
// the surface loop and pay nothing for media. The per-vertex steps both share are in
// render/path_vertex.h.
//
// Chromatic media make free-flight distances depend on λ. Distances are sampled with the
// hero wavelength's majorant, and every wavelength's estimate is divided by the average
// over the wavelengths still carried of the density with which *that* wavelength, as hero,
// would have produced the same path (one-sample spectral MIS, Wilkie et al. 2014): the
// ratios r_u (unidirectional) and r_l (light sampling) below, relative to the hero's
// density. No companion is terminated, so the colour of a medium costs no colour noise.
// Light sampling and unidirectional sampling are combined by the balance heuristic, which
// falls out of the same ratios: an estimate divided by mean(r_u + r_l).
#pragma once
#include "render/integrator.h"

namespace spt {

/// Radiance arriving along `ray` (which starts in the camera's medium) at the path's
/// wavelengths, through media, surfaces and shapes without a surface.
SampledSpectrum trace_volumetric_path(const Scene& scene, const IntegratorSettings& settings, Ray ray,
                                      SampledWavelengths& lambda, Rng& rng, PathStats& stats);

/// Transmittance estimate of the straight segment `ray` (up to ray.t_max) starting in
/// `medium`, through shapes without a surface (any other surface blocks it: T = 0), with
/// the spectral-MIS ratios of the segment: r_u the density ratio of sampling it by free
/// flight (passing every collision as null), r_l that of the light strategy (ratio
/// tracking), each relative to the hero's density of what was sampled. Homogeneous media
/// contribute exp(−σt·d) in closed form (nothing sampled: r_l unchanged, r_u × T).
struct SegmentTransmittance {
    SampledSpectrum T{1.f}, r_u{1.f}, r_l{1.f};
};
SegmentTransmittance segment_transmittance(const Scene& scene, Ray ray, int medium, const SampledWavelengths& lambda,
                                           Rng& rng, PathStats& stats);

}  // namespace spt

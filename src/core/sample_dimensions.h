// Which random number of a path sample is which: the dimension layout of the low-discrepancy
// sampler (core/sobol_sampler.h). Each quantity has a fixed dimension, so a bounce's numbers
// come from the same dimensions whichever events (light samples, roulette) the bounces before
// it used; dimensions past the sampler's matrices come from a PCG stream.
#pragma once

namespace spt::dims {

// ---- The camera sample: dimensions 0 to 5 (the first two form a (0,2)-sequence, the best
// stratified pair, given to the pixel position where the image sees the stratification most) ----
inline constexpr int kPixelX = 0, kPixelY = 1;
inline constexpr int kWavelength = 2;      ///< the hero wavelength's uniform number
inline constexpr int kLensU = 3, kLensV = 4;  ///< thin lens only
inline constexpr int kTime = 5;            ///< motion blur only
inline constexpr int kCameraDims = 6;

// ---- Each bounce: a block of kBounceDims, at these offsets ----
inline constexpr int kLightChoice = 0;            ///< which light next-event estimation samples
inline constexpr int kLightU = 1, kLightV = 2;    ///< the point on it
inline constexpr int kBsdfLobe = 3;               ///< the BSDF's lobe (and Fresnel choice)
inline constexpr int kBsdfU = 4, kBsdfV = 5;      ///< the BSDF's direction
inline constexpr int kRoulette = 6;               ///< Russian roulette
inline constexpr int kBounceDims = 7;

/// Specular next-event estimation through glass spheres (render/caustic_nee.h) and off
/// reflecting ones (render/reflection_nee.h) draw their four numbers each (sphere, light,
/// point on it) from here, in that order: a dimension past every sampler's matrices,
/// so they come from the sample's PCG stream and the bounce blocks above stay as they were.
inline constexpr int kCausticNee = 1 << 20;

/// A fluorescent vertex's two numbers (reflect or re-emit, then the excitation wavelength),
/// from the PCG stream likewise: only scenes with fluorescence draw them.
inline constexpr int kFluorescence = 1 << 20;

/// The dimension of `offset` in the block of bounce `depth` (0: the first hit).
constexpr int bounce(int depth, int offset) { return kCameraDims + depth * kBounceDims + offset; }

}  // namespace spt::dims

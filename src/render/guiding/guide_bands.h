// The wavelength bands of a spectral guiding field: the four quarters of the visible
// wavelength density (spectral/sampled.h). A path's hero set is stratified over those same
// quarters (companion k at u + k/4), so every path that keeps its companions brings one
// radiance value to each band, and the hero's band is the one its guided direction is drawn
// from.
#pragma once
#include "spectral/sampled.h"

namespace spt {

inline constexpr int kGuideBands = kLambdaCount;

/// The wavelengths between the bands, through the same inverse CDF that draws the
/// wavelengths: band k holds the λ drawn from u in [k/4, (k+1)/4). (At namespace scope, not a
/// function's static, so the hot loop reads them without an initialisation guard.)
inline const float kGuideBandEdges[kGuideBands - 1] = {
    sample_visible_wavelength(0.25f), sample_visible_wavelength(0.5f), sample_visible_wavelength(0.75f)};

/// The band of a wavelength (0 to kGuideBands − 1).
inline int guide_band(float lambda_nm) {
    int band = 0;
    for (float edge : kGuideBandEdges) band += lambda_nm >= edge ? 1 : 0;
    return band;
}

}  // namespace spt

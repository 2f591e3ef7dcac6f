// Automatic exposure for the PNG: a stated statistic of the image's luminance is brought to
// middle grey. The linear outputs are never scaled.
#pragma once
#include "io/image.h"
#include "spectral/color_space.h"

namespace spt {

/// Middle grey: the photographic "key" of an average scene (Reinhard et al. 2002, §2).
inline constexpr double kAutoExposureKey = 0.18;

/// Stops that take the median luminance of the image's non-black pixels to kAutoExposureKey
/// (black pixels, e.g. an empty background, are left out so they cannot push the exposure
/// up without bound). Luminance is Y of the image's RGB in `space` (its to_xyz row 1); the
/// median of an even count is the mean of the middle two. 0 when no pixel is above black;
/// limited to [-20, 20] like --exposure.
double auto_exposure_stops(const Image& image, const ColorSpace& space);

}  // namespace spt

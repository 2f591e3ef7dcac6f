// Spectra of RGB texels (image textures), binned at load time. A reflectance texel is the
// project's RGB fit (rgb_to_spectrum: under D65 it has the texel's colour). An emission
// texel is that fit times the D65 illuminant normalised to Y = 1, with the colour's largest
// component factored out first (pbrt-v4's RGBIlluminantSpectrum): it keeps the illuminant's
// white, so (1, 1, 1) emits D65 of luminance 1 and any texel's radiance has the XYZ of its
// linear sRGB colour (a directly seen emission texture renders as its colours).
#pragma once
#include <array>
#include <vector>

namespace spt {

enum class TexelUse { reflectance, emission };

/// Bin values (project_onto_bins, `bins` bins) of the spectrum of linear sRGB `rgb`.
/// Throws std::invalid_argument for components that are not finite, negative, or (a
/// reflectance) above 1; std::runtime_error if the fit does not converge.
std::vector<float> rgb_texel_bins(const std::array<float, 3>& rgb, TexelUse use, int bins);

/// The D65 illuminant at λ (nm), normalised so that its luminance Y is 1.
double d65_unit_luminance(double lambda_nm);

}  // namespace spt

// RGB reflectance → smooth spectrum. The spectrum is SpectrumSource::rgb_sigmoid: the
// algebraic sigmoid s(x) = ½ + x/(2√(1+x²)) of a quadratic x = c0·t² + c1·t + c2 in
// t = (λ − 360 nm)/470 nm (Jakob & Hanika 2019, "A low-dimensional function space for
// efficient spectral upsampling"). It lies in (0, 1) for any coefficients, so it is always a
// valid reflectance. The three coefficients are solved (damped Gauss-Newton in CIELAB, with
// continuation from grey) so that the spectrum lit by CIE D65 has the CIE 1931 XYZ of the
// linear sRGB colour, whose white is the D65 of the tables (so grey stays exactly grey).
// Equal components give a constant spectrum, which reproduces them exactly.
#pragma once
#include <array>

#include "spectral/cie.h"
#include "spectral/spectrum_source.h"

namespace spt {

/// Smooth reflectance of linear sRGB `rgb` (each in [0, 1]); throws std::invalid_argument for
/// values outside [0, 1] or not finite, std::runtime_error if the fit does not converge.
/// Fits are cached.
SpectrumSource rgb_to_spectrum(const std::array<double, 3>& rgb);

/// The fit behind rgb_to_spectrum from a given start instead of its continuation from grey:
/// at most `max_iterations` damped Gauss-Newton steps move the rgb_sigmoid coefficients `c`
/// towards the CIELAB of linear sRGB `rgb` (finite) under D65. Returns the final ΔE*ab residual;
/// never throws (a start far from the solution may leave a large residual: start from a near
/// solution, as a table built by continuation does).
double refine_rgb_sigmoid(const std::array<double, 3>& rgb, std::array<double, 3>& c, int max_iterations);

/// XYZ of a reflectance lit by D65 (1-nm sums over 360–830 nm), Y = 1 for a perfect white.
Xyz reflectance_xyz_d65(const SpectrumSource& reflectance);

/// Linear sRGB (primaries of IEC 61966-2-1, white = the tabulated D65) to XYZ and back.
Xyz linear_srgb_to_xyz_d65(const std::array<double, 3>& rgb);
std::array<double, 3> xyz_d65_to_linear_srgb(const Xyz& xyz);

/// CIELAB of XYZ relative to the tabulated D65 white.
std::array<double, 3> xyz_d65_to_lab(const Xyz& xyz);

}  // namespace spt

// White balance: chromatic adaptation by the Bradford transform (Lam 1985; the von Kries
// scaling of Bradford's sharpened cone responses, as in colour-science's
// matrix_chromatic_adaptation_VonKries(..., transform='Bradford')), and the white points it
// adapts from: named CIE illuminants or a correlated colour temperature.
#pragma once
#include <array>
#include <optional>
#include <string>

#include "spectral/color_space.h"

namespace spt {

using Chromaticity = std::array<double, 2>;  ///< CIE 1931 xy

/// Bradford's XYZ → sharpened-cone (ρ, γ, β) matrix.
inline constexpr Matrix3 kBradford = {{{0.8951, 0.2664, -0.1614},
                                       {-0.7502, 1.7135, 0.0367},
                                       {0.0389, -0.0685, 1.0296}}};

/// XYZ → XYZ matrix that takes colours seen under the white `source` to how they look under
/// `target` (both as xy with Y = 1, so a neutral keeps its luminance):
/// M⁻¹ · diag(M·target / M·source) · M with M = kBradford.
Matrix3 bradford_adaptation(const Chromaticity& source, const Chromaticity& target);

/// The colour space whose XYZ → RGB matrix first adapts `source` to the space's own white:
/// a surface of flat reflectance under `source` develops to R = G = B.
ColorSpace white_balanced(const ColorSpace& space, const Chromaticity& source);

/// CIE 1931 2° xy of a named illuminant (case-insensitive): A, D50, D55, D65, D75, E, F2, F11
/// (FL2, FL11 too). The CIE published values (CIE 15:2004 tables), as colour-science 0.4.7
/// tabulates them in CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]; D65 is
/// (0.3127, 0.3290), the sRGB white. nullopt for other names.
std::optional<Chromaticity> illuminant_xy(const std::string& name);

/// xy of the Planckian radiator at `kelvin`: Planck's law with the CIE's c2 = 1.4388e-2 m·K
/// (CIE 15:2004; so 2856 K is illuminant A) weighted by the CIE 1931 2° table at 1 nm over
/// 360-830 nm (spectra/cie_1931_2deg.csv), summed.
Chromaticity planckian_xy(double kelvin);

/// xy of CIE daylight at correlated colour temperature `kelvin` (4000 to 25000 K): CIE 15:2004
/// eq. 3.3 and 3.4, with `kelvin` used as given (D65 is at 6504 K).
Chromaticity daylight_xy(double kelvin);

inline constexpr double kMinWhiteKelvin = 1000, kMaxWhiteKelvin = 25000;
/// A correlated colour temperature's white: Planckian below 4000 K, CIE daylight from 4000 K
/// (where the two loci are 0.007 apart in y: the daylight locus lies above the Planckian).
Chromaticity cct_xy(double kelvin);

/// "A", "D65", ... or a temperature "3200K" / "3200" (1000 to 25000): the white's xy, or
/// nullopt when the text is neither.
std::optional<Chromaticity> parse_white(const std::string& text);

}  // namespace spt

// How many bins a light's spectrum needs. Bins of 25 nm (16 over 380–780 nm) hold smooth
// illuminants (daylight, tungsten) well, but not lamps whose power sits in lines a few nm
// wide (fluorescent tubes, some LEDs): the bins spread each line over its bin, and colours
// under the lamp shift (under CIE F11 the ColorChecker's mean error at 16 bins is 7.7
// ΔE2000, against 0.12 under D65; validation/results/color_accuracy.md).
//
// The measure: the ColorChecker's 24 patches lit by the light, their CIE 1931 XYZ from the
// binned light and binned reflectances (as the renderer evaluates them) against the exact
// spectra, both summed at 1 nm over 360–830 nm, as CIELAB (1976) differences relative to the
// light's exact white; the mean over the patches. A light needs the fewest bins, doubling
// from the default, at which that mean is no larger than daylight's (D65) at the default bins,
// times 1.5: what the default promises under daylight, kept under any light. The cost: the
// time per sample grows little with the bin count (binned look-ups are the same at any N).
#pragma once
#include "spectral/spectrum.h"

namespace spt {

/// Mean CIELAB ΔE (1976) of the 24 ColorChecker patches under `light` at `bins` bins against
/// exact spectra (header comment).
double binned_colour_error(const SpectrumSource& light, int bins);

/// The fewest bins (the default doubled, up to 256) that render colours under `light` as
/// accurately as the default renders them under D65 (header comment); the default for
/// smooth spectra.
int bins_for_light(const SpectrumSource& light);

}  // namespace spt

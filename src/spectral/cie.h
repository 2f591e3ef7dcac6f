// CIE 1931 2° colour matching functions (from spectra/cie_1931_2deg.csv): the film's default
// observer, normalised so that a constant spectrum of 1 gives Y = 1.
#pragma once
#include "spectral/observer.h"
#include "spectral/spectrum_source.h"

namespace spt {

struct Cie1931 {
    /// The CIE 1931 2° standard observer, loaded once from the table compiled into the program.
    static const Observer& get();
};

/// Luminance Y of a spectrum relative to a constant spectrum of 1 (which gives 1): the 1-nm
/// sum of s(λ)·ȳ(λ) over 360–830 nm divided by that of ȳ, as the film measures it. What a
/// pbrt-v4 file's "scale" of a light spectrum is (pbrt-v4 normalises light spectra to Y = 1).
double luminance(const SpectrumSource& s);

}  // namespace spt

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

/// Luminance of a spectrum: its CIE Y relative to an equal-energy spectrum of 1,
/// Σ ȳ(λ)·s(λ) / Σ ȳ(λ) over the table's rows (360–830 nm at 1 nm), the film's normalisation.
double cie_luminance(const SpectrumSource& s);

}  // namespace spt

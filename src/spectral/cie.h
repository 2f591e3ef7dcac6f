// CIE 1931 2° colour matching functions (from spectra/cie_1931_2deg.csv): the film's default
// observer, normalised so that a constant spectrum of 1 gives Y = 1.
#pragma once
#include "spectral/observer.h"

namespace spt {

struct Cie1931 {
    /// The CIE 1931 2° standard observer, loaded once from the table compiled into the program.
    static const Observer& get();
};

}  // namespace spt

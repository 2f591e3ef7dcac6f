// Spectra in scene files: a number, an [r, g, b] reflectance, or an object with a "type"
// (analytic sources, tables, CIE illuminants, ColorChecker patches); see scenes/README.md.
#pragma once
#include <string>

#include "scene/param_checker.h"
#include "spectral/spectrum.h"

namespace spt {

/// What a spectrum stands for, which sets its valid range.
enum class SpectrumUse {
    Reflectance,  ///< [0, 1]
    Emission,     ///< finite, >= 0 (radiance, intensity)
    Index,        ///< index of refraction in [1, 100]
    ConductorIndex,  ///< real part η of a conductor's complex index, in [0.001, 100]
    Extinction,      ///< imaginary part k of a complex index, in [0, 100]
};

class SpectrumParser : public ParamChecker {
public:
    SpectrumParser(const SourceFiles& files, SpectralResolution resolution)
        : ParamChecker(files), m_resolution(resolution) {}

    /// The spectrum described by `v`, checked at every nanometre from 360 to 830 nm for its
    /// use; `what` names it in messages. Throws LocatedError.
    Spectrum spectrum(const ParamValue& v, const std::string& what, SpectrumUse use) const;
    /// A spectrum from a source made elsewhere (a named table), checked as spectrum() does;
    /// errors point at `pos`.
    Spectrum spectrum_from(const SpectrumSource& source, SourcePos pos, const std::string& what, SpectrumUse use) const;

    /// The exact, unchecked source `v` describes (what spectrum() bins), for code that needs
    /// its values at any wavelength (the pbrt-v4 writer tabulates it). Throws LocatedError.
    SpectrumSource spectrum_source(const ParamValue& v, const std::string& what) const;

private:
    SpectralResolution m_resolution;

    SpectrumSource rgb(const ParamValue& v, const std::string& what, double scale) const;
};

}  // namespace spt

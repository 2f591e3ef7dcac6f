// Participating media in scene descriptions: the "media" section (scenes/README.md); the
// density types and their create functions are listed once, in medium_parser.cpp.
#pragma once
#include <string>

#include "model/media/medium.h"
#include "scene/scene_description.h"
#include "scene/spectrum_parser.h"

namespace spt {

class MediumParser : public ParamChecker {
public:
    MediumParser(const SourceFiles& files, const SpectrumParser& spectra, const RelativeFileReader& read_relative)
        : ParamChecker(files), m_spectra(spectra), m_read_relative(read_relative) {}

    /// The medium `name` defined by `def`: {"type": "homogeneous" | "grid" | "height_fog",
    /// "sigma_a", "sigma_s", "scale", "g", and the type's own keys}. Throws LocatedError.
    Medium medium(const std::string& name, const ParamValue& def) const;

    /// How the density types' create functions read the files a medium names.
    const RelativeFileReader& read_relative() const { return m_read_relative; }

private:
    const SpectrumParser& m_spectra;
    const RelativeFileReader& m_read_relative;
};

}  // namespace spt

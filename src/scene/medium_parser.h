// Participating media in scene files: the "media" section (scenes/README.md).
#pragma once
#include <string>

#include "model/media/medium.h"
#include "scene/scene_loader.h"
#include "scene/spectrum_parser.h"

namespace spt {

class MediumParser : public JsonChecker {
public:
    MediumParser(const std::string& origin, const SpectrumParser& spectra, const RelativeFileReader& read_relative)
        : JsonChecker(origin), m_spectra(spectra), m_read_relative(read_relative) {}

    /// The medium `name` defined by `def`: {"type": "homogeneous" | "grid" | "height_fog",
    /// "sigma_a", "sigma_s", "scale", "g", and the type's own keys}. Throws LocatedError.
    Medium medium(const std::string& name, const JsonValue& def) const;

private:
    const SpectrumParser& m_spectra;
    const RelativeFileReader& m_read_relative;
};

}  // namespace spt

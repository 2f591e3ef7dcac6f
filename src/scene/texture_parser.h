// The scene file's "textures" (name → definition) and the values that name one,
// {"texture": NAME} (with "scale" for emission); see scenes/README.md. A definition is built
// when a value first names it, once per use (reflectance, emission or number), since the
// use decides how its values become spectra.
#pragma once
#include <map>
#include <optional>
#include <string>
#include <tuple>

#include "scene/param_checker.h"
#include "scene/scene.h"
#include "scene/scene_description.h"
#include "scene/spectrum_parser.h"

namespace spt {

enum class TextureUse { reflectance, emission, number };

class TextureParser : public ParamChecker {
public:
    TextureParser(const SourceFiles& files, SpectralResolution resolution, const SpectrumParser& spectra,
                  const RelativeFileReader& read_relative, Scene& scene)
        : ParamChecker(files), m_resolution(resolution), m_spectra(spectra), m_read_relative(read_relative),
          m_scene(scene) {}

    /// Reads the top-level "textures" object (checked when a value names a texture).
    void definitions(const ParamValue& v);

    /// True when `v` names a texture ({"texture": ...}) rather than giving a value.
    static bool is_binding(const ParamValue& v) { return v.is_object() && v.peek("texture"); }

    /// The index in Scene::textures of the texture `v` names, built for `use`; `what` names
    /// the value in messages. Throws LocatedError.
    int bind(const ParamValue& v, const std::string& what, TextureUse use);

    /// Each bin's largest value over the texture's entries, as a spectrum: what a textured
    /// parameter holds at load time (see Material::textures).
    Spectrum envelope(int texture) const;
    /// The mean of a spectral texture over its (u, v) square (an image's texels, a
    /// procedural texture's area): an emitter's power for light selection.
    Spectrum mean(int texture) const;
    /// The largest number a float texture gives.
    float max_number(int texture) const;

private:
    SpectralResolution m_resolution;
    const SpectrumParser& m_spectra;
    const RelativeFileReader& m_read_relative;
    Scene& m_scene;
    const ParamValue* m_definitions = nullptr;
    std::map<std::tuple<std::string, TextureUse, double>, int> m_built;

    int bins(TextureUse use) const;
    /// A spectrum whose bins are `bins` (any count; the source interpolates the bin centres).
    Spectrum spectrum_of_bins(std::vector<float> bins) const;
    Texture build(const std::string& name, const ParamValue& def, TextureUse use, double scale) const;
    /// The value table entry of a procedural texture's value `v` (a spectrum or a number).
    void add_value(Texture& t, const ParamValue& v, const std::string& what, TextureUse use, double scale) const;
    void image(Texture& t, const ParamValue& def, const std::string& what, TextureUse use, double scale) const;
};

}  // namespace spt

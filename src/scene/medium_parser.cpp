// The "media" section of scene files: each medium checked where it is read.
#include "scene/medium_parser.h"

#include <algorithm>
#include <memory>

#include "io/density_grid_reader.h"

namespace spt {

Medium MediumParser::medium(const std::string& name, const JsonValue& def) const {
    const std::string what = "medium " + quote_text(name);
    object(def, what);
    Medium m;
    m.name = name;
    const std::string& type = string(required(def, "type", what), what + " type");
    const std::vector<std::string> types = {"homogeneous", "grid", "height_fog"};
    if (type == "homogeneous") {
        check_keys(def, what, {"type", "sigma_a", "sigma_s", "scale", "g"});
        m.density = UniformDensity{};
    } else if (type == "height_fog") {
        check_keys(def, what, {"type", "sigma_a", "sigma_s", "scale", "g", "up", "base", "scale_height", "top"});
        HeightFogDensity h;
        if (const JsonValue* up = def.find("up")) h.up = normalize(direction(*up, what + " up"));
        if (const JsonValue* b = def.find("base"))
            h.base = static_cast<float>(number_in(*b, what + " base", -kMaxSceneCoordinate, kMaxSceneCoordinate));
        h.scale_height = static_cast<float>(
            number_in(required(def, "scale_height", what), what + " scale_height", 0, kMaxSceneCoordinate, true));
        h.top = h.base + 20.f * h.scale_height;  // density e^−20 there
        if (const JsonValue* t = def.find("top")) {
            h.top = static_cast<float>(number_in(*t, what + " top", -kMaxSceneCoordinate, kMaxSceneCoordinate));
            if (!(h.top > h.base)) fail(t->pos(), what + " top is not above base; expected top > base");
        }
        m.density = h;
    } else if (type == "grid") {
        check_keys(def, what, {"type", "sigma_a", "sigma_s", "scale", "g", "file", "min", "max"});
        const JsonValue& fv = required(def, "file", what);
        const std::string& file = string(fv, what + " file");
        std::string contents, display, error;
        if (file.empty() || !m_read_relative(file, contents, display, error))
            fail(fv.pos(), "cannot read density grid " + quote_text(file) + (error.empty() ? "" : ": " + error) +
                               "; expected a grid file path relative to the scene file");
        GridDensity g;
        auto grid = std::make_shared<DensityGrid>(parse_density_grid(contents, display));
        g.max_value = *std::max_element(grid->values.begin(), grid->values.end());
        g.grid = std::move(grid);
        g.lo = point(required(def, "min", what), what + " min");
        g.hi = point(required(def, "max", what), what + " max");
        if (!(g.lo.x < g.hi.x && g.lo.y < g.hi.y && g.lo.z < g.hi.z))
            fail(def.find("max")->pos(), what + " max is not above min on every axis; expected min < max");
        m.density = std::move(g);
    } else {
        fail(def.find("type")->pos(), "unknown medium type " + quote_text(type) + "." + suggestion(type, types) +
                                          " Expected one of: " + join(types));
    }
    m.sigma_a = m_spectra.spectrum(required(def, "sigma_a", what), what + " sigma_a", SpectrumUse::Emission);
    m.sigma_s = m_spectra.spectrum(required(def, "sigma_s", what), what + " sigma_s", SpectrumUse::Emission);
    if (const JsonValue* s = def.find("scale")) m.scale = static_cast<float>(number_in(*s, what + " scale", 0, 1e12));
    if (const JsonValue* g = def.find("g")) m.phase.g = static_cast<float>(number_in(*g, what + " g", -0.999, 0.999));
    return m;
}

}  // namespace spt

// The media of a scene description: each density type's create function and the table of
// types, each medium checked where it is read.
#include "scene/medium_parser.h"

#include <algorithm>
#include <memory>

#include "io/density_grid_reader.h"

namespace spt {

namespace {

// Each density type's create function reads its own keys; MediumParser::medium reads those of
// every medium ("type", "sigma_a", "sigma_s", "scale", "g").

DensityField homogeneous(const MediumParser&, const ParamValue&, const std::string&) { return UniformDensity{}; }

DensityField height_fog(const MediumParser& p, const ParamValue& def, const std::string& what) {
    HeightFogDensity h;
    MediumParser::look_up(def, {"up", "top"});
    if (const ParamValue* up = def.find("up")) h.up = normalize(p.direction(*up, what + " up"));
    if (const ParamValue* b = def.find("base"))
        h.base = static_cast<float>(p.number_in(*b, what + " base", -kMaxSceneCoordinate, kMaxSceneCoordinate));
    h.scale_height = static_cast<float>(
        p.number_in(p.required(def, "scale_height", what), what + " scale_height", 0, kMaxSceneCoordinate, true));
    h.top = h.base + 20.f * h.scale_height;  // density e^−20 there
    if (const ParamValue* t = def.find("top")) {
        h.top = static_cast<float>(p.number_in(*t, what + " top", -kMaxSceneCoordinate, kMaxSceneCoordinate));
        if (!(h.top > h.base)) p.fail(t->pos(), what + " top is not above base; expected top > base");
    }
    return h;
}

DensityField grid(const MediumParser& p, const ParamValue& def, const std::string& what) {
    MediumParser::look_up(def, {"min", "max"});
    const ParamValue& fv = p.required(def, "file", what);
    const std::string& file = p.string(fv, what + " file");
    std::string contents, display, error;
    if (file.empty() || !p.read_relative()(file, contents, display, error))
        p.fail(fv.pos(), "cannot read density grid " + quote_text(file) + (error.empty() ? "" : ": " + error) +
                             "; expected a grid file path relative to the scene file");
    GridDensity g;
    auto values = std::make_shared<DensityGrid>(parse_density_grid(contents, display));
    g.max_value = *std::max_element(values->values.begin(), values->values.end());
    g.grid = std::move(values);
    g.lo = p.point(p.required(def, "min", what), what + " min");
    g.hi = p.point(p.required(def, "max", what), what + " max");
    if (!(g.lo.x < g.hi.x && g.lo.y < g.hi.y && g.lo.z < g.hi.z))
        p.fail(def.find("max")->pos(), what + " max is not above min on every axis; expected min < max");
    return g;
}

/// A density type: its name in scene descriptions and its create function.
struct MediumType {
    const char* name;
    DensityField (*create)(const MediumParser& p, const ParamValue& def, const std::string& what);
};

/// Every density type, one row each, in the order messages list them.
const MediumType kMediumTypes[] = {
    {"homogeneous", homogeneous},
    {"grid", grid},
    {"height_fog", height_fog},
};

}  // namespace

Medium MediumParser::medium(const std::string& name, const ParamValue& def) const {
    const std::string what = "medium " + quote_text(name);
    object(def, what);
    Medium m;
    m.name = name;
    const std::string& type = string(required(def, "type", what), what + " type");
    const MediumType* found = nullptr;
    for (const MediumType& t : kMediumTypes)
        if (type == t.name) found = &t;
    if (!found) {
        std::vector<std::string> types;
        for (const MediumType& t : kMediumTypes) types.emplace_back(t.name);
        fail(def.find("type")->pos(), "unknown medium type " + quote_text(type) + "." + suggestion(type, types) +
                                          " Expected one of: " + join(types));
    }
    m.density = found->create(*this, def, what);
    look_up(def, {"sigma_a", "sigma_s"});
    m.sigma_a = m_spectra.spectrum(required(def, "sigma_a", what), what + " sigma_a", SpectrumUse::Emission);
    m.sigma_s = m_spectra.spectrum(required(def, "sigma_s", what), what + " sigma_s", SpectrumUse::Emission);
    if (const ParamValue* s = def.find("scale")) m.scale = static_cast<float>(number_in(*s, what + " scale", 0, 1e12));
    if (const ParamValue* g = def.find("g")) m.phase.g = static_cast<float>(number_in(*g, what + " g", -0.999, 0.999));
    all_read(def, what + " of type " + quote_text(type));
    return m;
}

}  // namespace spt

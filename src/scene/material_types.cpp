// The material types' create functions and their table, and the checks of the microfacet
// types' parameters.
#include "scene/material_types.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "scene/scene.h"
#include "scene/texture_parser.h"
#include "spectral/dye_catalog.h"
#include "spectral/metal_catalog.h"

namespace spt {

namespace {

/// Anisotropic roughness is a conductor's ("roughness_u", "roughness_v"); on the other types
/// those keys, and "anisotropy" anywhere, are errors that say so.
void reject_anisotropy(const SpectrumParser& p, const ParamValue& def, const std::string& type, const std::string& what) {
    if (const ParamValue* v = def.peek("anisotropy"))
        p.fail(v->pos(), what + " anisotropy: anisotropic roughness is given by \"roughness_u\" and \"roughness_v\" "
                                "(conductors only); expected those instead");
    if (type == "conductor") return;
    for (const char* key : {"roughness_u", "roughness_v"})
        if (const ParamValue* v = def.peek(key))
            p.fail(v->pos(), what + " " + key + ": anisotropic roughness is available for conductors only; expected "
                                        "one number \"roughness\" in [0, 1]");
}

/// "roughness_u", "roughness_v" (both or neither, not with "roughness"): α along the surface's
/// dp/du and across it, each a number in [0.001, 1].
void anisotropic_roughness(const SpectrumParser& p, const ParamValue& def, const std::string& what,
                           const FloatParameter& number, ConductorBsdf& c) {
    const ParamValue *ru = def.find("roughness_u"), *rv = def.find("roughness_v");
    if (!ru && !rv) return;
    if (!ru || !rv)
        p.fail((ru ? ru : rv)->pos(), what + " has only one of \"roughness_u\" and \"roughness_v\"; expected both "
                                             "(α along the surface's u direction and across it)");
    if (const ParamValue* r = def.find("roughness"))
        p.fail(r->pos(), what + " has both \"roughness\" and \"roughness_u\"/\"roughness_v\"; expected one of them");
    for (const ParamValue* v : {ru, rv})
        if (!v->is_number())
            p.fail(v->pos(), what + " roughness_u and roughness_v must be numbers (they cannot be textures); expected "
                                    "a number in [0.001, 1]");
    c.aniso.alpha_x = number(*ru, "roughness_u", what + " roughness_u", 1e-3, 1, false);
    c.aniso.alpha_y = number(*rv, "roughness_v", what + " roughness_v", 1e-3, 1, false);
    c.ggx.alpha = std::max(c.aniso.alpha_x, c.aniso.alpha_y);  // rough: the flags
}

GgxDistribution roughness(const SpectrumParser& p, const ParamValue& def, const std::string& what,
                          const FloatParameter& number) {
    GgxDistribution g;
    const ParamValue* v = def.find("roughness");
    if (!v) return g;
    if (v->is_array())
        p.fail(v->pos(), what + " roughness is an array; expected one number in [0, 1] (a conductor's anisotropic "
                                "roughness: \"roughness_u\" and \"roughness_v\")");
    g.alpha = number(*v, "roughness", what + " roughness", 0, 1, false);
    return g;
}

/// "film": {"thickness_nm": d, "ior": spectrum}; absent or d = 0 means no film.
ThinFilm film(const SpectrumParser& p, const ParamValue& def, const std::string& what, const FloatParameter& number) {
    ThinFilm f;
    const ParamValue* v = def.find("film");
    if (!v) return f;
    const std::string w = what + " film";
    p.object(*v, w);
    f.thickness_nm = number(p.required(*v, "thickness_nm", w), "film thickness_nm", w + " thickness_nm", 0, 1e5, false);
    f.eta = p.spectrum(p.required(*v, "ior", w), w + " ior", SpectrumUse::Index);
    p.all_read(*v, w);
    return f;
}

ConductorBsdf conductor(const SpectrumParser& p, const ParamValue& def, const std::string& what,
                        const FloatParameter& number) {
    ConductorBsdf c;
    const ParamValue* metal = def.find("metal");
    const ParamValue *eta = def.find("eta"), *k = def.find("k");
    if (metal && (eta || k))
        p.fail(def.pos(), what + " has both \"metal\" and \"eta\"/\"k\"; expected one of them");
    if (metal) {
        const std::string& name = p.string(*metal, what + " metal");
        const std::optional<MetalInfo> m = find_metal(name);
        if (!m)
            p.fail(metal->pos(), "unknown metal " + quote_text(name) + "." + suggestion(name, metal_names()) +
                                     " Expected one of: " + join(metal_names()));
        c.eta = p.spectrum_from(m->eta, metal->pos(), what + " eta (" + m->symbol + ")", SpectrumUse::ConductorIndex);
        c.k = p.spectrum_from(m->k, metal->pos(), what + " k (" + m->symbol + ")", SpectrumUse::Extinction);
    } else {
        if (!eta || !k) {
            p.misspelt(def, what, {"metal", "eta", "k"});
            p.fail(def.pos(), what + " has no \"metal\" and not both \"eta\" and \"k\"; expected \"metal\": \"Au\" "
                                     "(or Ag, Cu, Al) or both spectra");
        }
        c.eta = p.spectrum(*eta, what + " eta", SpectrumUse::ConductorIndex);
        c.k = p.spectrum(*k, what + " k", SpectrumUse::Extinction);
    }
    c.ggx = roughness(p, def, what, number);
    anisotropic_roughness(p, def, what, number, c);
    c.film = film(p, def, what, number);
    return c;
}

DielectricBsdf dielectric(const SpectrumParser& p, const ParamValue& def, const std::string& what,
                          const FloatParameter& number) {
    DielectricBsdf d;
    d.eta = p.spectrum(p.required(def, "ior", what), what + " ior", SpectrumUse::Index);
    d.ggx = roughness(p, def, what, number);
    d.film = film(p, def, what, number);
    return d;
}

PlasticBsdf plastic(const SpectrumParser& p, const ParamValue& def, const std::string& what,
                    const FloatParameter& number, const ReflectanceParameter& reflectance) {
    // A textured kd: the lobe choice reads the mean of its envelope (make_plastic), the same
    // number in sampling and pdf, so the estimator stays unbiased.
    Spectrum kd = reflectance(p.required(def, "kd", what), "kd");
    // The coat index: any spectrum form; one varying with λ gives each wavelength its own coat
    // (plastic.h), its albedo table built here over the index's range.
    Spectrum eta(SpectrumSource::constant(1.5), SpectralResolution{});
    const ParamValue* ior = def.find("ior");
    if (ior) eta = p.spectrum(*ior, what + " ior", SpectrumUse::Index);
    // A textured roughness (an object {"texture": NAME}) reads the coat's albedo over α.
    const ParamValue* r = def.find("roughness");
    const bool textured_roughness = r && r->is_object();
    if (!eta.is_constant()) {
        if (!(eta.min_value() >= 1.f && eta.max_value() <= 100.f))
            p.fail(ior->pos(), what + " ior goes outside [1, 100] between 360 and 830 nm; expected a coat index in "
                                      "[1, 100] at every wavelength");
        if (textured_roughness)
            p.fail(r->pos(), what + " has a textured roughness and an ior that varies with wavelength (its coat's "
                                    "albedo would need a table over both); expected a constant roughness with a "
                                    "dispersive coat, or a constant ior with a textured roughness");
    }
    return make_plastic(std::move(kd), eta, roughness(p, def, what, number).alpha, textured_roughness);
}

ThinSheetBsdf thin_sheet(const SpectrumParser& p, const ParamValue& def, const std::string& what,
                        const FloatParameter& number) {
    ThinSheetBsdf t;
    t.film.thickness_nm = number(p.required(def, "thickness_nm", what), "thickness_nm", what + " thickness_nm", 0, 1e5, true);
    t.film.eta = p.spectrum(p.required(def, "ior", what), what + " ior", SpectrumUse::Index);
    return t;
}

Bsdf diffuse(const MaterialParams& p) {
    DiffuseBsdf d;
    if (const ParamValue* x = p.def.find("kd")) d.kd = p.reflectance(*x, "kd");
    return d;
}

Bsdf lobes(const MaterialParams& p) {
    const SpectrumParser& s = p.spectra;
    LobeMixBsdf b;
    if (const ParamValue* x = p.def.find("kd")) b.kd = p.reflectance(*x, "kd");
    if (const ParamValue* x = p.def.find("ks")) b.ks = p.reflectance(*x, "ks");
    if (const ParamValue* x = p.def.find("kt")) b.kt = p.reflectance(*x, "kt");
    if (const ParamValue* x = p.def.find("ior")) {
        if (TextureParser::is_binding(*x)) s.fail(x->pos(), p.what + " ior cannot be bound to a texture; expected a spectrum");
        b.eta = s.spectrum(*x, p.what + " ior", SpectrumUse::Index);
    }
    if (b.has_transmission() && !p.def.find("ior"))
        s.fail(p.def.pos(), p.what + " has kt but no \"ior\"; expected an index of refraction");
    // Only a diffuse lobe: the diffuse type, which behaves identically and is sampled inline
    // in the path loop.
    if (!b.has_mirror() && !b.has_transmission()) return DiffuseBsdf{std::move(b.kd)};
    return b;
}

/// The surface under a fluorescent dye layer: "surface" (a material of any other type) or
/// "base" (a diffuse one's kd), not both; default diffuse 0.9.
Bsdf fluorescent_surface(const MaterialParams& p, const std::string& w) {
    const SpectrumParser& s = p.spectra;
    const ParamValue* surface = p.def.find("surface");
    const ParamValue* base = p.def.find("base");
    if (surface && base)
        s.fail(base->pos(), w + " has both \"surface\" and \"base\"; expected one of them (\"base\" is the "
                                "reflectance of a diffuse surface)");
    if (!surface) {
        if (base && TextureParser::is_binding(*base))
            s.fail(base->pos(), w + " base cannot be bound to a texture; expected a spectrum (or a \"surface\" whose "
                                    "kd is a texture)");
        return DiffuseBsdf{base ? s.spectrum(*base, w + " base", SpectrumUse::Reflectance)
                                : s.spectrum_from(SpectrumSource::constant(0.9), p.def.pos(), w + " base",
                                                  SpectrumUse::Reflectance)};
    }
    const std::string sw = w + " surface";
    if (!surface->is_object())
        s.fail(surface->pos(), sw + " is not an object; expected a material: {\"type\": ..., its parameters}");
    std::string type = "lobes";
    if (const ParamValue* t = surface->find("type")) type = s.string(*t, sw + " type");
    const MaterialType* surface_type = type == "fluorescent" ? nullptr : find_material_type(type);
    if (!surface_type) {
        std::vector<std::string> types;
        for (const MaterialType& t : material_types())
            if (std::string(t.name) != "fluorescent") types.emplace_back(t.name);
        s.fail(surface->find("type")->pos(), sw + " has type " + quote_text(type) + "." + suggestion(type, types) +
                                                 " Expected one of: " + join(types));
    }
    Bsdf bsdf = surface_type->create({s, *surface, sw, p.number, p.reflectance, nullptr});
    s.all_read(*surface, sw + " of type " + quote_text(type));
    return bsdf;
}

/// A surface of any type under a fluorescent dye layer (model/fluorescence.h): the layer
/// absorbs a(λ) = 1 − 10^(−density·ε(λ)) and re-emits; the surface, Material::bsdf, reflects
/// what passes (the integrator applies the factor 1 − a(λ)).
Bsdf fluorescent(const MaterialParams& p) {
    const SpectrumParser& s = p.spectra;
    const std::string w = p.what + " of type \"fluorescent\"";
    const ParamValue& dv = s.required(p.def, "dye", w);
    SpectrumSource excitation, emission;
    double yield = 1;
    std::string dye = "custom";
    if (dv.is_object()) {
        const std::string dw = w + " dye";
        excitation = s.spectrum_source(s.required(dv, "excitation", dw), dw + " excitation");
        emission = s.spectrum_source(s.required(dv, "emission", dw), dw + " emission");
        yield = s.number_in(s.required(dv, "quantum_yield", dw), dw + " quantum_yield", 0, 1);
        s.all_read(dv, dw);
        for (const auto& [src, key] : {std::pair{&excitation, "excitation"}, std::pair{&emission, "emission"}}) {
            double peak = 0;
            for (double l = kTransportMin; l <= kTransportMax; l += 1.0) {
                const double x = src->eval(l);
                if (!(std::isfinite(x) && x >= 0))
                    s.fail(dv.find(key)->pos(), dw + " " + key + " is " + number_text(x) + " at " + number_text(l) +
                                                    " nm; expected a finite value >= 0 from 300 to 830 nm");
                peak = std::max(peak, x);
            }
            if (!(peak > 0))
                s.fail(dv.find(key)->pos(), dw + " " + key + " is 0 from 300 to 830 nm; expected a band there");
        }
    } else {
        const std::string& name = s.string(dv, w + " dye");
        const std::optional<DyeInfo> d = find_dye(name);
        if (!d)
            s.fail(dv.pos(), "unknown dye " + quote_text(name) + "." + suggestion(name, dye_names()) +
                                 " Expected one of: " + join(dye_names()) + ", or an object with \"excitation\", "
                                 "\"emission\" and \"quantum_yield\"");
        excitation = d->excitation, emission = d->emission, yield = d->quantum_yield, dye = d->name;
    }
    if (const ParamValue* q = p.def.find("quantum_yield")) yield = s.number_in(*q, w + " quantum_yield", 0, 1);
    double density = 1;
    if (const ParamValue* d = p.def.find("density")) density = s.number_in(*d, w + " density", 0, 10, true);
    Bsdf surface = fluorescent_surface(p, w);
    if (p.fluorescence) *p.fluorescence = std::make_shared<const Fluorescence>(excitation, emission, density, yield, dye);
    return surface;
}

/// The microfacet types name their type in messages, and reject anisotropic keys with a
/// message that says where they belong (the read check would only call them unknown).
template <const char* kName>
std::string microfacet_what(const MaterialParams& p) {
    const std::string w = p.what + " of type " + quote_text(kName);
    reject_anisotropy(p.spectra, p.def, kName, w);
    return w;
}

constexpr char kConductor[] = "conductor", kDielectric[] = "dielectric", kPlastic[] = "plastic",
               kThinSheet[] = "thin_sheet";

Bsdf create_conductor(const MaterialParams& p) {
    return conductor(p.spectra, p.def, microfacet_what<kConductor>(p), p.number);
}
Bsdf create_dielectric(const MaterialParams& p) {
    return dielectric(p.spectra, p.def, microfacet_what<kDielectric>(p), p.number);
}
Bsdf create_plastic(const MaterialParams& p) {
    return plastic(p.spectra, p.def, microfacet_what<kPlastic>(p), p.number, p.reflectance);
}
Bsdf create_thin_sheet(const MaterialParams& p) {
    return thin_sheet(p.spectra, p.def, microfacet_what<kThinSheet>(p), p.number);
}

/// Throws SceneError unless s stays in [lo, hi] from 360 to 830 nm (bins and exact source).
void check_range(const Spectrum& s, const std::string& what, double lo, double hi) {
    for (float l = kLambdaMin; l <= kLambdaMax; l += 1.f) {
        const double v = s.eval(l), x = s.source().eval(l);
        if (std::isfinite(v) && std::isfinite(x) && v >= lo && v <= hi && x >= lo && x <= hi) continue;
        std::ostringstream msg;
        msg << what << " is " << (v >= lo && v <= hi ? x : v) << " at " << l << " nm; expected a value in [" << lo
            << ", " << hi << "]";
        throw SceneError(msg.str());
    }
}

void check_alpha(const GgxDistribution& g, const std::string& who) {
    if (!(g.alpha >= 0.f && g.alpha <= 1.f)) throw SceneError(who + " roughness must be in [0, 1]");
}

void check_film(const ThinFilm& f, const std::string& who) {
    if (!(f.thickness_nm >= 0.f && f.thickness_nm <= 1e5f)) throw SceneError(who + " film thickness must be in [0, 1e5] nm");
    if (f.present()) check_range(f.eta, who + " film index", 1, 100);
}

}  // namespace

const std::vector<MaterialType>& material_types() {
    static const std::vector<MaterialType> types = {
        {"diffuse", diffuse},
        {"lobes", lobes},
        {kConductor, create_conductor},
        {kDielectric, create_dielectric},
        {kPlastic, create_plastic},
        {kThinSheet, create_thin_sheet},
        {"fluorescent", fluorescent},
    };
    return types;
}

const MaterialType* find_material_type(const std::string& name) {
    for (const MaterialType& t : material_types())
        if (name == t.name) return &t;
    return nullptr;
}

void validate_surface_model(const Bsdf& bsdf, const std::string& who) {
    if (const ConductorBsdf* c = std::get_if<ConductorBsdf>(&bsdf)) {
        check_range(c->eta, who + " eta", 1e-3, 100);
        check_range(c->k, who + " k", 0, 100);
        check_alpha(c->ggx, who);
        if (c->aniso.alpha_x != 0.f || c->aniso.alpha_y != 0.f)
            if (!(c->aniso.alpha_x >= 1e-3f && c->aniso.alpha_x <= 1.f && c->aniso.alpha_y >= 1e-3f &&
                  c->aniso.alpha_y <= 1.f))
                throw SceneError(who + " roughness_u and roughness_v must be in [0.001, 1]");
        check_film(c->film, who);
    } else if (const DielectricBsdf* d = std::get_if<DielectricBsdf>(&bsdf)) {
        check_range(d->eta, who + " index of refraction", 1, 100);
        check_alpha(d->ggx, who);
        check_film(d->film, who);
    } else if (const PlasticBsdf* p = std::get_if<PlasticBsdf>(&bsdf)) {
        check_range(p->kd, who + " kd", 0, 1);
        if (!(p->eta >= 1.f && p->eta <= 100.f)) throw SceneError(who + " coat index must be in [1, 100]");
        if (p->dispersion) check_range(p->dispersion->eta, who + " coat index", 1, 100);
        check_alpha(p->ggx, who);
    } else if (const ThinSheetBsdf* t = std::get_if<ThinSheetBsdf>(&bsdf)) {
        if (!(t->film.thickness_nm > 0.f && t->film.thickness_nm <= 1e5f))
            throw SceneError(who + " thickness must be in (0, 1e5] nm");
        check_range(t->film.eta, who + " index", 1, 100);
    }
}

}  // namespace spt

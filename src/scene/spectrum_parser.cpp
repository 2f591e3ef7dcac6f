// Parsing and range checks of the spectrum forms of scene files.
#include "scene/spectrum_parser.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "spectral/catalog_lookup.h"
#include "spectral/cie.h"
#include "spectral/dye_catalog.h"
#include "spectral/glass_catalog.h"
#include "spectral/rgb_to_spectrum.h"

namespace spt {

Spectrum SpectrumParser::spectrum(const ParamValue& v, const std::string& what, SpectrumUse use) const {
    return spectrum_from(spectrum_source(v, what), v.pos(), what, use);
}

Spectrum SpectrumParser::spectrum_from(const SpectrumSource& source, SourcePos pos, const std::string& what,
                                       SpectrumUse use) const {
    // Scan the exact source over the whole sampled range.
    double lo = 0, hi = 1e30;
    const char* expected = "a finite value >= 0";
    if (use == SpectrumUse::Reflectance) hi = 1, expected = "a reflectance in [0, 1]";
    if (use == SpectrumUse::Index) lo = 1, hi = 100, expected = "an index of refraction in [1, 100]";
    if (use == SpectrumUse::ConductorIndex) lo = 1e-3, hi = 100, expected = "a conductor's eta in [0.001, 100]";
    if (use == SpectrumUse::Extinction) lo = 0, hi = 100, expected = "an extinction coefficient k in [0, 100]";
    for (double l = kLambdaMin; l <= kLambdaMax; l += 1.0) {
        const double x = source.eval(l);
        if (std::isfinite(x) && x >= lo && x <= hi) continue;
        fail(pos, what + " is " + number_text(x) + " at " + number_text(l) + " nm; expected " + expected +
                          " at every wavelength from 360 to 830 nm");
    }
    return Spectrum(source, m_resolution);
}

SpectrumSource SpectrumParser::spectrum_source(const ParamValue& v, const std::string& what) const {
    if (v.is_number()) return SpectrumSource::constant(v.as_number());
    if (v.is_array()) return rgb(v, what, 1.0);
    if (!v.is_object())
        wrong_type(v, what, "a spectrum: a number, an [r, g, b] array or an object with a \"type\"");
    const std::string& type = string(required(v, "type", what), what + " type");
    const std::string w = what + " (" + type + ")";
    auto need = [&](const char* key) -> double { return number(required(v, key, w), w + " " + key); };
    auto opt = [&](const char* key, double fallback) { return optional_number(v, key, fallback, w); };
    auto width = [&](const char* key) {
        return number_in(required(v, key, w), w + " " + key, 0, 1e6, true);
    };
    // The source of each type, read by the branch of its type; the keys no branch read are
    // unknown.
    const auto typed = [&]() -> SpectrumSource {
        if (type == "constant") {
            return SpectrumSource::constant(need("value"));
        }
        if (type == "gaussian" || type == "sigmoid") {
            const double center = need("center_nm"), wd = width("width_nm");
            return type == "gaussian" ? SpectrumSource::gaussian(center, wd, opt("scale", 1), opt("offset", 0))
                                      : SpectrumSource::sigmoid(center, wd, opt("scale", 1), opt("offset", 0));
        }
        if (type == "blackbody") {
            const double t = number_in(required(v, "temperature_k", w), w + " temperature_k", 100, 1e6);
            const double at = v.find("normalize_nm")
                                  ? number_in(*v.find("normalize_nm"), w + " normalize_nm", 100, 10000)
                                  : 560.0;
            return SpectrumSource::blackbody(t, opt("scale", 1), at);
        }
        if (type == "table") {
            const ParamValue& pts = required(v, "points", w);
            if (!pts.is_array() || pts.items().empty())
                fail(pts.pos(), w + " points is not a non-empty array; expected [[lambda_nm, value], ...]");
            std::vector<std::pair<double, double>> table;
            const double scale = opt("scale", 1);
            for (const ParamValue& p : pts.items()) {
                const std::vector<double> lv = numbers(p, w + " point", 2);
                if (!table.empty() && !(lv[0] > table.back().first))
                    fail(p.pos(), w + " wavelengths do not increase; expected strictly increasing wavelengths");
                table.emplace_back(lv[0], lv[1] * scale);
            }
            return SpectrumSource::piecewise_linear(std::move(table));
        }
        if (type == "cauchy") {
            return SpectrumSource::cauchy(need("a"), opt("b_um2", 0), opt("c_um4", 0));
        }
        if (type == "sellmeier") {
            const auto b = numbers(required(v, "b", w), w + " b", 3);
            const auto c = numbers(required(v, "c_um2", w), w + " c_um2", 3);
            return SpectrumSource::sellmeier(b[0], b[1], b[2], c[0], c[1], c[2]);
        }
        if (type == "rgb") {
            return rgb(required(v, "value", w), w, opt("scale", 1));
        }
        if (type == "illuminant") {
            const ParamValue& n = required(v, "name", w);
            const std::string& name = string(n, w + " name");
            // D65 and A are tabulated as 100 at 560 nm and made 1 there. Lamps with lines are
            // tabulated on scales of their own, and 560 nm may fall between their lines, so they
            // are made luminance 1 instead (cie_luminance, the `normalized` form's).
            struct Named {
                const char* name;
                const char* file;
                bool at_560;
            };
            static constexpr Named kNamed[] = {{"D65", "cie_d65.csv", true},   {"A", "cie_a.csv", true},
                                               {"F2", "cie_f2.csv", false},    {"F7", "cie_f7.csv", false},
                                               {"F11", "cie_f11.csv", false}, {"LED-B3", "cie_led_b3.csv", false}};
            const Named* found = nullptr;
            std::vector<std::string> names;
            for (const Named& k : kNamed) {
                names.emplace_back(k.name);
                if (name == k.name) found = &k;
            }
            if (!found)
                fail(n.pos(), "unknown illuminant " + quote_text(name) + "." + suggestion(name, names) +
                                  " Expected one of: " + join(names));
            const SpectralTable& t = embedded_spectral_table(found->file);
            if (found->at_560) return column_spectrum(t, "value", opt("scale", 1) / 100.0);
            return column_spectrum(t, "value", opt("scale", 1) / cie_luminance(column_spectrum(t, "value", 1.0)));
        }
        if (type == "uv_lamp") {
            const ParamValue& n = required(v, "name", w);
            const std::string& name = string(n, w + " name");
            const std::optional<SpectrumSource> lamp = find_uv_lamp(name);
            if (!lamp)
                fail(n.pos(), "unknown UV lamp " + quote_text(name) + "." + suggestion(name, uv_lamp_names()) +
                                  " Expected one of: " + join(uv_lamp_names()));
            return SpectrumSource::product({*lamp}, opt("scale", 1));
        }
        if (type == "glass") {
            const ParamValue& n = required(v, "name", w);
            const std::string& name = string(n, w + " name");
            const std::optional<GlassInfo> glass = find_glass(name);
            if (!glass)
                fail(n.pos(), "unknown glass " + quote_text(name) + "." + suggestion(name, glass_names()) +
                                  " Expected one of: " + join(glass_names()));
            return glass->ior;
        }
        if (type == "colorchecker") {
            const ParamValue& n = required(v, "patch", w);
            const std::string& patch = string(n, w + " patch");
            const SpectralTable& t = embedded_spectral_table("colorchecker.csv");
            const std::vector<std::string> patches(t.column_names.begin() + 1, t.column_names.end());
            if (std::find(patches.begin(), patches.end(), patch) == patches.end())
                fail(n.pos(), "unknown ColorChecker patch " + quote_text(patch) + "." + suggestion(patch, patches) +
                                  " Expected one of: " + join(patches));
            return column_spectrum(t, patch, opt("scale", 1));
        }
        if (type == "product") {
            const ParamValue& fs = required(v, "factors", w);
            if (!fs.is_array() || fs.items().empty())
                fail(fs.pos(), w + " factors is not a non-empty array; expected [SPECTRUM, ...]");
            std::vector<SpectrumSource> factors;
            for (const ParamValue& f : fs.items()) factors.push_back(spectrum_source(f, w + " factor"));
            return SpectrumSource::product(std::move(factors), opt("scale", 1));
        }
        if (type == "normalized") {
            const ParamValue& sv = required(v, "spectrum", w);
            const ParamValue& yv = required(v, "luminance", w);
            const SpectrumSource s = spectrum_source(sv, w + " spectrum");
            const double y = number(yv, w + " luminance");
            if (!(y >= 0) || !std::isfinite(y))
                fail(yv.pos(), w + " luminance is " + number_text(y) + "; expected a finite number >= 0");
            const double own = cie_luminance(s);
            if (!(own > 0) || !std::isfinite(own))
                fail(sv.pos(), w + " spectrum has luminance " + number_text(own) +
                                   "; expected a spectrum of positive luminance to normalise");
            return SpectrumSource::product({s}, y / own);
        }
        const ParamValue& t = *v.find("type");
        const std::vector<std::string> types = {"constant", "gaussian", "sigmoid", "blackbody", "table", "cauchy",
                                                "sellmeier", "glass", "rgb", "illuminant", "colorchecker",
                                                "product", "normalized", "uv_lamp"};
        fail(t.pos(), "unknown spectrum type " + quote_text(type) + "." + suggestion(type, types) +
                          " Expected one of: " + join(types));
    };
    const SpectrumSource source = typed();
    all_read(v, w);
    return source;
}

SpectrumSource SpectrumParser::rgb(const ParamValue& v, const std::string& what, double scale) const {
    const std::vector<double> c = numbers(v, what + " rgb", 3);
    for (double x : c)
        if (x < 0 || x > 1)
            fail(v.pos(), what + " rgb component " + number_text(x) +
                              " is out of range; expected linear sRGB components in [0, 1] (use \"scale\" for brighter emission)");
    SpectrumSource s;
    try {
        s = rgb_to_spectrum({c[0], c[1], c[2]});
    } catch (const std::exception& e) {
        fail(v.pos(), what + ": " + e.what() + "; expected an RGB reflectance that can be fitted");
    }
    if (s.kind == SpectrumSource::Kind::Constant) return SpectrumSource::constant(s.p[0] * scale);
    s.p[3] = scale;
    return s;
}



}  // namespace spt

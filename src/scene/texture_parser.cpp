// Texture definitions → Scene::textures, RGB texels fitted once per distinct colour.
#include "scene/texture_parser.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>

#include "io/image_decoders.h"
#include "spectral/rgb_texels.h"

namespace spt {

namespace {

/// IEC 61966-2-1 sRGB decoding of a code in [0, 1].
float srgb_to_linear(float c) {
    return c <= 0.04045f ? c / 12.92f : static_cast<float>(std::pow((c + 0.055) / 1.055, 2.4));
}

const char* use_name(TextureUse use) {
    switch (use) {
        case TextureUse::reflectance: return "a reflectance";
        case TextureUse::emission: return "an emission";
        case TextureUse::number: return "a number";
    }
    return "";
}

}  // namespace

void TextureParser::definitions(const ParamValue& v) {
    object(v, "textures");
    for (const auto& [name, def] : v.members()) object(def, "texture " + quote_text(name));
    m_definitions = &v;
}

int TextureParser::bins(TextureUse use) const {
    if (use == TextureUse::number) return 1;
    return m_resolution.bins == SpectralResolution::kExact ? kExactTextureBins : m_resolution.bins;
}

int TextureParser::bind(const ParamValue& v, const std::string& what, TextureUse use) {
    const ParamValue& n = required(v, "texture", what);
    const std::string& name = string(n, what + " texture");
    const ParamValue* def = m_definitions ? m_definitions->find(name) : nullptr;
    if (!def) {
        std::vector<std::string> known;
        if (m_definitions)
            for (const auto& [k, d] : m_definitions->members()) known.push_back(k);
        fail(n.pos(), "unknown texture " + quote_text(name) + "." + suggestion(name, known) +
                          (known.empty() ? " Expected a texture defined in \"textures\" (there are none)"
                                         : " Expected one of: " + join(known)));
    }
    const double scale = use == TextureUse::emission ? optional_number(v, "scale", 1.0, what) : 1.0;
    if (!(scale >= 0 && scale <= 1e30)) fail(v.find("scale")->pos(), what + " scale is out of range; expected a number in [0, 1e30]");
    all_read(v, what);  // "scale" is an emission's only
    const auto key = std::make_tuple(name, use, scale);
    if (auto it = m_built.find(key); it != m_built.end()) return it->second;
    m_scene.textures.push_back(build(name, *def, use, scale));
    const int index = static_cast<int>(m_scene.textures.size()) - 1;
    m_built.emplace(key, index);
    return index;
}

Texture TextureParser::build(const std::string& name, const ParamValue& def, TextureUse use, double scale) const {
    const std::string what = "texture " + quote_text(name);
    Texture t;
    t.name = name;
    t.bins = bins(use);
    const std::string& type = string(required(def, "type", what), what + " type");
    // The (u, v) transform, which every type has.
    const auto uv_transform = [&] {
        if (const ParamValue* s = def.find("uv_scale")) {
            const auto c = numbers(*s, what + " uv_scale", 2);
            for (double x : c)
                if (!(std::fabs(x) <= 1e6)) fail(s->pos(), what + " uv_scale is out of range; expected magnitudes up to 1e6");
            t.transform.scale_u = static_cast<float>(c[0]), t.transform.scale_v = static_cast<float>(c[1]);
        }
        if (const ParamValue* o = def.find("uv_offset")) {
            const auto c = numbers(*o, what + " uv_offset", 2);
            for (double x : c)
                if (!(std::fabs(x) <= 1e6)) fail(o->pos(), what + " uv_offset is out of range; expected magnitudes up to 1e6");
            t.transform.offset_u = static_cast<float>(c[0]), t.transform.offset_v = static_cast<float>(c[1]);
        }
    };
    if (type == "checkerboard") {
        uv_transform();
        t.pattern = CheckerboardTexture{};
        add_value(t, required(def, "even", what), what + " even", use, scale);
        add_value(t, required(def, "odd", what), what + " odd", use, scale);
    } else if (type == "gradient") {
        uv_transform();
        GradientTexture g;
        if (const ParamValue* a = def.find("axis")) {
            const std::string& axis = string(*a, what + " axis");
            if (axis != "u" && axis != "v") fail(a->pos(), what + " axis is " + quote_text(axis) + "; expected \"u\" or \"v\"");
            g.along_v = axis == "v";
        }
        t.pattern = g;
        add_value(t, required(def, "start", what), what + " start", use, scale);
        add_value(t, required(def, "end", what), what + " end", use, scale);
    } else if (type == "image") {
        uv_transform();
        image(t, def, what, use, scale);
    } else {
        const std::vector<std::string> types = {"checkerboard", "gradient", "image"};
        fail(def.find("type")->pos(), "unknown texture type " + quote_text(type) + "." + suggestion(type, types) +
                                          " Expected one of: " + join(types));
    }
    all_read(def, what + " of type " + quote_text(type));
    return t;
}

void TextureParser::add_value(Texture& t, const ParamValue& v, const std::string& what, TextureUse use,
                              double scale) const {
    if (use == TextureUse::number) {
        t.values.push_back(static_cast<float>(number_in(v, what, -1e30, 1e30)));
        return;
    }
    const Spectrum s = m_spectra.spectrum(v, what, use == TextureUse::emission ? SpectrumUse::Emission : SpectrumUse::Reflectance);
    for (float b : project_onto_bins(s.source(), t.bins)) t.values.push_back(static_cast<float>(b * scale));
}

void TextureParser::image(Texture& t, const ParamValue& def, const std::string& what, TextureUse use,
                          double scale) const {
    const ParamValue& fv = required(def, "file", what);
    const std::string& file = string(fv, what + " file");
    std::string contents, display, error;
    if (file.empty() || !m_read_relative(file, contents, display, error))
        fail(fv.pos(), "cannot read texture image " + quote_text(file) + (error.empty() ? "" : ": " + error) +
                           "; expected a PNG, PPM, PFM, EXR or Radiance HDR file path relative to the scene file");
    DecodedImage img;
    try {
        img = decode_image(contents);
    } catch (const ImageDecodeError& e) {
        fail(fv.pos(), "cannot read texture image " + quote_text(display) + ": " + e.what());
    }
    ImageTexture it;
    it.width = img.width, it.height = img.height;
    if (const ParamValue* w = def.find("wrap")) {
        const std::string& mode = string(*w, what + " wrap");
        const std::vector<std::string> modes = {"repeat", "clamp", "mirror"};
        if (mode == "repeat") it.wrap = WrapMode::repeat;
        else if (mode == "clamp") it.wrap = WrapMode::clamp;
        else if (mode == "mirror") it.wrap = WrapMode::mirror;
        else fail(w->pos(), "unknown wrap mode " + quote_text(mode) + "." + suggestion(mode, modes) + " Expected one of: " + join(modes));
    }
    if (const ParamValue* f = def.find("filter")) {
        const std::string& filter = string(*f, what + " filter");
        if (filter != "bilinear" && filter != "nearest")
            fail(f->pos(), "unknown filter " + quote_text(filter) + "; expected \"bilinear\" or \"nearest\"");
        it.bilinear = filter == "bilinear";
    }
    bool srgb = img.integer_codes;
    if (const ParamValue* e = def.find("encoding")) {
        const std::string& enc = string(*e, what + " encoding");
        if (enc != "srgb" && enc != "linear") fail(e->pos(), "unknown encoding " + quote_text(enc) + "; expected \"srgb\" or \"linear\"");
        if (enc == "srgb" && !img.integer_codes)
            fail(e->pos(), what + ": " + quote_text(display) + " holds floating-point values, which are linear; expected no \"encoding\" or \"linear\"");
        srgb = enc == "srgb";
    }
    // Texels → entries: one per distinct colour, fitted once.
    struct KeyHash {
        std::size_t operator()(const std::array<float, 3>& k) const {
            std::uint32_t b[3];
            std::memcpy(b, k.data(), sizeof b);
            return (std::size_t(b[0]) * 0x9E3779B1u) ^ (std::size_t(b[1]) * 0x85EBCA77u) ^ (std::size_t(b[2]) * 0xC2B2AE3Du);
        }
    };
    std::unordered_map<std::array<float, 3>, std::uint32_t, KeyHash> entries;
    it.texels.resize(static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height));
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            std::array<float, 3> rgb;
            for (int c = 0; c < 3; ++c) {
                // Grey (and grey + alpha) images give equal components; alpha is not used.
                const float code = img.at(x, y, img.channels >= 3 ? c : 0);
                rgb[static_cast<std::size_t>(c)] = srgb ? srgb_to_linear(code) : code;
            }
            if (use == TextureUse::number) rgb[1] = rgb[2] = rgb[0];  // a number reads the first channel
            auto [pos, added] = entries.emplace(rgb, static_cast<std::uint32_t>(entries.size()));
            it.texels[static_cast<std::size_t>(y) * static_cast<std::size_t>(img.width) + static_cast<std::size_t>(x)] = pos->second;
            if (!added) continue;
            if (use == TextureUse::number) {
                if (!std::isfinite(rgb[0])) fail(fv.pos(), what + ": texel (" + std::to_string(x) + ", " + std::to_string(y) + ") of " + quote_text(display) + " is not finite; expected finite values");
                t.values.push_back(rgb[0]);
                continue;
            }
            try {
                for (float b : rgb_texel_bins(rgb, use == TextureUse::emission ? TexelUse::emission : TexelUse::reflectance, t.bins))
                    t.values.push_back(static_cast<float>(b * scale));
            } catch (const std::exception& e) {
                fail(fv.pos(), what + ": texel (" + std::to_string(x) + ", " + std::to_string(y) + ") of " +
                                   quote_text(display) + ": " + e.what() + " (" + use_name(use) + " texture)");
            }
        }
    t.pattern = std::move(it);
}

Spectrum TextureParser::envelope(int texture) const {
    const Texture& t = m_scene.textures[static_cast<std::size_t>(texture)];
    std::vector<float> hi(static_cast<std::size_t>(t.bins), 0.f);
    for (std::uint32_t e = 0; e < t.entry_count(); ++e) {
        const std::span<const float> v = t.entry(e);
        for (std::size_t b = 0; b < hi.size(); ++b) hi[b] = std::max(hi[b], v[b]);
    }
    return spectrum_of_bins(std::move(hi));
}

Spectrum TextureParser::mean(int texture) const {
    const Texture& t = m_scene.textures[static_cast<std::size_t>(texture)];
    // Each entry's share of the (u, v) square: its texels' for an image; the checkerboard's
    // two cells cover equal areas, and the gradient's mean over [0, 1] is its ends' mean.
    std::vector<double> share(t.entry_count(), 1.0 / static_cast<double>(t.entry_count()));
    if (const ImageTexture* img = std::get_if<ImageTexture>(&t.pattern)) {
        std::fill(share.begin(), share.end(), 0.0);
        for (const std::uint32_t e : img->texels) share[e] += 1.0 / static_cast<double>(img->texels.size());
    }
    std::vector<double> sum(static_cast<std::size_t>(t.bins), 0.0);
    for (std::uint32_t e = 0; e < t.entry_count(); ++e) {
        const std::span<const float> v = t.entry(e);
        for (std::size_t b = 0; b < sum.size(); ++b) sum[b] += share[e] * v[b];
    }
    return spectrum_of_bins(std::vector<float>(sum.begin(), sum.end()));
}

Spectrum TextureParser::spectrum_of_bins(std::vector<float> bins) const {
    // A source through the bin centres (for the checks that read the exact source), and the
    // bins themselves (for the look-up and the flags).
    std::vector<std::pair<double, double>> points;
    const double width = double(Spectrum::kBinMax - Spectrum::kBinMin) / static_cast<double>(bins.size());
    for (std::size_t b = 0; b < bins.size(); ++b) points.emplace_back(Spectrum::kBinMin + (b + 0.5) * width, bins[b]);
    if (points.size() == 1) points.emplace_back(Spectrum::kBinMax, bins[0]);
    Spectrum s(SpectrumSource::piecewise_linear(std::move(points)), m_resolution);
    s.assign_bins(bins);
    return s;
}

float TextureParser::max_number(int texture) const {
    const Texture& t = m_scene.textures[static_cast<std::size_t>(texture)];
    return t.values.empty() ? 0.f : *std::max_element(t.values.begin(), t.values.end());
}

}  // namespace spt

// OpenEXR 2.0: single-part scanline file, no compression, FLOAT channels: B, G, R, and with
// spectral output the emissive spectral channels of Fichet, Pacanowski & Wilkie, "An OpenEXR
// Layout for Spectral Images", JCGT 10(3), 2021: one channel per band named S0.<λ>nm, λ the
// band centre printed as C's "%f" with the decimal point replaced by a comma (the point
// separates layers in EXR channel names): "S0.555,000000nm", as the paper's reference code
// (std::to_string then ',') writes it; header attributes spectralLayoutVersion = "1.0" and
// emissiveUnits = "W.m^-2.sr^-1".
#include <algorithm>
#include <cstdio>
#include <initializer_list>
#include <stdexcept>

#include "io/image_encoders.h"

namespace spt {
namespace {

std::string le_ints(std::initializer_list<std::int32_t> values) {
    std::string s;
    for (std::int32_t v : values) append_le32(s, static_cast<std::uint32_t>(v));
    return s;
}

std::string le_floats(std::initializer_list<float> values) {
    std::string s;
    for (float v : values) append_le_float(s, v);
    return s;
}

/// A channel's values: pixel (x, y) is base[(y·width + x)·stride].
struct ChannelSource {
    std::string name;
    const float* base;
    std::size_t stride;
};

}  // namespace

ExrAttribute ExrAttribute::text(std::string name, const std::string& value) {
    return {std::move(name), "string", value};
}
ExrAttribute ExrAttribute::integer(std::string name, std::int32_t value) {
    return {std::move(name), "int", le_ints({value})};
}
ExrAttribute ExrAttribute::real(std::string name, double value) {
    std::string bytes;
    append_le64(bytes, std::bit_cast<std::uint64_t>(value));
    return {std::move(name), "double", bytes};
}

std::string spectral_channel_name(double lambda_nm) {
    char text[64];
    std::snprintf(text, sizeof text, "%f", lambda_nm);
    std::string name = std::string("S0.") + text + "nm";
    std::replace(name.begin() + 3, name.end(), '.', ',');
    return name;
}

std::string encode_exr(const Image& image, const ImageWriteOptions& options) {
    const int w = image.width, h = image.height;
    const std::size_t pixels = static_cast<std::size_t>(w) * h;
    constexpr int kPixelTypeFloat = 2;

    std::vector<ChannelSource> channels = {
        {"R", image.rgb.data(), 3}, {"G", image.rgb.data() + 1, 3}, {"B", image.rgb.data() + 2, 3}};
    std::vector<ExrAttribute> attributes = options.exr_attributes;
    if (const SpectralImage* s = options.spectral) {
        const auto n = static_cast<std::size_t>(s->bands.count);
        if (n == 0 || s->values.size() != n * pixels)
            throw std::invalid_argument("spectral bands do not match the image size");
        for (std::size_t b = 0; b < n; ++b)
            channels.push_back({spectral_channel_name(s->bands.center_nm(static_cast<int>(b))),
                                s->values.data() + b, n});
        attributes.push_back(ExrAttribute::text("spectralLayoutVersion", "1.0"));
        attributes.push_back(ExrAttribute::text("emissiveUnits", "W.m^-2.sr^-1"));
    }
    // chlist must be sorted by name (byte order: "S0.1000,..." before "S0.360,..."); blocks
    // store the channels in the same order.
    std::sort(channels.begin(), channels.end(),
              [](const ChannelSource& a, const ChannelSource& b) { return a.name < b.name; });

    std::string chlist;
    for (const ChannelSource& c : channels) {
        chlist += c.name;
        chlist += '\0';
        chlist += le_ints({kPixelTypeFloat});
        chlist += std::string(4, '\0');  // pLinear = 0 and 3 reserved bytes
        chlist += le_ints({1, 1});       // x and y sampling
    }
    chlist += '\0';
    const Chromaticities& c = options.chromaticities;
    attributes.push_back({"channels", "chlist", chlist});
    if (options.exr_chromaticities)
        attributes.push_back({"chromaticities", "chromaticities",
                              le_floats({c.red[0], c.red[1], c.green[0], c.green[1], c.blue[0],
                                         c.blue[1], c.white[0], c.white[1]})});
    attributes.push_back({"compression", "compression", std::string(1, '\0')});  // NONE
    attributes.push_back({"dataWindow", "box2i", le_ints({0, 0, w - 1, h - 1})});
    attributes.push_back({"displayWindow", "box2i", le_ints({0, 0, w - 1, h - 1})});
    attributes.push_back({"lineOrder", "lineOrder", std::string(1, '\0')});  // INCREASING_Y
    attributes.push_back({"pixelAspectRatio", "float", le_floats({1.0f})});
    attributes.push_back({"screenWindowCenter", "v2f", le_floats({0.0f, 0.0f})});
    attributes.push_back({"screenWindowWidth", "float", le_floats({1.0f})});
    // In alphabetical order, as the OpenEXR library writes them.
    std::sort(attributes.begin(), attributes.end(),
              [](const ExrAttribute& a, const ExrAttribute& b) { return a.name < b.name; });
    for (std::size_t i = 1; i < attributes.size(); ++i)
        if (attributes[i].name == attributes[i - 1].name)
            throw std::invalid_argument("EXR attribute '" + attributes[i].name + "' given twice");

    std::string out;
    append_le32(out, 20000630);  // magic
    // Version 2; bit 10 (long names) once a name or type exceeds 31 bytes.
    bool long_names = false;
    for (const ExrAttribute& a : attributes) long_names |= a.name.size() > 31 || a.type.size() > 31;
    for (const ChannelSource& ch : channels) long_names |= ch.name.size() > 31;
    append_le32(out, 2u | (long_names ? 0x400u : 0u));
    for (const ExrAttribute& a : attributes) {
        out += a.name;
        out += '\0';
        out += a.type;
        out += '\0';
        append_le32(out, static_cast<std::uint32_t>(a.value.size()));
        out += a.value;
    }
    out += '\0';  // end of header

    // Uncompressed: one scanline per block, each block = y, byte count, then one row per channel.
    const std::uint64_t data_bytes =
        std::uint64_t{4} * static_cast<std::uint64_t>(w) * channels.size();
    if (data_bytes > 0xffffffffu)
        throw std::invalid_argument("too many channels for one EXR scanline");
    const std::uint64_t table_end = out.size() + static_cast<std::uint64_t>(h) * 8;
    for (int y = 0; y < h; ++y)
        append_le64(out, table_end + (8 + data_bytes) * static_cast<std::uint64_t>(y));
    for (int y = 0; y < h; ++y) {
        append_le32(out, static_cast<std::uint32_t>(y));
        append_le32(out, static_cast<std::uint32_t>(data_bytes));
        for (const ChannelSource& ch : channels) {
            const float* row = ch.base + static_cast<std::size_t>(y) * w * ch.stride;
            for (int x = 0; x < w; ++x)
                append_le_float(out, row[static_cast<std::size_t>(x) * ch.stride]);
        }
    }
    return out;
}

}  // namespace spt

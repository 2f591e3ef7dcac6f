// OpenEXR 2.0: single-part scanline file, no compression, FLOAT channels B, G, R.
#include <initializer_list>

#include "io/image_encoders.h"

namespace spt {
namespace {

void append_attribute(std::string& out, const char* name, const char* type,
                      const std::string& value) {
    out += name;
    out += '\0';
    out += type;
    out += '\0';
    append_le32(out, static_cast<std::uint32_t>(value.size()));
    out += value;
}

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

}  // namespace

std::string encode_exr(const Image& image, const ImageWriteOptions& options) {
    const int w = image.width, h = image.height;
    constexpr int kPixelTypeFloat = 2;
    // chlist must be sorted by name; blocks store the channels in the same order.
    constexpr char kChannels[3] = {'B', 'G', 'R'};
    constexpr int kChannelOffset[3] = {2, 1, 0};  // position of B, G, R within an RGB pixel

    std::string out;
    append_le32(out, 20000630);  // magic
    append_le32(out, 2);         // version 2, flags 0: single-part scanline, short names

    std::string chlist;
    for (char name : kChannels) {
        chlist += name;
        chlist += '\0';
        chlist += le_ints({kPixelTypeFloat});
        chlist += std::string(4, '\0');  // pLinear = 0 and 3 reserved bytes
        chlist += le_ints({1, 1});       // x and y sampling
    }
    chlist += '\0';
    const Chromaticities& c = options.chromaticities;
    // Attributes in alphabetical order, as the OpenEXR library writes them.
    append_attribute(out, "channels", "chlist", chlist);
    append_attribute(out, "chromaticities", "chromaticities",
                     le_floats({c.red[0], c.red[1], c.green[0], c.green[1], c.blue[0],
                                c.blue[1], c.white[0], c.white[1]}));
    append_attribute(out, "compression", "compression", std::string(1, '\0'));  // NONE
    append_attribute(out, "dataWindow", "box2i", le_ints({0, 0, w - 1, h - 1}));
    append_attribute(out, "displayWindow", "box2i", le_ints({0, 0, w - 1, h - 1}));
    append_attribute(out, "lineOrder", "lineOrder", std::string(1, '\0'));  // INCREASING_Y
    append_attribute(out, "pixelAspectRatio", "float", le_floats({1.0f}));
    append_attribute(out, "screenWindowCenter", "v2f", le_floats({0.0f, 0.0f}));
    append_attribute(out, "screenWindowWidth", "float", le_floats({1.0f}));
    out += '\0';  // end of header

    // Uncompressed: one scanline per block, each block = y, byte count, then B, G, R rows.
    const std::uint32_t data_bytes = static_cast<std::uint32_t>(w) * 3 * 4;
    const std::uint64_t table_end = out.size() + static_cast<std::uint64_t>(h) * 8;
    for (int y = 0; y < h; ++y) append_le64(out, table_end + std::uint64_t{8 + data_bytes} * y);
    for (int y = 0; y < h; ++y) {
        append_le32(out, static_cast<std::uint32_t>(y));
        append_le32(out, data_bytes);
        for (int offset : kChannelOffset) {
            const float* row = image.pixel(0, y);
            for (int x = 0; x < w; ++x) append_le_float(out, row[3 * x + offset]);
        }
    }
    return out;
}

}  // namespace spt

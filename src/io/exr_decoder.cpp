// OpenEXR reader for the files the renderer writes (src/io/exr_writer.cpp): single-part
// scanline, no compression, HALF or FLOAT channels. R, G, B (and A) give an RGB(A) image,
// a lone Y a grey one; other channels (spectral bands) are skipped. Linear values.
#include <bit>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>

#include "io/image_decoders.h"

namespace spt {

namespace {

struct ExrInput {
    std::string_view s;

    void need(std::size_t at, std::size_t n, const char* what) const {
        if (at > s.size() || s.size() - at < n)
            throw ImageDecodeError(std::string("OpenEXR: the file ends inside ") + what + " (truncated file)");
    }
    std::uint32_t u32(std::size_t at, const char* what) const {
        need(at, 4, what);
        std::uint32_t v = 0;
        for (int i = 3; i >= 0; --i) v = v << 8 | std::uint8_t(s[at + static_cast<std::size_t>(i)]);
        return v;
    }
    std::uint64_t u64(std::size_t at, const char* what) const {
        return u32(at, what) | std::uint64_t(u32(at + 4, what)) << 32;
    }
    std::string cstring(std::size_t& at, const char* what) const {
        const std::size_t end = s.find('\0', at);
        if (end == std::string_view::npos || end - at > 255) throw ImageDecodeError(std::string("OpenEXR: bad ") + what);
        std::string text(s.substr(at, end - at));
        at = end + 1;
        return text;
    }
};

float half_to_float(std::uint16_t h) {
    const std::uint32_t sign = std::uint32_t(h & 0x8000u) << 16, exp = (h >> 10) & 0x1fu, mant = h & 0x3ffu;
    if (exp == 0) return (sign ? -1.f : 1.f) * std::ldexp(static_cast<float>(mant), -24);  // zero, subnormal
    if (exp == 31) return std::bit_cast<float>(sign | 0x7f800000u | mant << 13);            // inf, NaN
    return std::bit_cast<float>(sign | (exp + 112) << 23 | mant << 13);
}

struct Channel {
    std::string name;
    int type;  ///< 1 HALF, 2 FLOAT
};

}  // namespace

DecodedImage decode_exr(std::string_view s) {
    const ExrInput in{s};
    if (in.u32(0, "the magic number") != 20000630u) throw ImageDecodeError("not an OpenEXR file (bad magic number)");
    const std::uint32_t version = in.u32(4, "the version");
    if ((version & 0xff) != 2) throw ImageDecodeError("OpenEXR version " + std::to_string(version & 0xff) + "; expected 2");
    if (version & 0x1a00u) throw ImageDecodeError("tiled, deep or multi-part OpenEXR is not supported; expected a scanline file");
    std::size_t at = 8;
    std::map<std::string, std::string_view> attributes;
    for (;;) {
        in.need(at, 1, "the header");
        if (s[at] == '\0') break;
        const std::string name = in.cstring(at, "attribute name");
        in.cstring(at, "attribute type");
        const std::uint32_t size = in.u32(at, "an attribute");
        in.need(at + 4, size, "an attribute");
        attributes[name] = s.substr(at + 4, size);
        at += 4 + size;
    }
    ++at;
    auto attribute = [&](const char* name, std::size_t min_size) {
        auto it = attributes.find(name);
        if (it == attributes.end() || it->second.size() < min_size)
            throw ImageDecodeError(std::string("OpenEXR header has no valid ") + name + " attribute");
        return it->second;
    };
    if (attribute("compression", 1)[0] != 0)
        throw ImageDecodeError("compressed OpenEXR is not supported; expected compression NONE (as the renderer writes)");
    const ExrInput window{attribute("dataWindow", 16)};
    const auto x0 = static_cast<std::int32_t>(window.u32(0, "")), y0 = static_cast<std::int32_t>(window.u32(4, ""));
    const auto x1 = static_cast<std::int32_t>(window.u32(8, "")), y1 = static_cast<std::int32_t>(window.u32(12, ""));
    const long long w = static_cast<long long>(x1) - x0 + 1, h = static_cast<long long>(y1) - y0 + 1;
    check_image_size(w, h);
    std::vector<Channel> channels;
    {
        const std::string_view list = attribute("channels", 1);
        const ExrInput cl{list};
        std::size_t p = 0;
        while (p < list.size() && list[p] != '\0') {
            Channel c;
            c.name = cl.cstring(p, "channel name");
            c.type = static_cast<int>(cl.u32(p, "the channel list"));
            cl.need(p, 16, "the channel list");
            if (cl.u32(p + 8, "") != 1 || cl.u32(p + 12, "") != 1)
                throw ImageDecodeError("OpenEXR channel " + c.name + " is subsampled; expected full resolution");
            if (c.type != 1 && c.type != 2)
                throw ImageDecodeError("OpenEXR channel " + c.name + " is UINT; expected HALF or FLOAT");
            channels.push_back(c);
            p += 16;
        }
    }
    // Where each wanted channel sits in a scanline block, and its type.
    std::map<std::string, std::pair<std::size_t, int>> where;
    std::size_t line_bytes = 0;
    for (const Channel& c : channels) {
        where[c.name] = {line_bytes, c.type};
        line_bytes += static_cast<std::size_t>(w) * (c.type == 2 ? 4 : 2);
    }
    std::vector<std::string> wanted;
    if (where.count("R") && where.count("G") && where.count("B")) wanted = {"R", "G", "B"};
    else if (where.count("Y")) wanted = {"Y"};
    else throw ImageDecodeError("OpenEXR file has neither R, G, B nor Y channels");
    if (wanted.size() == 3 && where.count("A")) wanted.push_back("A");

    const std::size_t table = at;
    in.need(table, static_cast<std::size_t>(h) * 8, "the offset table");
    // Every scanline's block (8-byte header and its data) must fit in the file.
    if ((s.size() - table) / static_cast<std::size_t>(h) < 16 + line_bytes)
        throw ImageDecodeError("OpenEXR file is shorter than its " + std::to_string(h) + " scanlines need (truncated file)");
    DecodedImage img;
    img.width = static_cast<int>(w), img.height = static_cast<int>(h), img.channels = static_cast<int>(wanted.size());
    img.values.resize(static_cast<std::size_t>(w * h) * wanted.size());
    for (long long row = 0; row < h; ++row) {
        const std::uint64_t offset = in.u64(table + static_cast<std::size_t>(row) * 8, "the offset table");
        if (offset > s.size()) throw ImageDecodeError("OpenEXR offset table points past the end of the file (truncated file)");
        const auto block = static_cast<std::size_t>(offset);
        const auto y = static_cast<std::int32_t>(in.u32(block, "a scanline block"));
        const std::uint32_t size = in.u32(block + 4, "a scanline block");
        if (y < y0 || y > y1) throw ImageDecodeError("OpenEXR scanline " + std::to_string(y) + " is outside the data window");
        if (size != line_bytes) throw ImageDecodeError("OpenEXR scanline block has the wrong size for uncompressed data");
        in.need(block + 8, line_bytes, "a scanline block");
        const std::size_t out_row = static_cast<std::size_t>(y - y0);
        for (std::size_t k = 0; k < wanted.size(); ++k) {
            const auto [start, type] = where[wanted[k]];
            for (std::size_t x = 0; x < static_cast<std::size_t>(w); ++x) {
                const std::size_t src = block + 8 + start + x * (type == 2 ? 4 : 2);
                float v;
                if (type == 2) v = std::bit_cast<float>(in.u32(src, ""));
                else v = half_to_float(static_cast<std::uint16_t>(std::uint8_t(s[src]) | std::uint8_t(s[src + 1]) << 8));
                img.values[(out_row * static_cast<std::size_t>(w) + x) * wanted.size() + k] = v;
            }
        }
    }
    return img;
}

}  // namespace spt

// OpenEXR reader: single-part scan-line or tiled files (of a tiled file with mipmap or ripmap
// levels, level 0), compression NONE, RLE, ZIPS, ZIP or PIZ, HALF, FLOAT or UINT channels at
// full resolution. R, G, B (and A) give an RGB(A) image, a lone Y a grey one; other channels
// (spectral bands, layers) are skipped. Values are linear, as stored.
//
// Before the image is allocated, every chunk's header is read and its stored size checked
// against the file and against the most its compression can expand (1032:1 for DEFLATE), so
// a small file cannot make the reader allocate a large image.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>

#include "io/exr_compression.h"
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
    std::int32_t i32(std::size_t at, const char* what) const { return static_cast<std::int32_t>(u32(at, what)); }
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

float half_bits_to_float(std::uint16_t h) {
    const std::uint32_t sign = std::uint32_t(h & 0x8000u) << 16, exp = (h >> 10) & 0x1fu, mant = h & 0x3ffu;
    if (exp == 0) return (sign ? -1.f : 1.f) * std::ldexp(static_cast<float>(mant), -24);  // zero, subnormal
    if (exp == 31) return std::bit_cast<float>(sign | 0x7f800000u | mant << 13);            // inf, NaN
    return std::bit_cast<float>(sign | (exp + 112) << 23 | mant << 13);
}

/// Every half's float value (256 KiB, built once): a lookup is cheaper than the bit shuffling.
const float* half_table() {
    static const std::vector<float> table = [] {
        std::vector<float> t(65536);
        for (unsigned i = 0; i < 65536; ++i) t[i] = half_bits_to_float(static_cast<std::uint16_t>(i));
        return t;
    }();
    return table.data();
}

enum class PixelType { uint = 0, half = 1, floating = 2 };

struct Channel {
    std::string name;
    PixelType type;
    std::size_t bytes() const { return type == PixelType::half ? 2 : 4; }
};

constexpr const char* kCompressionNames[] = {"NONE", "RLE", "ZIPS", "ZIP", "PIZ", "PXR24", "B44", "B44A", "DWAA", "DWAB"};
enum Compression { kNone = 0, kRle = 1, kZips = 2, kZip = 3, kPiz = 4 };

/// Scan lines per chunk of a scan-line file.
int lines_per_chunk(int compression) { return compression == kZip ? 16 : compression == kPiz ? 32 : 1; }

/// The most a chunk's pixel data can exceed its stored size (RLE: 2 bytes → 128; DEFLATE's
/// longest match of 258 bytes costs at least 2 bits; PIZ's run symbol of at least 1 bit and
/// 8 bits of count gives up to 255 values of 2 bytes).
std::size_t max_expansion(int compression) {
    switch (compression) {
        case kNone: return 1;
        case kRle: return 64;
        default: return 1032;
    }
}

/// One chunk: where its stored pixel data is, and the pixels it covers.
struct Chunk {
    std::string_view data;
    int x = 0, y = 0, width = 0, lines = 0;  ///< relative to the data window's corner
};

}  // namespace

DecodedImage decode_exr(std::string_view s) {
    const ExrInput in{s};
    if (in.u32(0, "the magic number") != 20000630u) throw ImageDecodeError("not an OpenEXR file (bad magic number)");
    const std::uint32_t version = in.u32(4, "the version");
    if ((version & 0xff) != 2) throw ImageDecodeError("OpenEXR version " + std::to_string(version & 0xff) + "; expected 2");
    if (version & 0x800u) throw ImageDecodeError("deep OpenEXR data is not supported; expected a scan-line or tiled image");
    if (version & 0x1000u)
        throw ImageDecodeError("multi-part OpenEXR is not supported; expected a single-part scan-line or tiled image");
    const bool tiled = (version & 0x200u) != 0;
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
    const int compression = static_cast<unsigned char>(attribute("compression", 1)[0]);
    if (compression > kPiz) {
        const std::string name = compression < 10 ? kCompressionNames[compression] : "number " + std::to_string(compression);
        throw ImageDecodeError("OpenEXR compression " + name + " is not supported; expected NONE, RLE, ZIPS, ZIP or PIZ");
    }
    const ExrInput window{attribute("dataWindow", 16)};
    const std::int32_t x0 = window.i32(0, ""), y0 = window.i32(4, "");
    const std::int32_t x1 = window.i32(8, ""), y1 = window.i32(12, "");
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
            const std::uint32_t type = cl.u32(p, "the channel list");
            cl.need(p, 16, "the channel list");
            if (cl.u32(p + 8, "") != 1 || cl.u32(p + 12, "") != 1)
                throw ImageDecodeError("OpenEXR channel " + c.name + " is subsampled; expected full resolution");
            if (type > 2)
                throw ImageDecodeError("OpenEXR channel " + c.name + " has pixel type " + std::to_string(type) +
                                       "; expected UINT (0), HALF (1) or FLOAT (2)");
            c.type = static_cast<PixelType>(type);
            channels.push_back(c);
            p += 16;
        }
    }
    if (channels.empty()) throw ImageDecodeError("OpenEXR file has no channels");
    // Each channel's byte offset within one scan line of a chunk, per pixel of the chunk's width.
    std::map<std::string, std::size_t> index;
    std::vector<std::size_t> before(channels.size());
    std::size_t pixel_bytes = 0;
    for (std::size_t k = 0; k < channels.size(); ++k) {
        index[channels[k].name] = k;
        before[k] = pixel_bytes;
        pixel_bytes += channels[k].bytes();
    }
    std::vector<std::size_t> wanted;
    if (index.count("R") && index.count("G") && index.count("B")) wanted = {index["R"], index["G"], index["B"]};
    else if (index.count("Y")) wanted = {index["Y"]};
    else throw ImageDecodeError("OpenEXR file has neither R, G, B nor Y channels");
    if (wanted.size() == 3 && index.count("A")) wanted.push_back(index["A"]);

    // The chunk grid: scan-line blocks, or the tiles of level 0.
    long long tile_w = w, tile_h = lines_per_chunk(compression), tiles_x = 1;
    if (tiled) {
        const ExrInput tiles{attribute("tiles", 9)};
        tile_w = tiles.u32(0, ""), tile_h = tiles.u32(4, "");
        const int level_mode = static_cast<unsigned char>(tiles.s[8]) & 0x0f;
        if (level_mode > 2)
            throw ImageDecodeError("OpenEXR tile level mode " + std::to_string(level_mode) +
                                   " is unknown; expected ONE_LEVEL, MIPMAP_LEVELS or RIPMAP_LEVELS");
        if (tile_w < 1 || tile_h < 1 || tile_w > kMaxTextureTexels || tile_h > kMaxTextureTexels)
            throw ImageDecodeError("OpenEXR tile size " + std::to_string(tile_w) + "x" + std::to_string(tile_h) +
                                   " is invalid; expected a positive size");
        tile_w = std::min(tile_w, w), tile_h = std::min(tile_h, h);
        tiles_x = (w + tile_w - 1) / tile_w;
    }
    const long long tiles_y = (h + tile_h - 1) / tile_h, count = tiles_x * tiles_y;
    const std::size_t table = at;
    in.need(table, static_cast<std::size_t>(count) * 8, "the offset table");
    const std::size_t header_bytes = tiled ? 20 : 8;
    // Every chunk's header and stored size, checked before anything is allocated.
    std::vector<Chunk> chunks(static_cast<std::size_t>(count));
    for (long long i = 0; i < count; ++i) {
        const std::uint64_t offset = in.u64(table + static_cast<std::size_t>(i) * 8, "the offset table");
        if (offset > s.size() || s.size() - offset < header_bytes)
            throw ImageDecodeError("OpenEXR chunk " + std::to_string(i) + "'s offset " + std::to_string(offset) +
                                   " is past the end of the file (truncated file)");
        const auto block = static_cast<std::size_t>(offset);
        Chunk& c = chunks[static_cast<std::size_t>(i)];
        const long long tx = i % tiles_x, ty = i / tiles_x;
        if (tiled) {
            const std::int32_t fx = in.i32(block, ""), fy = in.i32(block + 4, ""), lx = in.i32(block + 8, ""),
                               ly = in.i32(block + 12, "");
            if (fx != tx || fy != ty || lx != 0 || ly != 0)
                throw ImageDecodeError("OpenEXR tile " + std::to_string(i) + " says it is tile (" + std::to_string(fx) +
                                       ", " + std::to_string(fy) + ") of level (" + std::to_string(lx) + ", " +
                                       std::to_string(ly) + "); expected tile (" + std::to_string(tx) + ", " +
                                       std::to_string(ty) + ") of level (0, 0)");
        } else {
            const std::int32_t fy = in.i32(block, "");
            if (static_cast<long long>(fy) != y0 + ty * tile_h)
                throw ImageDecodeError("OpenEXR chunk " + std::to_string(i) + " starts at scan line " + std::to_string(fy) +
                                       "; expected " + std::to_string(y0 + ty * tile_h));
        }
        const std::uint32_t size = in.u32(block + header_bytes - 4, "");
        if (s.size() - block - header_bytes < size)
            throw ImageDecodeError("OpenEXR chunk " + std::to_string(i) + " has " + std::to_string(size) +
                                   " bytes of pixel data; the file has only " +
                                   std::to_string(s.size() - block - header_bytes) + " after it (truncated file)");
        c.data = s.substr(block + header_bytes, size);
        c.x = static_cast<int>(tx * tile_w), c.y = static_cast<int>(ty * tile_h);
        c.width = static_cast<int>(std::min(tile_w, w - c.x)), c.lines = static_cast<int>(std::min(tile_h, h - c.y));
        const std::size_t raw = static_cast<std::size_t>(c.width) * static_cast<std::size_t>(c.lines) * pixel_bytes;
        if (size > raw || (size < raw && (compression == kNone || size * max_expansion(compression) < raw)))
            throw ImageDecodeError("OpenEXR chunk " + std::to_string(i) + " has " + std::to_string(size) +
                                   " bytes of pixel data; " + kCompressionNames[compression] + " data for its " +
                                   std::to_string(c.width) + "x" + std::to_string(c.lines) + " pixels must be " +
                                   (compression == kNone ? "exactly " : "at most ") + std::to_string(raw));
    }

    DecodedImage img;
    img.width = static_cast<int>(w), img.height = static_cast<int>(h), img.channels = static_cast<int>(wanted.size());
    const std::size_t nc = wanted.size();
    img.values.resize(static_cast<std::size_t>(w * h) * nc);
    std::vector<std::uint8_t> buffer;
    std::vector<PizChannel> piz;
    const float* halves = half_table();
    for (const Chunk& c : chunks) {
        const std::size_t cw = static_cast<std::size_t>(c.width);
        const std::size_t raw_size = cw * static_cast<std::size_t>(c.lines) * pixel_bytes;
        const std::uint8_t* raw = reinterpret_cast<const std::uint8_t*>(c.data.data());
        // A chunk that would not shrink is stored uncompressed, whatever the file's compression.
        if (c.data.size() < raw_size) {
            switch (compression) {
                case kRle: exr_uncompress_rle(c.data, buffer, raw_size); break;
                case kZips:
                case kZip: exr_uncompress_zip(c.data, buffer, raw_size); break;
                default:
                    piz.clear();
                    for (const Channel& ch : channels) piz.push_back({c.width, c.lines, ch.type == PixelType::half ? 1 : 2});
                    exr_uncompress_piz(c.data, buffer, raw_size, piz);
            }
            raw = buffer.data();
        }
        for (int line = 0; line < c.lines; ++line) {
            const std::uint8_t* row = raw + static_cast<std::size_t>(line) * cw * pixel_bytes;
            float* out = img.values.data() +
                         (static_cast<std::size_t>(c.y + line) * static_cast<std::size_t>(w) + static_cast<std::size_t>(c.x)) * nc;
            for (std::size_t k = 0; k < nc; ++k) {
                const Channel& ch = channels[wanted[k]];
                const std::uint8_t* src = row + before[wanted[k]] * cw;
                if (ch.type == PixelType::half) {
                    for (std::size_t x = 0; x < cw; ++x)
                        out[x * nc + k] = halves[src[2 * x] | src[2 * x + 1] << 8];
                } else {
                    for (std::size_t x = 0; x < cw; ++x) {
                        const std::uint32_t bits = std::uint32_t(src[4 * x]) | std::uint32_t(src[4 * x + 1]) << 8 |
                                                   std::uint32_t(src[4 * x + 2]) << 16 | std::uint32_t(src[4 * x + 3]) << 24;
                        out[x * nc + k] = ch.type == PixelType::floating ? std::bit_cast<float>(bits) : static_cast<float>(bits);
                    }
                }
            }
        }
    }
    return img;
}

}  // namespace spt

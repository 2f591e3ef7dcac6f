// PNG reader (ISO/IEC 15948): every colour type (grey, grey + alpha, RGB, RGBA, palette with
// optional tRNS alpha) at every bit depth the format allows (1, 2, 4, 8, 16), all five
// scanline filters, chunk CRCs checked, our own inflate. Interlaced (Adam7) files are
// refused with a clear error.
#include <array>
#include <cstdint>
#include <string>

#include "io/checksums.h"
#include "io/image_decoders.h"
#include "io/inflate.h"

namespace spt {

namespace {

std::uint32_t be32(std::string_view s, std::size_t at) {
    return std::uint32_t(std::uint8_t(s[at])) << 24 | std::uint32_t(std::uint8_t(s[at + 1])) << 16 |
           std::uint32_t(std::uint8_t(s[at + 2])) << 8 | std::uint32_t(std::uint8_t(s[at + 3]));
}

int paeth(int a, int b, int c) {
    const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
    if (pa <= pb && pa <= pc) return a;
    return pb <= pc ? b : c;
}

/// Samples per pixel in the file for a colour type (0 for an invalid type).
int file_channels(int color_type) {
    switch (color_type) {
        case 0: return 1;
        case 2: return 3;
        case 3: return 1;
        case 4: return 2;
        case 6: return 4;
        default: return 0;
    }
}

bool depth_allowed(int color_type, int depth) {
    switch (color_type) {
        case 0: return depth == 1 || depth == 2 || depth == 4 || depth == 8 || depth == 16;
        case 3: return depth == 1 || depth == 2 || depth == 4 || depth == 8;
        default: return depth == 8 || depth == 16;
    }
}

}  // namespace

DecodedImage decode_png(std::string_view s) {
    static constexpr std::string_view kSignature("\x89PNG\r\n\x1a\n", 8);
    if (!s.starts_with(kSignature)) throw ImageDecodeError("not a PNG file (bad signature)");
    std::size_t at = 8;
    long long width = 0, height = 0;
    int depth = 0, color_type = -1;
    std::vector<std::array<std::uint8_t, 4>> palette;
    std::string idat;
    bool seen_header = false, seen_end = false;
    while (!seen_end) {
        if (at + 12 > s.size()) throw ImageDecodeError("the file ends inside a chunk header (truncated PNG)");
        const std::uint32_t length = be32(s, at);
        const std::string_view type = s.substr(at + 4, 4);
        if (length > 0x7fffffffu || at + 12 + length > s.size())
            throw ImageDecodeError("chunk " + std::string(type) + " runs past the end of the file (truncated PNG)");
        const std::string_view data = s.substr(at + 8, length);
        if (crc32(s.substr(at + 4, 4 + length)) != be32(s, at + 8 + length))
            throw ImageDecodeError("chunk " + std::string(type) + " has a wrong CRC (corrupt PNG)");
        at += 12 + length;
        if (!seen_header && type != "IHDR") throw ImageDecodeError("the first chunk is not IHDR");
        if (type == "IHDR") {
            if (seen_header || length != 13) throw ImageDecodeError("bad IHDR chunk");
            seen_header = true;
            width = be32(data, 0), height = be32(data, 4);
            depth = std::uint8_t(data[8]), color_type = std::uint8_t(data[9]);
            if (file_channels(color_type) == 0)
                throw ImageDecodeError("unknown PNG colour type " + std::to_string(color_type));
            if (!depth_allowed(color_type, depth))
                throw ImageDecodeError("bit depth " + std::to_string(depth) + " is not allowed for colour type " +
                                       std::to_string(color_type));
            if (data[10] != 0 || data[11] != 0) throw ImageDecodeError("unknown PNG compression or filter method");
            if (data[12] == 1)
                throw ImageDecodeError("interlaced (Adam7) PNG is not supported; expected a non-interlaced PNG");
            if (data[12] != 0) throw ImageDecodeError("unknown PNG interlace method");
            check_image_size(width, height);
        } else if (type == "PLTE") {
            if (length % 3 != 0 || length == 0 || length > 768) throw ImageDecodeError("bad PLTE chunk");
            palette.clear();
            for (std::size_t i = 0; i < length; i += 3)
                palette.push_back({std::uint8_t(data[i]), std::uint8_t(data[i + 1]), std::uint8_t(data[i + 2]), 255});
        } else if (type == "tRNS") {
            if (color_type == 3) {
                if (length > palette.size()) throw ImageDecodeError("tRNS has more entries than the palette");
                for (std::size_t i = 0; i < length; ++i) palette[i][3] = std::uint8_t(data[i]);
            }
            // Grey or RGB key colours are not applied: a texture's colour stays as stored.
        } else if (type == "IDAT") {
            idat.append(data);
        } else if (type == "IEND") {
            seen_end = true;
        } else if (!(type[0] & 0x20)) {  // an unknown critical chunk (upper-case first letter)
            throw ImageDecodeError("unknown critical chunk " + std::string(type));
        }
    }
    if (color_type == 3 && palette.empty()) throw ImageDecodeError("a palette image has no PLTE chunk");
    if (idat.empty()) throw ImageDecodeError("no IDAT chunk (no image data)");

    const int in_channels = file_channels(color_type);
    const std::size_t row_bytes = (static_cast<std::size_t>(width) * in_channels * depth + 7) / 8;
    const std::size_t bpp = std::max<std::size_t>(1, static_cast<std::size_t>(in_channels * depth / 8));
    std::vector<std::uint8_t> raw;
    try {
        raw = zlib_decompress(idat, static_cast<std::size_t>(height) * (row_bytes + 1));
    } catch (const InflateError& e) {
        throw ImageDecodeError(std::string("corrupt compressed image data: ") + e.what());
    }

    // Undo the filters in place, row by row (each row: filter byte, then row_bytes).
    std::vector<std::uint8_t> pixels(static_cast<std::size_t>(height) * row_bytes);
    for (std::size_t y = 0; y < static_cast<std::size_t>(height); ++y) {
        const std::uint8_t filter = raw[y * (row_bytes + 1)];
        const std::uint8_t* in = &raw[y * (row_bytes + 1) + 1];
        std::uint8_t* out = &pixels[y * row_bytes];
        const std::uint8_t* up = y > 0 ? out - row_bytes : nullptr;
        for (std::size_t i = 0; i < row_bytes; ++i) {
            const int a = i >= bpp ? out[i - bpp] : 0, b = up ? up[i] : 0, c = (up && i >= bpp) ? up[i - bpp] : 0;
            int pred;
            switch (filter) {
                case 0: pred = 0; break;
                case 1: pred = a; break;
                case 2: pred = b; break;
                case 3: pred = (a + b) / 2; break;
                case 4: pred = paeth(a, b, c); break;
                default: throw ImageDecodeError("unknown scanline filter type " + std::to_string(filter));
            }
            out[i] = static_cast<std::uint8_t>(in[i] + pred);
        }
    }

    DecodedImage img;
    img.width = static_cast<int>(width), img.height = static_cast<int>(height);
    img.integer_codes = true;
    const bool palette_alpha = color_type == 3 && [&] {
        for (const auto& p : palette)
            if (p[3] != 255) return true;
        return false;
    }();
    img.channels = color_type == 3 ? (palette_alpha ? 4 : 3) : in_channels;
    img.values.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) *
                      static_cast<std::size_t>(img.channels));
    const float max_code = static_cast<float>((1u << depth) - 1u);
    std::size_t o = 0;
    for (std::size_t y = 0; y < static_cast<std::size_t>(height); ++y) {
        const std::uint8_t* row = &pixels[y * row_bytes];
        for (std::size_t x = 0; x < static_cast<std::size_t>(width); ++x) {
            for (int c = 0; c < in_channels; ++c) {
                const std::size_t sample = x * static_cast<std::size_t>(in_channels) + static_cast<std::size_t>(c);
                unsigned code;
                if (depth == 16) code = unsigned(row[2 * sample]) << 8 | row[2 * sample + 1];
                else if (depth == 8) code = row[sample];
                else {  // 1, 2 or 4 bits, most significant first
                    const std::size_t bit = sample * static_cast<std::size_t>(depth);
                    code = (row[bit / 8] >> (8 - depth - bit % 8)) & ((1u << depth) - 1u);
                }
                if (color_type == 3) {
                    if (code >= palette.size())
                        throw ImageDecodeError("a pixel's palette index " + std::to_string(code) +
                                               " is beyond the palette's " + std::to_string(palette.size()) +
                                               " entries");
                    for (int k = 0; k < img.channels; ++k) img.values[o++] = palette[code][static_cast<std::size_t>(k)] / 255.f;
                } else {
                    img.values[o++] = static_cast<float>(code) / max_code;
                }
            }
        }
    }
    return img;
}

}  // namespace spt

// Radiance picture reader (.hdr, .pic): a text header ("#?RADIANCE" or "#?RGBE", variable
// lines, a blank line), the resolution line "-Y height +X width" (rows top to bottom, the
// standard orientation; the seven others are an error), then one RGBE pixel per texel:
// three 8-bit mantissas sharing an exponent byte. Scan lines are either run-length coded per
// component (the "new" form: 2, 2, width) or flat pixels where (1, 1, 1, n) repeats the
// previous pixel (the "old" form).
//
// A texel is m · 2^(e − 136) per component (0 when e = 0), exact in float. Radiance's own
// tools add 0.5 to the mantissa (the centre of its rounding interval) and divide by the
// EXPOSURE lines of the header; pbrt-v4 (stb_image), Mitsuba 3 and Walter's rgbe.c do
// neither, and the reader follows them so renders of the same map compare. EXPOSURE,
// PRIMARIES and the other variables are ignored.
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <string>

#include "io/image_decoders.h"

namespace spt {

namespace {

[[noreturn]] void fail(const std::string& what) { throw ImageDecodeError("Radiance HDR: " + what); }

}  // namespace

DecodedImage decode_rgbe(std::string_view s) {
    if (!s.starts_with("#?")) fail("no \"#?\" signature; expected a file starting \"#?RADIANCE\" or \"#?RGBE\"");
    std::size_t at = 0;
    constexpr std::size_t kMaxLine = 4096;
    auto line = [&](const char* what) {
        const std::size_t end = s.find('\n', at);
        if (end == std::string_view::npos) fail(std::string("the file ends inside ") + what + " (truncated file)");
        if (end - at > kMaxLine) fail(std::string("a line of ") + what + " is longer than 4096 bytes");
        const std::string_view text = s.substr(at, end - at);
        at = end + 1;
        return text;
    };
    line("the header");
    for (;;) {
        const std::string_view text = line("the header");
        if (text.empty()) break;
        if (text.starts_with("FORMAT=") && text != "FORMAT=32-bit_rle_rgbe")
            fail("format \"" + std::string(text.substr(7)) + "\" is not supported; expected 32-bit_rle_rgbe");
    }
    const std::string resolution(line("the resolution line"));
    long long h = 0, w = 0;
    {
        char ys = 0, yc = 0, xs = 0, xc = 0;
        long long a = 0, b = 0;
        int used = 0;
        if (std::sscanf(resolution.c_str(), "%c%c %lld %c%c %lld%n", &ys, &yc, &a, &xs, &xc, &b, &used) != 6 ||
            static_cast<std::size_t>(used) != resolution.size() || (ys != '-' && ys != '+') || (xs != '-' && xs != '+') ||
            !((yc == 'Y' && xc == 'X') || (yc == 'X' && xc == 'Y')))
            fail("resolution line \"" + resolution + "\" is not understood; expected \"-Y height +X width\"");
        if (ys != '-' || yc != 'Y' || xs != '+' || xc != 'X')
            fail("resolution line \"" + resolution +
                 "\" stores the image in an orientation other than the standard one; expected \"-Y height +X width\"");
        h = a, w = b;
    }
    check_image_size(w, h);
    // Rows are appended as they are decoded (old-style repeats can expand 16 bytes to 2^24
    // texels, so no bound on the file size holds): a truncated file fails before its image
    // is allocated in full. Files of at least a byte per 32 texels (real pictures) reserve
    // the whole image at once.
    DecodedImage img;
    img.width = static_cast<int>(w), img.height = static_cast<int>(h), img.channels = 3;
    const std::size_t texels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    if ((s.size() - at) * 32 >= texels) img.values.reserve(texels * 3);
    const auto width = static_cast<std::size_t>(w);
    std::vector<std::uint8_t> row(width * 4);
    // 2^(e − 136) for each exponent byte (0 for e = 0): powers of two from 2^-135 to 2^119,
    // so the product with an 8-bit mantissa is exact.
    float scale[256];
    scale[0] = 0.f;
    for (int e = 1; e < 256; ++e) scale[e] = std::ldexp(1.f, e - 136);
    auto byte = [&]() -> std::uint8_t {
        if (at >= s.size()) fail("the file ends inside the pixels (truncated file)");
        return static_cast<std::uint8_t>(s[at++]);
    };
    for (std::size_t y = 0; y < static_cast<std::size_t>(h); ++y) {
        const bool rle = width >= 8 && width < 0x8000 && s.size() - at >= 4 && s[at] == 2 && s[at + 1] == 2 &&
                         (static_cast<unsigned char>(s[at + 2]) & 0x80) == 0;
        if (rle) {
            const std::size_t stated = static_cast<std::size_t>(static_cast<unsigned char>(s[at + 2])) << 8 |
                                       static_cast<unsigned char>(s[at + 3]);
            if (stated != width)
                fail("scan line " + std::to_string(y) + " says it is " + std::to_string(stated) + " texels wide; expected " +
                     std::to_string(width));
            at += 4;
            for (std::size_t c = 0; c < 4; ++c) {
                for (std::size_t x = 0; x < width;) {
                    unsigned n = byte();
                    if (n > 128) {
                        n -= 128;
                        if (n > width - x) fail("a run in scan line " + std::to_string(y) + " is longer than the line");
                        const std::uint8_t v = byte();
                        for (unsigned i = 0; i < n; ++i) row[(x++) * 4 + c] = v;
                    } else {
                        if (n == 0) fail("scan line " + std::to_string(y) + " has a literal run of length 0 (corrupt file)");
                        if (n > width - x) fail("a run in scan line " + std::to_string(y) + " is longer than the line");
                        for (unsigned i = 0; i < n; ++i) row[(x++) * 4 + c] = byte();
                    }
                }
            }
        } else {
            int shift = 0;
            for (std::size_t x = 0; x < width;) {
                std::uint8_t p[4] = {byte(), byte(), byte(), byte()};
                if (p[0] == 1 && p[1] == 1 && p[2] == 1) {
                    if (x == 0) fail("scan line " + std::to_string(y) + " starts with a repeat (corrupt file)");
                    if (shift > 16) fail("scan line " + std::to_string(y) + " has a repeat count past 2^24 (corrupt file)");
                    const std::size_t n = static_cast<std::size_t>(p[3]) << shift;
                    if (n > width - x) fail("a repeat in scan line " + std::to_string(y) + " is longer than the line");
                    for (std::size_t i = 0; i < n; ++i, ++x)
                        for (std::size_t c = 0; c < 4; ++c) row[x * 4 + c] = row[(x - 1) * 4 + c];
                    shift += 8;
                } else {
                    for (std::size_t c = 0; c < 4; ++c) row[x * 4 + c] = p[c];
                    ++x;
                    shift = 0;
                }
            }
        }
        img.values.resize((y + 1) * width * 3);
        float* out = img.values.data() + y * width * 3;
        for (std::size_t x = 0; x < width; ++x) {
            const float f = scale[row[x * 4 + 3]];
            for (std::size_t c = 0; c < 3; ++c) out[x * 3 + c] = static_cast<float>(row[x * 4 + c]) * f;
        }
    }
    return img;
}

}  // namespace spt

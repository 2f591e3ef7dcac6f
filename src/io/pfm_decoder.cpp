// PFM reader: "PF" (RGB) or "Pf" (grey), width and height, then the scale, whose sign gives
// the byte order (negative: little-endian); float rows stored bottom to top. Linear values.
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "io/image_decoders.h"

namespace spt {

DecodedImage decode_pfm(std::string_view s) {
    const bool rgb = s.starts_with("PF");
    if (!rgb && !s.starts_with("Pf")) throw ImageDecodeError("not a PFM file (expected PF or Pf)");
    // The header is three whitespace-separated tokens after the magic; it is short.
    std::size_t at = 2;
    auto token = [&](const char* what) {
        while (at < s.size() && std::isspace(static_cast<unsigned char>(s[at]))) ++at;
        const std::size_t begin = at;
        while (at < s.size() && !std::isspace(static_cast<unsigned char>(s[at])) && at - begin < 64) ++at;
        if (at == begin) throw ImageDecodeError(std::string("PFM header: expected the ") + what + " (truncated)");
        return std::string(s.substr(begin, at - begin));
    };
    auto integer = [&](const char* what) {
        const std::string t = token(what);
        char* end = nullptr;
        const long long v = std::strtoll(t.c_str(), &end, 10);
        if (*end != '\0') throw ImageDecodeError(std::string("PFM header: the ") + what + " is not an integer");
        return v;
    };
    const long long w = integer("width"), h = integer("height");
    check_image_size(w, h);
    const std::string scale_text = token("scale");
    char* end = nullptr;
    const double scale = std::strtod(scale_text.c_str(), &end);
    if (*end != '\0' || !std::isfinite(scale) || scale == 0)
        throw ImageDecodeError("PFM header: the scale is not a finite non-zero number");
    if (at >= s.size()) throw ImageDecodeError("PFM: no pixel data (truncated file)");
    ++at;  // the single whitespace byte before the data
    const bool little = scale < 0;
    DecodedImage img;
    img.width = static_cast<int>(w), img.height = static_cast<int>(h), img.channels = rgb ? 3 : 1;
    const std::size_t row = static_cast<std::size_t>(w) * static_cast<std::size_t>(img.channels);
    const std::size_t n = row * static_cast<std::size_t>(h);
    if (s.size() - at < n * 4)
        throw ImageDecodeError("PFM pixel data is shorter than " + std::to_string(w) + "x" + std::to_string(h) +
                               " pixels need (truncated file)");
    img.values.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        std::uint32_t bits = 0;
        for (int k = 0; k < 4; ++k) {
            const std::uint32_t b = std::uint8_t(s[at + i * 4 + static_cast<std::size_t>(k)]);
            bits |= little ? b << (8 * k) : b << (8 * (3 - k));
        }
        // File rows run bottom to top; ours top to bottom.
        const std::size_t y = i / row, x = i % row;
        img.values[(static_cast<std::size_t>(h) - 1 - y) * row + x] = std::bit_cast<float>(bits);
    }
    return img;
}

}  // namespace spt

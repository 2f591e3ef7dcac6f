// PPM reader: binary P6 (maxval ≤ 255: one byte per sample; ≤ 65535: two, big-endian) and
// ASCII P3 (maxval ≤ 65535), whose codes are sRGB-encoded; and the renderer's HDR P3
// (src/io/ppm_writer.cpp: a "#MAX=M" comment and any maxval R up to 2^53), whose values
// q·M/R are linear.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <string>

#include "io/image_decoders.h"

namespace spt {

namespace {

class PpmHeader {
public:
    explicit PpmHeader(std::string_view s) : m_s(s), m_at(2) {}

    /// The next unsigned integer of the header (whitespace and # comments skipped).
    unsigned long long number(const char* what) {
        skip_space();
        if (m_at >= m_s.size() || !std::isdigit(static_cast<unsigned char>(m_s[m_at])))
            throw ImageDecodeError(std::string("PPM: expected the ") + what + " at byte " + std::to_string(m_at) + " (truncated or not a number)");
        unsigned long long v = 0;
        while (m_at < m_s.size() && std::isdigit(static_cast<unsigned char>(m_s[m_at]))) {
            if (v > (1ull << 60)) throw ImageDecodeError(std::string("PPM: the ") + what + " is too large");
            v = v * 10 + static_cast<unsigned>(m_s[m_at++] - '0');
        }
        return v;
    }
    /// After the maxval: exactly one whitespace byte, then the binary samples.
    std::size_t binary_start() {
        if (m_at >= m_s.size() || !std::isspace(static_cast<unsigned char>(m_s[m_at])))
            throw ImageDecodeError("PPM header: expected one whitespace byte after maxval");
        return m_at + 1;
    }
    /// "#MAX=" value if a comment so far had one (the renderer's HDR PPM), else a negative value.
    double hdr_max() const { return m_hdr_max; }

private:
    std::string_view m_s;
    std::size_t m_at;
    double m_hdr_max = -1;

    void skip_space() {
        while (m_at < m_s.size()) {
            if (m_s[m_at] == '#') {
                const std::size_t end = std::min(m_s.find('\n', m_at), m_s.size());
                const std::string_view comment = m_s.substr(m_at, end - m_at);
                if (comment.starts_with("#MAX=")) {
                    const std::string text(comment.substr(5));
                    char* stop = nullptr;
                    m_hdr_max = std::strtod(text.c_str(), &stop);
                    if (stop == text.c_str() || !std::isfinite(m_hdr_max) || m_hdr_max < 0)
                        throw ImageDecodeError("PPM: the #MAX= comment is not a finite number >= 0");
                }
                m_at = end;
            } else if (std::isspace(static_cast<unsigned char>(m_s[m_at]))) {
                ++m_at;
            } else {
                return;
            }
        }
    }
};

}  // namespace

DecodedImage decode_ppm(std::string_view s) {
    const bool ascii = s.starts_with("P3");
    if (!ascii && !s.starts_with("P6")) throw ImageDecodeError("not a PPM file (expected P3 or P6)");
    PpmHeader h(s);
    const unsigned long long w = h.number("width"), ht = h.number("height");
    check_image_size(static_cast<long long>(std::min(w, 1ull << 40)), static_cast<long long>(std::min(ht, 1ull << 40)));
    const unsigned long long maxval = h.number("maxval");
    const bool hdr = h.hdr_max() >= 0;
    if (maxval == 0 || (maxval > 65535 && !(ascii && hdr)) || maxval > (1ull << 53))
        throw ImageDecodeError("PPM maxval " + std::to_string(maxval) + " is out of range; expected 1 to 65535");
    DecodedImage img;
    img.width = static_cast<int>(w), img.height = static_cast<int>(ht), img.channels = 3;
    img.integer_codes = !hdr;
    const std::size_t n = static_cast<std::size_t>(w * ht * 3);
    const double scale = hdr ? h.hdr_max() / static_cast<double>(maxval) : 1.0 / static_cast<double>(maxval);
    if (ascii) {
        // Each sample takes a digit and a separator: a short file cannot claim a large image.
        if (s.size() < 2 * n)
            throw ImageDecodeError("PPM has fewer bytes than " + std::to_string(w) + "x" + std::to_string(ht) +
                                   " pixels need (truncated file)");
        img.values.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            const unsigned long long q = h.number("sample");
            if (q > maxval) throw ImageDecodeError("PPM sample " + std::to_string(q) + " exceeds maxval");
            img.values[i] = static_cast<float>(static_cast<double>(q) * scale);
        }
        return img;
    }
    const std::size_t start = h.binary_start(), bytes = maxval > 255 ? 2 : 1;
    if (s.size() - std::min(s.size(), start) < n * bytes)
        throw ImageDecodeError("PPM pixel data is shorter than " + std::to_string(w) + "x" + std::to_string(ht) +
                               " pixels need (truncated file)");
    img.values.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        unsigned q = std::uint8_t(s[start + i * bytes]);
        if (bytes == 2) q = q << 8 | std::uint8_t(s[start + i * bytes + 1]);
        if (q > maxval) throw ImageDecodeError("PPM sample " + std::to_string(q) + " exceeds maxval");
        img.values[i] = static_cast<float>(q * scale);
    }
    return img;
}

}  // namespace spt

#include "io/checksums.h"

#include <algorithm>
#include <array>

namespace spt {

std::uint32_t crc32(std::string_view data) {
    static const auto table = [] {
        std::array<std::uint32_t, 256> t{};
        for (std::uint32_t n = 0; n < 256; ++n) {
            std::uint32_t c = n;
            for (int k = 0; k < 8; ++k) c = c & 1 ? 0xedb88320u ^ (c >> 1) : c >> 1;
            t[n] = c;
        }
        return t;
    }();
    std::uint32_t c = 0xffffffffu;
    for (char ch : data) c = table[(c ^ std::uint8_t(ch)) & 0xff] ^ (c >> 8);
    return c ^ 0xffffffffu;
}

std::uint32_t adler32(std::string_view data) {
    std::uint32_t a = 1, b = 0;
    for (std::size_t i = 0; i < data.size();) {
        // 5552 bytes is the most that keeps b below 2^32 before the modulo (zlib's NMAX).
        const std::size_t end = std::min(data.size(), i + 5552);
        for (; i < end; ++i) a += static_cast<unsigned char>(data[i]), b += a;
        a %= 65521u, b %= 65521u;
    }
    return b << 16 | a;
}

std::uint64_t fnv1a64(std::string_view data) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (unsigned char c : data) h = (h ^ c) * 0x100000001b3ull;
    return h;
}

}  // namespace spt

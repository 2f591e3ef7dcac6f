// A small independent OpenEXR reader for the tests (uncompressed single-part scanline FLOAT
// files, the kind our writer makes): little-endian fields, the header's attributes, the
// channel list and each channel's pixels.
#pragma once
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace spt::exr_test {

inline std::uint32_t le32(const std::string& s, std::size_t at) {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = v << 8 | static_cast<std::uint8_t>(s.at(at + i));
    return v;
}
inline std::uint64_t le64(const std::string& s, std::size_t at) {
    return le32(s, at) | static_cast<std::uint64_t>(le32(s, at + 4)) << 32;
}
inline float le_float(const std::string& s, std::size_t at) {
    return std::bit_cast<float>(le32(s, at));
}
inline double le_double(const std::string& s, std::size_t at) {
    return std::bit_cast<double>(le64(s, at));
}

struct HeaderAttribute {
    std::string type, value;
};

inline std::string read_cstring(const std::string& s, std::size_t& at) {
    const std::size_t end = s.find('\0', at);
    if (end == std::string::npos) throw std::runtime_error("unterminated string");
    std::string text = s.substr(at, end - at);
    at = end + 1;
    return text;
}

/// Attributes by name; `at` ends just past the header's terminating null byte.
inline std::map<std::string, HeaderAttribute> parse_exr_header(const std::string& s,
                                                               std::size_t& at) {
    std::map<std::string, HeaderAttribute> attributes;
    at = 8;
    while (s.at(at) != '\0') {
        const std::string name = read_cstring(s, at);
        HeaderAttribute a;
        a.type = read_cstring(s, at);
        const std::uint32_t size = le32(s, at);
        a.value = s.substr(at + 4, size);
        at += 4 + size;
        EXPECT_TRUE(attributes.emplace(name, a).second) << "duplicate attribute " << name;
    }
    ++at;
    return attributes;
}

/// Channel names of a chlist value, in file order.
inline std::vector<std::string> chlist_names(const std::string& chlist) {
    std::vector<std::string> names;
    std::size_t p = 0;
    while (chlist.at(p) != '\0') {
        names.push_back(read_cstring(chlist, p));
        p += 16;  // pixel type, pLinear + reserved, x and y sampling
    }
    return names;
}

/// Every channel's pixels (row-major, row 0 = top) of a FLOAT scanline file of `width` ×
/// `height`, read through the offset table.
inline std::map<std::string, std::vector<float>> read_exr_channels(const std::string& s, int width,
                                                                   int height) {
    std::size_t at = 0;
    const auto attributes = parse_exr_header(s, at);
    const std::vector<std::string> names = chlist_names(attributes.at("channels").value);
    std::map<std::string, std::vector<float>> channels;
    for (const std::string& n : names) channels[n].resize(static_cast<std::size_t>(width) * height);
    for (int y = 0; y < height; ++y) {
        const std::uint64_t offset = le64(s, at + 8 * static_cast<std::size_t>(y));
        if (le32(s, offset) != static_cast<std::uint32_t>(y))
            throw std::runtime_error("scanline order");
        for (std::size_t k = 0; k < names.size(); ++k)
            for (int x = 0; x < width; ++x)
                channels[names[k]][static_cast<std::size_t>(y) * width + x] =
                    le_float(s, offset + 8 + (k * width + x) * 4);
    }
    return channels;
}

}  // namespace spt::exr_test

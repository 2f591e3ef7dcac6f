// The checksums of PNG files: CRC-32 of each chunk and Adler-32 of the zlib stream (shared
// by the PNG writer and the PNG reader with its inflate).
#pragma once
#include <cstdint>
#include <string_view>

namespace spt {

/// CRC-32 (ISO 3309 / ITU-T V.42, as PNG chunks use it) of `data`.
std::uint32_t crc32(std::string_view data);

/// Adler-32 (RFC 1950 §8) of `data`.
std::uint32_t adler32(std::string_view data);

}  // namespace spt

// Checksums: CRC-32 and Adler-32 of PNG files (shared by the PNG writer and the PNG reader
// with its inflate), FNV-1a of checkpoints and of the files a render reads (their fingerprint).
#pragma once
#include <cstdint>
#include <string_view>

namespace spt {

/// CRC-32 (ISO 3309 / ITU-T V.42, as PNG chunks use it) of `data`.
std::uint32_t crc32(std::string_view data);

/// Adler-32 (RFC 1950 §8) of `data`.
std::uint32_t adler32(std::string_view data);

/// FNV-1a 64-bit hash of `data`.
std::uint64_t fnv1a64(std::string_view data);

}  // namespace spt

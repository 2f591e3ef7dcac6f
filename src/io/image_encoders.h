// Internal: one encoder per format (each in its own file) and shared little-endian helpers.
#pragma once
#include <bit>
#include <cstdint>
#include <string>

#include "io/image.h"
#include "io/image_writer.h"

namespace spt {

// Each assumes a valid image (width, height > 0 and 3 floats per pixel), see encode_image.
std::string encode_png(const Image& image, const ImageWriteOptions& options);
std::string encode_exr(const Image& image, const ImageWriteOptions& options);
std::string encode_pfm(const Image& image, const ImageWriteOptions& options);
std::string encode_ppm(const Image& image, const ImageWriteOptions& options);

/// Name of the emissive spectral channel of wavelength λ (Fichet et al. 2021): "S0.555,000000nm".
std::string spectral_channel_name(double lambda_nm);

inline void append_le32(std::string& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
inline void append_le64(std::string& out, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
inline void append_le_float(std::string& out, float v) {
    append_le32(out, std::bit_cast<std::uint32_t>(v));
}

}  // namespace spt

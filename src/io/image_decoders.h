// Image readers for textures and environment maps (our own code, no library): PNG, PPM (P3/P6,
// and the renderer's own HDR P3 with "#MAX="), PFM, OpenEXR (scan-line or tiled; NONE, RLE,
// ZIPS, ZIP and PIZ compression) and Radiance RGBE (.hdr, .pic). Each checks
// every size against the bytes it has before allocating, so truncated files, wrong sizes and
// absurd dimensions fail with an ImageDecodeError, never a crash or a huge allocation.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace spt {

/// A file that cannot be decoded; the message says what is wrong (the caller adds the name).
struct ImageDecodeError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// The most texels an image may have (2^27: 16384 × 8192, the largest common environment
/// maps): beyond it, an error. Decoded, such an image takes 12 bytes a texel as RGB floats
/// (1.5 GiB), 16 as RGBA.
inline constexpr long long kMaxTextureTexels = 1ll << 27;

/// Decoded samples: `channels` per texel (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA), row-major,
/// row 0 = the top of the image.
struct DecodedImage {
    int width = 0, height = 0, channels = 0;
    std::vector<float> values;
    /// True for integer formats (8/16-bit PNG, standard PPM): values are the stored codes
    /// divided by the largest code, still in the file's encoding (sRGB unless told
    /// otherwise). False for float formats (PFM, EXR, HDR PPM): linear values as stored.
    bool integer_codes = false;

    float at(int x, int y, int c) const {
        return values[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) *
                          static_cast<std::size_t>(channels) + static_cast<std::size_t>(c)];
    }
};

/// The format is told by the first bytes (PNG signature, "P3"/"P6", "PF"/"Pf", EXR magic,
/// "#?RADIANCE" or "#?RGBE").
DecodedImage decode_image(std::string_view bytes);

DecodedImage decode_png(std::string_view bytes);
DecodedImage decode_ppm(std::string_view bytes);
DecodedImage decode_pfm(std::string_view bytes);
DecodedImage decode_exr(std::string_view bytes);
DecodedImage decode_rgbe(std::string_view bytes);

/// Throws unless 1 ≤ width, height and width·height ≤ kMaxTextureTexels.
void check_image_size(long long width, long long height);

}  // namespace spt

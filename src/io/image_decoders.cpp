// Format detection and the size limit shared by the image readers.
#include "io/image_decoders.h"

#include <string>

namespace spt {

void check_image_size(long long width, long long height) {
    if (width < 1 || height < 1)
        throw ImageDecodeError("image size " + std::to_string(width) + "x" + std::to_string(height) +
                               " is empty; expected at least 1x1");
    if (width > kMaxTextureTexels || height > kMaxTextureTexels || width * height > kMaxTextureTexels)
        throw ImageDecodeError("image size " + std::to_string(width) + "x" + std::to_string(height) +
                               " is too large; expected at most " + std::to_string(kMaxTextureTexels) +
                               " texels (16384x8192)");
}

DecodedImage decode_image(std::string_view bytes) {
    if (bytes.starts_with("\x89PNG")) return decode_png(bytes);
    if (bytes.starts_with("P3") || bytes.starts_with("P6")) return decode_ppm(bytes);
    if (bytes.starts_with("PF") || bytes.starts_with("Pf")) return decode_pfm(bytes);
    if (bytes.starts_with(std::string_view("\x76\x2f\x31\x01", 4))) return decode_exr(bytes);
    if (bytes.starts_with("#?RADIANCE") || bytes.starts_with("#?RGBE")) return decode_rgbe(bytes);
    throw ImageDecodeError("not a PNG, PPM (P3/P6), PFM, OpenEXR or Radiance HDR file (unknown first bytes)");
}

}  // namespace spt

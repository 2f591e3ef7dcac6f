// PFM: "PF" header, little-endian float32 RGB (scale -1.0), rows stored bottom-to-top.
#include "io/image_encoders.h"

namespace spt {

std::string encode_pfm(const Image& image, const ImageWriteOptions& /*options*/) {
    std::string out = "PF\n" + std::to_string(image.width) + " " +
                      std::to_string(image.height) + "\n-1.0\n";  // negative scale = little-endian
    out.reserve(out.size() + image.rgb.size() * 4);
    for (int y = image.height - 1; y >= 0; --y) {
        const float* row = image.pixel(0, y);
        for (int i = 0; i < image.width * 3; ++i) append_le_float(out, row[i]);
    }
    return out;
}

}  // namespace spt

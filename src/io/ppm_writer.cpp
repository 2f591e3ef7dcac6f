// HDR-extended ASCII PPM (P3): a "#MAX=M" comment plus a large maxval R, so value = q * M / R.
// maxval deliberately exceeds netpbm's 65535 to keep more than float precision.
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "io/image_encoders.h"

namespace spt {

std::string encode_ppm(const Image& image, const ImageWriteOptions& options) {
    const std::uint64_t levels = options.color_resolution;
    if (levels == 0 || levels > (1ull << 53)) {  // 2^53: every level exact as a double
        throw std::invalid_argument("PPM color_resolution must be in [1, 2^53], got " +
                                    std::to_string(levels));
    }
    float max_value = 0.0f;  // over finite values; negatives and non-finite are written as 0
    for (float v : image.rgb) {
        if (std::isfinite(v) && v > max_value) max_value = v;
    }
    char max_text[32];
    std::snprintf(max_text, sizeof max_text, "%.9g", static_cast<double>(max_value));

    std::string out = "P3\n#MAX=" + std::string(max_text) + "\n" + std::to_string(image.width) +
                      " " + std::to_string(image.height) + "\n" + std::to_string(levels) + "\n";
    for (std::size_t i = 0; i < image.rgb.size(); ++i) {
        const float v = image.rgb[i];
        // A valid v is <= max, so q <= levels: the conversion cannot overflow.
        const bool valid = std::isfinite(v) && v > 0.0f;
        const double level = valid ? std::round(static_cast<double>(v) / max_value * levels) : 0.0;
        const auto q = static_cast<std::uint64_t>(level);
        out += std::to_string(q);
        out += i % 3 == 2 ? '\n' : ' ';  // one pixel per line keeps lines short
    }
    return out;
}

}  // namespace spt

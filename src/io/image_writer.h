// Writing an Image to PNG, OpenEXR, PFM or (HDR-extended) PPM, chosen by file extension.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "io/image.h"
#include "io/tone_map.h"

namespace spt {

struct Chromaticities {
    float red[2], green[2], blue[2], white[2];  ///< CIE xy, for the EXR header
};

struct ImageWriteOptions {
    double exposure_stops = 0.0;                  ///< PNG only: scale by 2^exposure first
    ToneMap tone_map = kDefaultToneMap;           ///< PNG only: then this curve
    std::uint64_t color_resolution = 1ull << 25;  ///< PPM: integer levels (above 2^24 = float)
    Chromaticities chromaticities = {
        {0.64f, 0.33f}, {0.30f, 0.60f}, {0.15f, 0.06f}, {0.3127f, 0.3290f}};  // sRGB / D65
};

enum class ImageFormat { Png, Exr, Pfm, Ppm };

/// The format named by the path's extension (case-insensitive), or nullopt.
std::optional<ImageFormat> image_format_from_path(const std::string& path);

/// The bytes of the image file. Throws std::invalid_argument on an empty or inconsistent image.
std::string encode_image(const Image& image, ImageFormat format, const ImageWriteOptions& options);

/// Encodes by extension and writes atomically. Throws std::runtime_error naming the file on an
/// unknown extension or any write error.
void write_image(const std::string& path, const Image& image, const ImageWriteOptions& options);

/// Writes one image to several files; none is replaced unless all of them can be written.
void write_images(const std::vector<std::string>& paths, const Image& image,
                  const ImageWriteOptions& options);

}  // namespace spt

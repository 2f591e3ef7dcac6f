// Writing an Image to PNG, OpenEXR, PFM or (HDR-extended) PPM, chosen by file extension.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "io/image.h"
#include "io/tone_map.h"
#include "spectral/spectral_bands.h"

namespace spt {

struct Chromaticities {
    float red[2], green[2], blue[2], white[2];  ///< CIE xy, for the EXR header
};

/// One OpenEXR header attribute: name, type name and the value's bytes (little-endian).
struct ExrAttribute {
    std::string name, type, value;
    static ExrAttribute text(std::string name, const std::string& value);     ///< "string"
    static ExrAttribute integer(std::string name, std::int32_t value);        ///< "int"
    static ExrAttribute real(std::string name, double value);                 ///< "double"
};

/// Band images for a spectral EXR: bands.count floats per pixel (row-major, row 0 = top),
/// each the band's mean spectral radiance.
struct SpectralImage {
    SpectralBands bands;
    std::vector<float> values;
};

struct ImageWriteOptions {
    double exposure_stops = 0.0;                  ///< PNG only: scale by 2^exposure first
    ToneMap tone_map = kDefaultToneMap;           ///< PNG only: then this curve
    std::uint64_t color_resolution = 1ull << 25;  ///< PPM: integer levels (above 2^24 = float)
    Chromaticities chromaticities = {
        {0.64f, 0.33f}, {0.30f, 0.60f}, {0.15f, 0.06f}, {0.3127f, 0.3290f}};  // sRGB / D65
    bool exr_chromaticities = true;  ///< false: RGB of no colour space (raw camera RGB)
    std::vector<ExrAttribute> exr_attributes;  ///< EXR: more header attributes (render metadata)
    /// EXR: also write these bands as emissive spectral channels (Fichet et al. 2021); must
    /// match the image size. Not owned.
    const SpectralImage* spectral = nullptr;
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

// Format selection by extension and the write_image entry point.
#include "io/image_writer.h"

#include <cctype>
#include <stdexcept>

#include "io/atomic_file.h"
#include "io/image_encoders.h"

namespace spt {
namespace {

/// ".ext" of the last path component, lower-cased, or "" when it has no dot.
std::string lower_extension(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    const std::size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string ext = path.substr(dot);
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

}  // namespace

std::optional<ImageFormat> image_format_from_path(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext == ".png") return ImageFormat::Png;
    if (ext == ".exr") return ImageFormat::Exr;
    if (ext == ".pfm") return ImageFormat::Pfm;
    if (ext == ".ppm") return ImageFormat::Ppm;
    return std::nullopt;
}

std::string encode_image(const Image& image, ImageFormat format,
                         const ImageWriteOptions& options) {
    if (image.width <= 0 || image.height <= 0 ||
        image.rgb.size() != static_cast<std::size_t>(image.width) * image.height * 3) {
        throw std::invalid_argument("invalid image: " + std::to_string(image.width) + "x" +
                                    std::to_string(image.height) + " with " +
                                    std::to_string(image.rgb.size()) + " floats");
    }
    switch (format) {
        case ImageFormat::Png: return encode_png(image, options);
        case ImageFormat::Exr: return encode_exr(image, options);
        case ImageFormat::Pfm: return encode_pfm(image, options);
        case ImageFormat::Ppm: return encode_ppm(image, options);
    }
    throw std::invalid_argument("unknown image format");
}

namespace {

std::string encode_for_path(const std::string& path, const Image& image,
                            const ImageWriteOptions& options) {
    const std::optional<ImageFormat> format = image_format_from_path(path);
    if (!format) {
        const std::string ext = lower_extension(path);
        throw std::runtime_error(
            (ext.empty() ? "missing image extension" : "unsupported image extension '" +
                                                           path.substr(path.size() - ext.size()) +
                                                           "'") +
            " for '" + path + "' (expected .png, .exr, .pfm, .ppm)");
    }
    try {
        return encode_image(image, *format, options);
    } catch (const std::invalid_argument& e) {
        throw std::runtime_error("cannot write '" + path + "': " + e.what());
    }
}

}  // namespace

void write_image(const std::string& path, const Image& image, const ImageWriteOptions& options) {
    write_images({path}, image, options);
}

void write_images(const std::vector<std::string>& paths, const Image& image,
                  const ImageWriteOptions& options) {
    std::vector<std::pair<std::string, std::string>> files;
    for (const std::string& path : paths) files.emplace_back(path, encode_for_path(path, image, options));
    write_files_atomically(files);
}

}  // namespace spt

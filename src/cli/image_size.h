// The render's image size from the scene's default and the --width, --height, --scale flags.
#pragma once
#include <optional>

namespace spt {

inline constexpr int kMaxImageSide = 65536;

struct ImageSize {
    int width = 0, height = 0;
};

/// Both of width and height given: that size. One of them: the other follows the scene's
/// aspect ratio, round(given · other_side / given_side) (halves away from zero), at least 1.
/// scale (never with width or height, see parse_options): each side of the scene's size times
/// scale, rounded, at least 1. Neither: the scene's size. Throws UsageError naming the flag
/// when a derived side exceeds kMaxImageSide.
ImageSize resolve_image_size(int scene_width, int scene_height, std::optional<int> width,
                             std::optional<int> height, std::optional<double> scale);

}  // namespace spt

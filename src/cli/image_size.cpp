// Aspect-preserving image sizes: one side given, or a scale of the scene's size.
#include "cli/image_size.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "cli/options.h"

namespace spt {

namespace {

int derived_side(double exact, const char* flag) {
    const double side = std::max(1.0, std::round(exact));
    if (side > kMaxImageSide)
        throw UsageError(std::string(flag) + ": the image would be " +
                         std::to_string(static_cast<long long>(side)) +
                         " pixels on a side (at most " + std::to_string(kMaxImageSide) + ")");
    return static_cast<int>(side);
}

}  // namespace

ImageSize resolve_image_size(int scene_width, int scene_height, std::optional<int> width,
                             std::optional<int> height, std::optional<double> scale) {
    if (scale)
        return {derived_side(scene_width * *scale, "--scale"),
                derived_side(scene_height * *scale, "--scale")};
    if (width && !height)
        return {*width, derived_side(double(*width) * scene_height / scene_width, "--width")};
    if (height && !width)
        return {derived_side(double(*height) * scene_width / scene_height, "--height"), *height};
    return {width.value_or(scene_width), height.value_or(scene_height)};
}

}  // namespace spt

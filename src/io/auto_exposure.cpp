// Median-luminance auto exposure.
#include "io/auto_exposure.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace spt {

double auto_exposure_stops(const Image& image, const ColorSpace& space) {
    const std::array<double, 3>& weight = space.to_xyz[1];
    std::vector<double> luminance;
    luminance.reserve(image.rgb.size() / 3);
    for (std::size_t i = 0; i + 2 < image.rgb.size(); i += 3) {
        const double y = weight[0] * image.rgb[i] + weight[1] * image.rgb[i + 1] +
                         weight[2] * image.rgb[i + 2];
        if (y > 0.0 && std::isfinite(y)) luminance.push_back(y);
    }
    if (luminance.empty()) return 0.0;
    const std::size_t n = luminance.size(), mid = n / 2;
    std::nth_element(luminance.begin(), luminance.begin() + mid, luminance.end());
    double median = luminance[mid];
    if (n % 2 == 0)  // the largest of the lower half is the other middle value
        median = 0.5 * (median + *std::max_element(luminance.begin(), luminance.begin() + mid));
    return std::clamp(std::log2(kAutoExposureKey / median), -20.0, 20.0);
}

}  // namespace spt

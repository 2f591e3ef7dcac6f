#include "spectral/rgb_sigmoid_table.h"

#include <algorithm>

#include "spectral/rgb_to_spectrum.h"

namespace spt {

SigmoidCoefficients rgb_sigmoid_coefficients(const std::array<float, 3>& rgb) {
    const SpectrumSource s = rgb_to_spectrum({rgb[0], rgb[1], rgb[2]});
    return {static_cast<float>(s.p[0]), static_cast<float>(s.p[1]), static_cast<float>(s.p[2])};
}

RgbIlluminant rgb_illuminant(const std::array<float, 3>& rgb) {
    const float scale = 2.f * std::max({rgb[0], rgb[1], rgb[2]});
    if (!(scale > 0.f)) return {};
    return {rgb_sigmoid_coefficients({rgb[0] / scale, rgb[1] / scale, rgb[2] / scale}), scale};
}

}  // namespace spt

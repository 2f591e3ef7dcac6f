// A linear-RGB float image: the renderer's output, handed to the image writers.
#pragma once
#include <cstddef>
#include <vector>

namespace spt {

struct Image {
    int width = 0, height = 0;
    std::vector<float> rgb;  ///< linear RGB, 3 floats per pixel, row-major, row 0 = top

    float* pixel(int x, int y) { return &rgb[(static_cast<std::size_t>(y) * width + x) * 3]; }
    const float* pixel(int x, int y) const {
        return &rgb[(static_cast<std::size_t>(y) * width + x) * 3];
    }
};

}  // namespace spt

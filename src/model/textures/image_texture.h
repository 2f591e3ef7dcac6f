// Image texture: texel (i, j) (column i, row j from the top) covers
// u ∈ [i/W, (i+1)/W], v ∈ [1 − (j+1)/H, 1 − j/H]: v = 0 is the bottom edge of the image, as
// in OpenGL and pbrt. Bilinear filtering weights the four texels whose centres surround
// (u, v); "nearest" takes the one containing it. Texel indices outside the image are
// wrapped: repeat (the default: the image tiles the plane), clamp (edge texels extend) or
// mirror (every other tile flipped).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "model/textures/texel_weights.h"

namespace spt {

enum class WrapMode : std::uint8_t { repeat, clamp, mirror };

/// Texel index i of an axis of n texels after wrapping.
inline int wrap_texel(long long i, int n, WrapMode mode) {
    switch (mode) {
        case WrapMode::clamp: return static_cast<int>(std::clamp<long long>(i, 0, n - 1));
        case WrapMode::mirror: {
            const long long period = 2ll * n, m = ((i % period) + period) % period;
            return static_cast<int>(m < n ? m : period - 1 - m);
        }
        case WrapMode::repeat: break;
    }
    return static_cast<int>(((i % n) + n) % n);
}

struct ImageTexture {
    int width = 0, height = 0;
    WrapMode wrap = WrapMode::repeat;
    bool bilinear = true;
    std::vector<std::uint32_t> texels;  ///< per texel (row-major, top row first): its value entry

    std::uint32_t texel(long long i, long long j) const {
        return texels[static_cast<std::size_t>(wrap_texel(j, height, wrap)) * static_cast<std::size_t>(width) +
                      static_cast<std::size_t>(wrap_texel(i, width, wrap))];
    }

    TexelWeights lookup(float u, float v) const {
        // Continuous texel coordinates: x along u from the left, y along −v from the top. In
        // double, so that large (u, v) (planes) keep their sub-texel position.
        const double x = double(u) * width, y = (1.0 - double(v)) * height;
        TexelWeights w;
        if (!(std::fabs(x) < 0x1p52 && std::fabs(y) < 0x1p52)) {  // not finite, or beyond texel precision
            w.add(texel(0, 0), 1.f);
            return w;
        }
        if (!bilinear) {
            w.add(texel(static_cast<long long>(std::floor(x)), static_cast<long long>(std::floor(y))), 1.f);
            return w;
        }
        const double xs = x - 0.5, ys = y - 0.5, x0 = std::floor(xs), y0 = std::floor(ys);
        const float fx = static_cast<float>(xs - x0), fy = static_cast<float>(ys - y0);
        const auto i = static_cast<long long>(x0), j = static_cast<long long>(y0);
        w.add(texel(i, j), (1.f - fx) * (1.f - fy));
        w.add(texel(i + 1, j), fx * (1.f - fy));
        w.add(texel(i, j + 1), (1.f - fx) * fy);
        w.add(texel(i + 1, j + 1), fx * fy);
        return w.finished();
    }
};

}  // namespace spt

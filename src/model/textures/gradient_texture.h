// Linear gradient along u (or v): value 0 ("start") at 0, value 1 ("end") at 1, held
// constant outside [0, 1].
#pragma once
#include <algorithm>

#include "model/textures/texel_weights.h"

namespace spt {

struct GradientTexture {
    bool along_v = false;

    TexelWeights lookup(float u, float v) const {
        const float t = std::clamp(along_v ? v : u, 0.f, 1.f);
        TexelWeights w;
        w.add(0u, 1.f - t);
        w.add(1u, t);
        return w;
    }
};

}  // namespace spt

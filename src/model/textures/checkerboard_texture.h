// Checkerboard: unit cells in the texture's (u, v); the cell (⌊u⌋, ⌊v⌋) takes value 0 when
// ⌊u⌋ + ⌊v⌋ is even ("even"), value 1 when odd ("odd"). uv_scale [8, 8] makes 8 × 8 cells
// over a surface's unit square.
#pragma once
#include "model/textures/texel_weights.h"

namespace spt {

struct CheckerboardTexture {
    TexelWeights lookup(float u, float v) const {
        const double cell = std::floor(double(u)) + std::floor(double(v));
        TexelWeights w;
        w.add(std::fmod(cell, 2.0) == 0.0 ? 0u : 1u, 1.f);
        return w;
    }
};

}  // namespace spt

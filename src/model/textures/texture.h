// The closed set of textures and what they give. A texture maps the surface's (u, v) (after
// its UvTransform) to a weighted sum of entries of its value table: spectra as bin values
// (a reflectance or an emission) or numbers (a float parameter). The table is made at load
// time, RGB texels fitted there once per distinct colour, so a look-up at render time is a
// few multiply-adds per bin and never a fit. Adding a texture type is one header in this
// folder and one entry in `TexturePattern`.
#pragma once
#include <algorithm>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "model/textures/checkerboard_texture.h"
#include "model/textures/gradient_texture.h"
#include "model/textures/image_texture.h"
#include "model/textures/texel_weights.h"

namespace spt {

using TexturePattern = std::variant<CheckerboardTexture, GradientTexture, ImageTexture>;

/// Bins per spectrum of texture values in exact mode (--spectral-bins exact): 1 nm over
/// 380–780 nm, where the spectra texels are fitted to are smooth to far below a bin.
inline constexpr int kExactTextureBins = 400;

struct Texture {
    std::string name;
    UvTransform transform;
    TexturePattern pattern;
    /// Spectral textures: `bins` values per entry, entry after entry. Float textures:
    /// bins = 1 and one number per entry.
    int bins = 1;
    std::vector<float> values;

    std::span<const float> entry(std::uint32_t e) const {
        return std::span<const float>(values).subspan(static_cast<std::size_t>(e) * static_cast<std::size_t>(bins),
                                                      static_cast<std::size_t>(bins));
    }
    std::size_t entry_count() const { return values.size() / static_cast<std::size_t>(bins); }

    TexelWeights lookup(float u, float v) const {
        transform.apply(u, v);
        return std::visit([&](const auto& p) { return p.lookup(u, v); }, pattern);
    }

    /// The value at (u, v) as `bins` numbers written to `out` (its size is bins).
    void eval(float u, float v, std::span<float> out) const {
        const TexelWeights w = lookup(u, v);
        std::fill(out.begin(), out.end(), 0.f);
        for (int k = 0; k < w.count; ++k) {
            const std::span<const float> e = entry(w.entry[static_cast<std::size_t>(k)]);
            const float wk = w.weight[static_cast<std::size_t>(k)];
            for (std::size_t b = 0; b < out.size(); ++b) out[b] += wk * e[b];
        }
    }
};

}  // namespace spt

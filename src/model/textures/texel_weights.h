// What a texture look-up returns: up to four entries of the texture's value table with
// their weights (summing to 1). Every value a texture gives is such a weighted sum, so a
// look-up is linear in the stored values: filtering spectra bin by bin is exact.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>

namespace spt {

struct TexelWeights {
    std::array<std::uint32_t, 4> entry{};
    std::array<float, 4> weight{};
    int count = 0;

    /// Adds weight w to entry e (merged with an earlier weight of the same entry).
    void add(std::uint32_t e, float w) {
        for (int k = 0; k < count; ++k)
            if (entry[static_cast<std::size_t>(k)] == e) {
                weight[static_cast<std::size_t>(k)] += w;
                return;
            }
        entry[static_cast<std::size_t>(count)] = e;
        weight[static_cast<std::size_t>(count)] = w;
        ++count;
    }

    /// Called once every weight is added: a single entry then has all of the weight, exactly
    /// 1, so a uniform region gives its value bit for bit (its float weights may sum to
    /// 1 ± rounding).
    TexelWeights& finished() {
        if (count == 1) weight[0] = 1.f;
        return *this;
    }
};

/// The (u, v) a texture sees: the surface's scaled, then offset ("uv_scale", "uv_offset").
struct UvTransform {
    float scale_u = 1.f, scale_v = 1.f, offset_u = 0.f, offset_v = 0.f;
    void apply(float& u, float& v) const { u = u * scale_u + offset_u, v = v * scale_v + offset_v; }
};

}  // namespace spt

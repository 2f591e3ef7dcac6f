// Trilinear lookup in the precomputed coefficient table (layout: rgb_sigmoid_table_data.h).
#include "spectral/rgb_sigmoid_table.h"

#include <algorithm>
#include <cstddef>
#include <utility>

#include "spectral/rgb_sigmoid_table_data.h"

namespace spt {

namespace {

using namespace rgb_sigmoid_table;

/// |x| at or above this makes s(x) exactly 0 or 1 in float and double (x² then swamps the 1);
/// it is a power of two, so ±kSaturated gives exactly 0 and 1 and x² does not overflow a float.
constexpr float kSaturated = 0x1p60f;

/// A constant spectrum g: s(c2) = g for c2 = (g − ½)/√(g(1 − g)).
SigmoidCoefficients grey(float g) {
    if (g <= 0.f) return {0, 0, -kSaturated};
    if (g >= 1.f) return {0, 0, kSaturated};
    const double gd = g;
    const double c2 = (gd - 0.5) / std::sqrt(gd * (1.0 - gd));
    return {0, 0, static_cast<float>(std::clamp(c2, -double(kSaturated), double(kSaturated)))};
}

/// The cell [nodes[i], nodes[i + 1]] holding v and v's place in it, clamped to [0, 1] (0 below
/// nodes[0], 1 above the last node). A binary search without branches: texel colours are in
/// no order, so a branch per step would be mispredicted half the time.
template <std::size_t N>
std::pair<int, float> cell(const float (&nodes)[N], float v) {
    static_assert(N >= 2 && (N & (N - 1)) == 0, "the search halves a power of two");
    int i = 0;
    for (std::size_t step = N / 2; step > 0; step /= 2) i += nodes[i + step] <= v ? static_cast<int>(step) : 0;
    i = std::min(i, static_cast<int>(N) - 2);
    return {i, std::clamp((v - nodes[i]) / (nodes[i + 1] - nodes[i]), 0.f, 1.f)};
}

float clamp01(float v) { return v > 0.f ? (v < 1.f ? v : 1.f) : 0.f; }  // NaN → 0

}  // namespace

SigmoidCoefficients rgb_sigmoid_coefficients(const std::array<float, 3>& in) {
    const float rgb[3] = {clamp01(in[0]), clamp01(in[1]), clamp01(in[2])};
    if (rgb[0] == rgb[1] && rgb[1] == rgb[2]) return grey(rgb[0]);
    const int m = rgb[0] > rgb[1] ? (rgb[0] > rgb[2] ? 0 : 2) : (rgb[1] > rgb[2] ? 1 : 2);
    const float z = rgb[m];  // > 0: not all components are equal
    const auto [xi, fx] = cell(kXYNodes, rgb[(m + 1) % 3] / z);
    const auto [yi, fy] = cell(kXYNodes, rgb[(m + 2) % 3] / z);

    // The table holds coefficients·√z (rgb_sigmoid_table_data.h). Below the first node z₀
    // (2.5e-5: L* < 0.03) the coefficients of z₀ are extrapolated as 1/√z; 1e-30 keeps x²
    // finite in float.
    const auto [zi, fz] = cell(kZNodes, z);
    const float inv_sqrt_z = 1.f / std::sqrt(std::max(z, 1e-30f));

    float c[3] = {0, 0, 0};
    const float wz[2] = {1.f - fz, fz}, wy[2] = {1.f - fy, fy}, wx[2] = {1.f - fx, fx};
    for (int dz = 0; dz < 2; ++dz) {
        if (wz[dz] == 0.f) continue;  // z on a node: the illuminant case, and the top plane
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) {
                const float w = wz[dz] * wy[dy] * wx[dx];
                const float* node = kCoefficients + coefficient_index(m, zi + dz, yi + dy, xi + dx);
                c[0] += w * node[0], c[1] += w * node[1], c[2] += w * node[2];
            }
    }
    return {c[0] * inv_sqrt_z, c[1] * inv_sqrt_z, c[2] * inv_sqrt_z};
}

RgbIlluminant rgb_illuminant(const std::array<float, 3>& rgb) {
    const float scale = 2.f * std::max({rgb[0], rgb[1], rgb[2]});
    if (!(scale > 0.f)) return {};
    return {rgb_sigmoid_coefficients({rgb[0] / scale, rgb[1] / scale, rgb[2] / scale}), scale};
}

}  // namespace spt

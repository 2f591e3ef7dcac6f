// Layout of the coefficient table behind rgb_sigmoid_coefficients (rgb_sigmoid_table.h), shared
// by the lookup and by the generator that fits it at build time (make_rgb_sigmoid_table.cpp).
#pragma once
#include <cstddef>

namespace spt::rgb_sigmoid_table {

/// Nodes along z, the largest RGB component: z_j = smoothstep(smoothstep((j + 1)/kZResolution)),
/// j = 0 … kZResolution − 1 (dense near 0 and 1). kZResolution is even so that z = ½, the
/// only z an RgbIlluminant looks up, is node kZResolution/2 − 1 and needs no interpolation in z.
inline constexpr int kZResolution = 32;
/// Nodes along x and y, the two other components divided by z: smoothstep(i/(kXYResolution − 1)),
/// denser near 0, where a saturated colour's CIELAB changes fastest with the small components,
/// and near 1, where a bright near-grey's coefficients do.
inline constexpr int kXYResolution = 32;

inline constexpr std::size_t kPlaneSize = std::size_t(kXYResolution) * kXYResolution * 3;
/// Coefficients (c0, c1, c2)·√z of node (m, j, y, x), m = index of the largest component, the
/// other two being x·z (component m + 1 mod 3) and y·z (m + 2 mod 3). Scaled by √z because
/// the coefficients of dark colours grow roughly as 1/√z (a sigmoid far below ½ falls as
/// 1/(4x²)), which linear interpolation between dark nodes far apart in ratio follows badly.
inline constexpr std::size_t coefficient_index(int m, int j, int y, int x) {
    return ((std::size_t(m) * kZResolution + j) * kXYResolution + y) * kXYResolution * 3 + std::size_t(x) * 3;
}
inline constexpr std::size_t kCoefficientCount = 3 * kZResolution * kPlaneSize;

inline constexpr double smoothstep(double x) { return x * x * (3.0 - 2.0 * x); }
inline constexpr double z_node(int j) { return smoothstep(smoothstep(double(j + 1) / kZResolution)); }
inline constexpr double xy_node(int i) { return smoothstep(double(i) / (kXYResolution - 1)); }

extern const float kZNodes[kZResolution];    ///< float(z_node(j))
extern const float kXYNodes[kXYResolution];  ///< float(xy_node(i))
extern const float kCoefficients[kCoefficientCount];

}  // namespace spt::rgb_sigmoid_table

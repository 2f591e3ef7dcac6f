// Scalar constants and guarded maths used everywhere (no NaN from tiny domain errors).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace spt {

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.31830988618379067154f;
inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

/// sqrt that treats tiny negative rounding errors as zero instead of returning NaN.
inline float safe_sqrt(float x) { return std::sqrt(std::max(0.f, x)); }
inline double safe_sqrt(double x) { return std::sqrt(std::max(0.0, x)); }

template <typename T>
inline T sqr(T x) { return x * x; }

inline float lerp(float t, float a, float b) { return (1.f - t) * a + t * b; }

/// Relative rounding error bound of n float operations (Higham's gamma_n, as in pbrt).
inline constexpr float gamma_bound(int n) {
    constexpr float eps = std::numeric_limits<float>::epsilon() * 0.5f;
    return (n * eps) / (1 - n * eps);
}

/// The next representable float above / below v (used to push ray origins off surfaces).
inline float next_float_up(float v) {
    if (std::isinf(v) && v > 0.f) return v;
    if (v == -0.f) v = 0.f;
    std::uint32_t ui;
    std::memcpy(&ui, &v, sizeof ui);
    ui = (v >= 0) ? ui + 1 : ui - 1;
    std::memcpy(&v, &ui, sizeof ui);
    return v;
}
inline float next_float_down(float v) {
    if (std::isinf(v) && v < 0.f) return v;
    if (v == 0.f) v = -0.f;
    std::uint32_t ui;
    std::memcpy(&ui, &v, sizeof ui);
    ui = (v > 0) ? ui - 1 : ui + 1;
    std::memcpy(&v, &ui, sizeof ui);
    return v;
}

}  // namespace spt

// Logarithm, sine/cosine and atan2 for the hot sampling code, written without branches or library
// calls so that they inline; the logarithm works on the four wavelengths of a path at once.
// Both are plain series with their exact coefficients, kept to float accuracy by range
// reduction (tests/test_fast_math.cpp bounds the error against <cmath>).
#pragma once
#include <bit>
#include <cmath>
#include <cstdint>

#include "core/simd.h"

namespace spt {

/// Natural logarithm of positive, finite, normal floats, four at a time (no checks: the
/// callers' arguments are in a known range). x = 2^e·m with m in [√½, √2), and
/// log m = 2·atanh(z) with z = (m − 1)/(m + 1), |z| ≤ 0.172: five terms of the atanh series
/// leave < 1e-9.
inline Float4 log_positive(Float4 x) {
    const Int4 bits = std::bit_cast<Int4>(x);
    const Int4 mantissa = bits & 0x007fffff;
    // Mantissas above √2 move down an octave: above is −1 in those lanes, 0 elsewhere.
    const Int4 above = mantissa > 0x3504f3;
    const Int4 e = ((bits >> 23) & 0xff) - 127 - above;
    const Int4 m_bits = mantissa | ((127 + above) << 23);
    const Float4 m = std::bit_cast<Float4>(m_bits);
    const Float4 z = (m - 1.f) / (m + 1.f), z2 = z * z;
    const Float4 series = 1.f + z2 * (1.f / 3 + z2 * (1.f / 5 + z2 * (1.f / 7 + z2 * (1.f / 9))));
    return to_float4(e) * 0.693147180559945f + 2.f * z * series;
}
inline float log_positive(float x) { return log_positive(splat4(x))[0]; }

/// sin and cos of θ = (π/4)·s for s in [−1, 1] (|θ| ≤ π/4): Taylor series to θ⁹ and θ¹⁰,
/// whose first omitted terms are below 2e-9 there.
inline void sincos_quarter_pi(float s, float& sin_out, float& cos_out) {
    const float t = 0.785398163397448f * s, t2 = t * t;
    sin_out = t * (1.f - t2 * (1.f / 6 - t2 * (1.f / 120 - t2 * (1.f / 5040 - t2 * (1.f / 362880)))));
    cos_out = 1.f - t2 * (0.5f - t2 * (1.f / 24 - t2 * (1.f / 720 - t2 * (1.f / 40320 - t2 * (1.f / 3628800)))));
}

/// sincos_quarter_pi in four lanes (the same operations: the same bits in every lane).
inline void sincos_quarter_pi(Float4 s, Float4& sin_out, Float4& cos_out) {
    const Float4 t = 0.785398163397448f * s, t2 = t * t;
    sin_out = t * (1.f - t2 * (1.f / 6 - t2 * (1.f / 120 - t2 * (1.f / 5040 - t2 * (1.f / 362880)))));
    cos_out = 1.f - t2 * (0.5f - t2 * (1.f / 24 - t2 * (1.f / 720 - t2 * (1.f / 40320 - t2 * (1.f / 3628800)))));
}

/// atan2(y, x) for y ≥ 0 (an angle in [0, π]; (0, 0) gives 0), in double: with t the ratio
/// of the smaller of y, |x| to the larger (t ∈ [0, 1]), atan t = π/4 + atan((t − 1)/(t + 1))
/// above tan(π/8) leaves |u| ≤ tan(π/8) = 0.4142, where eleven terms of u − u³/3 + u⁵/5 − …
/// leave less than u²³/23 < 7e-11; then π/2 − · where y > |x|, and π − · where x < 0. One
/// division, no library call (std::atan2f cost ~130 instructions with its wrapper).
inline double atan2_nonnegative(double y, double x) {
    const double ax = std::fabs(x);
    const bool swap = y > ax;
    const double num = swap ? ax : y, den = swap ? y : ax;
    const bool shift = num > 0.41421356237309503 * den;
    const double u = den > 0.0 ? (shift ? (num - den) / (num + den) : num / den) : 0.0, u2 = u * u;
    const double series =
        1.0 - u2 * (1.0 / 3 - u2 * (1.0 / 5 - u2 * (1.0 / 7 - u2 * (1.0 / 9 - u2 * (1.0 / 11 - u2 * (1.0 / 13 -
        u2 * (1.0 / 15 - u2 * (1.0 / 17 - u2 * (1.0 / 19 - u2 * (1.0 / 21))))))))));
    double a = (shift ? 0.78539816339744831 : 0.0) + u * series;
    if (swap) a = 1.5707963267948966 - a;
    if (x < 0.0) a = 3.1415926535897932 - a;
    return a;
}

/// atan2(y, x) for any y (an angle in [−π, π]): atan2_nonnegative of |y|, with y's sign (so
/// y = −0 gives −0 or −π, as std::atan2 does). For the environment maps' direction → image
/// look-ups, where std::atan2f was a tenth of a path's time.
inline double atan2_signed(double y, double x) {
    const double a = atan2_nonnegative(std::fabs(y), x);
    return std::signbit(y) ? -a : a;
}

/// atan2_nonnegative in four lanes (into `out`), operation for operation the scalar one (the
/// same bits in every lane: the branches become selects, the two quotients one division of
/// selected operands, |x| the sign bit cleared).
inline void atan2_nonnegative(const Double4& y, const Double4& x, Double4& out) {
    const Double4 zero{};
    const Double4 ax = reinterpret_cast<Double4>(reinterpret_cast<Long4>(x) & std::int64_t(0x7fffffffffffffff));
    const Long4 swap = y > ax;
    const Double4 num = swap ? ax : y, den = swap ? y : ax;
    const Long4 shift = num > 0.41421356237309503 * den;
    const Double4 q = (shift ? num - den : num) / (shift ? num + den : den);
    const Double4 u = den > zero ? q : zero, u2 = u * u;
    const Double4 series =
        1.0 - u2 * (1.0 / 3 - u2 * (1.0 / 5 - u2 * (1.0 / 7 - u2 * (1.0 / 9 - u2 * (1.0 / 11 - u2 * (1.0 / 13 -
        u2 * (1.0 / 15 - u2 * (1.0 / 17 - u2 * (1.0 / 19 - u2 * (1.0 / 21))))))))));
    Double4 a = (shift ? Double4{} + 0.78539816339744831 : zero) + u * series;
    a = swap ? 1.5707963267948966 - a : a;
    out = x < zero ? 3.1415926535897932 - a : a;
}

}  // namespace spt

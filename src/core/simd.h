// Four-lane float vectors, one lane per wavelength of a path. GCC/Clang vector extensions
// (no library): SSE on x86-64, NEON on ARM, plain scalar code elsewhere. Each lane rounds
// exactly as the scalar operation would, so vector and scalar code give the same bits.
#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>

namespace spt {

using Float4 = float __attribute__((vector_size(16)));
using Int4 = std::int32_t __attribute__((vector_size(16)));
using UInt4 = std::uint32_t __attribute__((vector_size(16)));
/// Two doubles: the film's sums (double) are built two components at a time.
using Double2 = double __attribute__((vector_size(16)));
/// Four doubles (two SSE registers, or one AVX register where the build targets it) and the
/// masks their comparisons give. Functions take and give them by reference: by value, their
/// ABI differs between builds with and without AVX (GCC's -Wpsabi).
using Double4 = double __attribute__((vector_size(32)));
using Long4 = std::int64_t __attribute__((vector_size(32)));

inline Float4 splat4(float v) { return Float4{v, v, v, v}; }
inline Int4 splat4(std::int32_t v) { return Int4{v, v, v, v}; }
/// Lane-wise minimum and maximum (b where a is NaN, like a < b ? a : b).
inline Float4 min4(Float4 a, Float4 b) { return a < b ? a : b; }
inline Float4 max4(Float4 a, Float4 b) { return a > b ? a : b; }
inline Int4 to_int4(Float4 v) { return __builtin_convertvector(v, Int4); }  ///< truncates
inline Float4 to_float4(Int4 v) { return __builtin_convertvector(v, Float4); }
/// One bit per lane of a comparison mask (lane k → bit k): one instruction on SSE, where
/// testing the lanes one by one costs a dozen.
inline unsigned lane_bits(Int4 mask) {
#if defined(__SSE__)
    return static_cast<unsigned>(__builtin_ia32_movmskps(reinterpret_cast<Float4>(mask)));
#else
    return (mask[0] & 1u) | (mask[1] & 2u) | (mask[2] & 4u) | (mask[3] & 8u);
#endif
}
/// lane_bits of a Double4 comparison's mask.
inline unsigned lane_bits(const Long4& mask) {
    return unsigned(mask[0] & 1) | unsigned(mask[1] & 2) | unsigned(mask[2] & 4) | unsigned(mask[3] & 8);
}
/// Eight floats and the masks their comparisons give (one AVX register, or two SSE registers
/// where the build does not target AVX): the BVH's wide nodes test eight boxes at once. Passed
/// by reference, as Double4 is.
using Float8 = float __attribute__((vector_size(32)));
using Mask8 = std::int32_t __attribute__((vector_size(32)));
/// lane_bits of a Float8 comparison's mask (lane k → bit k).
inline unsigned lane_bits(const Mask8& mask) {
#if defined(__AVX__)
    return static_cast<unsigned>(__builtin_ia32_movmskps256(reinterpret_cast<Float8>(mask)));
#else
    return lane_bits(Int4(__builtin_shufflevector(mask, mask, 0, 1, 2, 3))) |
           lane_bits(Int4(__builtin_shufflevector(mask, mask, 4, 5, 6, 7))) << 4;
#endif
}
/// Four floats from p (any alignment).
inline Float4 load4(const float* p) {
    Float4 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
/// Lane-wise square root, correctly rounded as std::sqrt (the same bits).
inline Float4 sqrt4(Float4 v) {
#if defined(__SSE__)
    return __builtin_ia32_sqrtps(v);
#else
    return Float4{std::sqrt(v[0]), std::sqrt(v[1]), std::sqrt(v[2]), std::sqrt(v[3])};
#endif
}

/// Lanes 0–1 and lanes 2–3 of a Float4 as doubles (exact).
inline Double2 low_to_double2(Float4 v) {
    return __builtin_convertvector(__builtin_shufflevector(v, v, 0, 1), Double2);
}
inline Double2 high_to_double2(Float4 v) {
    return __builtin_convertvector(__builtin_shufflevector(v, v, 2, 3), Double2);
}

}  // namespace spt

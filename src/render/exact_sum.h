// A fixed-point accumulator whose additions are exact, hence associative: the film folds its
// floating-point sums into these at fixed sample counts, so a render split into parts (each
// folding its own chunks) merges into the very bits of one uninterrupted render.
#pragma once
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace spt {

/// A non-negative number as 128 integer and 64 fraction bits: resolution 2^-64 ≈ 5.4e-20,
/// largest 2^128 ≈ 3.4e38 (a float's range, so even squared fireflies fit). Adding is integer
/// addition, so the result does not depend on the order of the terms; a sum beyond the largest
/// value saturates there.
struct ExactSum {
    std::uint64_t high = 0, whole = 0, fraction = 0;  ///< bits 127-64, 63-0, and 2^-1 to 2^-64

    /// Adds a finite v ≥ 0, truncated to a multiple of 2^-64 (truncation, not rounding, so the
    /// conversion never carries). v = m·2^e with an integer mantissa m < 2^53: in units of
    /// 2^-64 that is m shifted left by e + 64 (right, dropping the bits below 2^-64, when
    /// negative), placed into the three words with integer shifts only. The film folds every
    /// pixel at each chunk's end, so this avoids floor and ldexp (library calls, a visible
    /// share of the time per path). Equal, bit for bit, to reference_add (a test compares them).
    void add(double v) {
        if (!(v < 0x1p128)) return saturate();
        if (!(v > 0.0)) return;  // +0 and −0 add nothing
        const auto bits = std::bit_cast<std::uint64_t>(v);
        const int biased = static_cast<int>(bits >> 52);  // the sign bit is 0 here
        const std::uint64_t m = (bits & ((std::uint64_t{1} << 52) - 1)) | (biased ? std::uint64_t{1} << 52 : 0);
        // v = m·2^(biased − 1075) for normal numbers, m·2^−1074 for subnormal ones.
        const int shift = (biased ? biased - 1075 : -1074) + 64;
        std::uint64_t word[3] = {0, 0, 0};  // fraction, whole, high
        if (shift < 0) {
            word[0] = shift > -64 ? m >> -shift : 0;
        } else {
            // v < 2^128 keeps shift ≤ 139: the top word holds m << (shift − 128) without overflow.
            const int w = shift >> 6, b = shift & 63;
            word[w] = m << b;
            if (w < 2 && b != 0) word[w + 1] = m >> (64 - b);
        }
        add(ExactSum{word[2], word[1], word[0]});
    }
    /// The definition add(double) computes faster: each step exact (scaling by powers of two,
    /// floor, and differences whose results are representable). Kept for the test.
    void reference_add(double v) {
        if (!(v < 0x1p128)) return saturate();
        const double h = std::floor(std::ldexp(v, -64));
        const double rest = v - std::ldexp(h, 64);
        const double w = std::floor(rest);
        add(ExactSum{static_cast<std::uint64_t>(h), static_cast<std::uint64_t>(w),
                     static_cast<std::uint64_t>(std::ldexp(rest - w, 64))});
    }
    void add(const ExactSum& o) {
        const std::uint64_t f = fraction + o.fraction;
        const std::uint64_t w = whole + o.whole + (f < fraction ? 1 : 0);
        const bool carry = w < whole || (w == whole && f < fraction);
        const std::uint64_t h = high + o.high + (carry ? 1 : 0);
        if (h < high || (h == high && carry)) return saturate();
        high = h, whole = w, fraction = f;
    }
    double value() const {
        return std::ldexp(static_cast<double>(high), 64) + static_cast<double>(whole) +
               std::ldexp(static_cast<double>(fraction), -64);
    }
    bool operator==(const ExactSum&) const = default;

private:
    void saturate() { high = whole = fraction = std::numeric_limits<std::uint64_t>::max(); }
};

}  // namespace spt

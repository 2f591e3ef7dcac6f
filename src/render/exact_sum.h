// A fixed-point accumulator whose additions are exact, hence associative: the film folds its
// floating-point sums into these at fixed sample counts, so a render split into parts (each
// folding its own chunks) merges into the very bits of one uninterrupted render.
#pragma once
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
    /// conversion never carries).
    void add(double v) {
        if (!(v < 0x1p128)) return saturate();
        // Each step is exact: scaling by powers of two, floor, and the differences (the
        // remainders are representable, so IEEE subtraction gives them without rounding).
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

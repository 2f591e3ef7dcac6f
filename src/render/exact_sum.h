// A fixed-point accumulator whose additions are exact, hence associative: the film folds its
// floating-point sums into these at fixed sample counts, so a render split into parts (each
// folding its own chunks) merges into the very bits of one uninterrupted render.
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>

namespace spt {

/// A non-negative number as 64 integer and 64 fraction bits (resolution 2^-64 ≈ 5.4e-20,
/// largest 2^64 ≈ 1.8e19). Adding is integer addition, so the result does not depend on the
/// order of the terms; a sum beyond the largest value saturates there.
struct ExactSum {
    std::uint64_t whole = 0, fraction = 0;

    /// Adds a finite v ≥ 0, truncated to a multiple of 2^-64 (truncation, not rounding, so the
    /// fraction never carries out of its 64 bits by conversion).
    void add(double v) {
        constexpr double kWholeLimit = 18446744073709551616.0;  // 2^64
        if (!(v < kWholeLimit)) return saturate();
        const double w = std::floor(v);
        // v − floor(v) is exact, and so is the scaling by 2^64; the cast drops bits below 2^-64.
        add(ExactSum{static_cast<std::uint64_t>(w), static_cast<std::uint64_t>(std::ldexp(v - w, 64))});
    }
    void add(const ExactSum& o) {
        const std::uint64_t f = fraction + o.fraction;
        const std::uint64_t carry = f < fraction ? 1 : 0;
        const std::uint64_t w = whole + o.whole;
        if (w < whole || w + carry < w) return saturate();
        whole = w + carry, fraction = f;
    }
    double value() const { return static_cast<double>(whole) + std::ldexp(static_cast<double>(fraction), -64); }
    bool operator==(const ExactSum&) const = default;

private:
    void saturate() { whole = fraction = std::numeric_limits<std::uint64_t>::max(); }
};

}  // namespace spt

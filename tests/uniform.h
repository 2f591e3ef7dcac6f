// The tests' uniform random numbers: a fixed-seed 64-bit Mersenne Twister giving floats with 24
// random bits and doubles with 53, and for the geometry robustness tests magnitudes
// 10^U(lo, hi) with random signs.
#pragma once
#include <cmath>
#include <cstdint>
#include <random>

#include "core/vec3.h"

namespace spt_test {

class Uniform {
public:
    explicit Uniform(std::uint64_t seed) : m_gen(seed) {}
    /// Float in [0, 1) with 24 random bits (every value exactly representable).
    float next_float() { return static_cast<float>(m_gen() >> 40) * 0x1p-24f; }
    /// Double in [0, 1) with 53 random bits.
    double next_double() { return static_cast<double>(m_gen() >> 11) * 0x1p-53; }
    double next() { return next_double(); }
    /// 10^U(lo, hi)
    double log_uniform(double lo, double hi) { return std::pow(10.0, lo + (hi - lo) * next()); }
    double sign() { return next() < 0.5 ? -1.0 : 1.0; }
    /// A point whose components are each ±10^U(lo, hi), drawn x, y, z in that order.
    spt::Vec3 signed_log_point(double lo, double hi) {
        float v[3];
        for (float& c : v) c = float(sign() * log_uniform(lo, hi));
        return {v[0], v[1], v[2]};
    }

private:
    std::mt19937_64 m_gen;
};

}  // namespace spt_test

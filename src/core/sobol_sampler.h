// Owen-scrambled Sobol points, one randomisation per pixel: the low-discrepancy sampler of
// --sampler sobol. Dimension d of sample i is point i of the Sobol sequence's dimension d
// (Joe-Kuo direction numbers, core/sobol_matrices.h), nested-uniform scrambled (Owen 1995) by
// a hash seeded per (seed, pixel, d) (Laine and Karras 2011, with Vegdahl's constants as
// in Burley 2020). Scrambling keeps every net property of the sequence: the first 2^m
// samples of a pixel are a (t,m,s)-net, dimensions 0 and 1 a (0,m,2)-net. Determinism as
// with Rng: a function of (seed, pixel, sample, dimension) only.
#pragma once
#include <cstdint>

#include "core/rng.h"
#include "core/sobol_matrices.h"

namespace spt {

/// x with its 32 bits in reverse order.
inline constexpr std::uint32_t reverse_bits(std::uint32_t x) {
    x = __builtin_bswap32(x);
    x = ((x & 0x0f0f0f0fu) << 4) | ((x >> 4) & 0x0f0f0f0fu);
    x = ((x & 0x33333333u) << 2) | ((x >> 2) & 0x33333333u);
    return ((x & 0x55555555u) << 1) | ((x >> 1) & 0x55555555u);
}

/// A random nested permutation of bit-reversed values: each step changes a bit only as a
/// function of the bits below it (additions and multiplications carry upwards only), so in
/// the unreversed value each digit is permuted as a function of the digits above it: Owen's
/// nested uniform scrambling, with the hash standing in for the tree of random bits.
inline constexpr std::uint32_t owen_permute_reversed(std::uint32_t x, std::uint32_t seed) {
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

/// Point `index` of Sobol dimension `dim` (< kSobolDimensions), bit-reversed, unscrambled.
inline std::uint32_t sobol_reversed(std::uint32_t index, int dim) {
    const std::uint32_t* columns = kSobolMatricesReversed[dim];
    std::uint32_t x = 0;
    for (; index != 0; index >>= 1, ++columns)
        if (index & 1u) x ^= *columns;
    return x;
}

/// Point `index` of dimension `dim`, Owen-scrambled with `seed`, as 32 bits.
inline std::uint32_t scrambled_sobol(std::uint32_t index, int dim, std::uint32_t seed) {
    return reverse_bits(owen_permute_reversed(sobol_reversed(index, dim), seed));
}

/// The random numbers of one path sample: sequential like Rng::uniform(), from the current
/// dimension, which seek() moves to the place core/sample_dimensions.h gives each quantity.
/// Past kSobolDimensions, numbers come from the sample's PCG stream (Rng of the same seed,
/// pixel and sample), so paths of any depth stay correct.
class SobolSampler {
public:
    SobolSampler(const RngStream& stream, std::uint64_t sample_index)
        : m_key(stream.inc ^ stream.sample_key), m_index(static_cast<std::uint32_t>(sample_index)),
          m_fallback(stream, sample_index) {}

    float uniform() {
        if (m_dim >= kSobolDimensions) return m_fallback.uniform();
        const int dim = m_dim++;
        return static_cast<float>(scrambled_sobol(m_index, dim, dimension_seed(dim)) >> 8) * 0x1p-24f;
    }
    /// Makes `dim` the next dimension uniform() draws.
    void seek(int dim) { m_dim = dim; }
    /// The PCG stream behind the sampler (integrators that take their path's numbers from it).
    Rng& fallback() { return m_fallback; }

private:
    std::uint32_t dimension_seed(int dim) const {
        return static_cast<std::uint32_t>(mix64(m_key + std::uint64_t(dim) * 0x9e3779b97f4a7c15ull));
    }
    std::uint64_t m_key;    ///< the pixel's randomisation (from the seed and the pixel index)
    std::uint32_t m_index;  ///< the sample's index in the pixel's sequence
    int m_dim = 0;
    Rng m_fallback;
};

/// Moving to a dimension: the independent sampler has no dimensions (a no-op, so templated
/// integrators compile to the code of before for it).
inline void seek_dimension(Rng&, int) {}
inline void seek_dimension(SobolSampler& sampler, int dim) { sampler.seek(dim); }

/// The PCG stream of a sample, for integrators that draw everything from one.
inline Rng& pcg_stream(Rng& rng) { return rng; }
inline Rng& pcg_stream(SobolSampler& sampler) { return sampler.fallback(); }

}  // namespace spt

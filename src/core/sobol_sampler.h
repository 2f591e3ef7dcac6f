// Owen-scrambled Sobol points, one randomisation per pixel: the low-discrepancy sampler of
// --sampler sobol. Dimension d of sample i is point i of the Sobol sequence's dimension d
// (Joe-Kuo direction numbers, core/sobol_matrices.h), nested-uniform scrambled (Owen 1995) by
// a hash seeded per (seed, pixel, d) (Laine and Karras 2011, with Vegdahl's constants as
// in Burley 2020). Cost per number (the sampler's whole overhead over PCG): one 32-bit hash
// for the dimension's seed, one table load per nibble of the sample index, the scramble's
// three multiplications and a bit reversal; no branch that depends on the numbers. Scrambling keeps every net property of the sequence: the first 2^m
// samples of a pixel are a (t,m,s)-net, dimensions 0 and 1 a (0,m,2)-net. Determinism as
// with Rng: a function of (seed, pixel, sample, dimension) only.
#pragma once
#include <cstdint>
#include <optional>

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

/// The Sobol matrices by nibbles: entry [d][k][n] is dimension d's matrix times the index
/// whose nibble k is n and whose other nibbles are 0 (bit-reversed), so a point is the XOR of
/// one entry per nibble of its index: no branch on the index's bits (which the branch
/// predictor cannot learn: they made most of the sampler's mispredictions), and one load per
/// 16 samples of the index's range rather than one test per bit. 16 KiB; a render touches the
/// entries of the nibbles its sample indices have (2 for 256 spp: 128 bytes per dimension).
struct SobolNibbleTables {
    std::uint32_t entry[kSobolDimensions][8][16];
};
inline constexpr SobolNibbleTables kSobolNibbles = [] {
    SobolNibbleTables t{};
    for (int d = 0; d < kSobolDimensions; ++d)
        for (int k = 0; k < 8; ++k)
            for (std::uint32_t n = 0; n < 16; ++n)
                for (int b = 0; b < 4; ++b)
                    if ((n >> b) & 1u) t.entry[d][k][n] ^= kSobolMatricesReversed[d][4 * k + b];
    return t;
}();

/// Point `index` of Sobol dimension `dim` (< kSobolDimensions), bit-reversed, unscrambled.
inline std::uint32_t sobol_reversed(std::uint32_t index, int dim) {
    const std::uint32_t* nibble = kSobolNibbles.entry[dim][0];
    std::uint32_t x = 0;
    for (; index != 0; index >>= 4, nibble += 16) x ^= nibble[index & 15u];
    return x;
}

/// Point `index` of dimension `dim`, Owen-scrambled with `seed`, as 32 bits.
inline std::uint32_t scrambled_sobol(std::uint32_t index, int dim, std::uint32_t seed) {
    return reverse_bits(owen_permute_reversed(sobol_reversed(index, dim), seed));
}

/// A 32-bit hash with good avalanche (Wellons' lowbias32, hash-prospector): the scramble seed
/// of a dimension from the pixel's key, at a third of SplitMix64's cost.
inline constexpr std::uint32_t hash32(std::uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    return x ^ (x >> 16);
}

/// The random numbers of one path sample: sequential like Rng::uniform(), from the current
/// dimension, which seek() moves to the place core/sample_dimensions.h gives each quantity.
/// Past kSobolDimensions, numbers come from the sample's PCG stream (Rng of the same seed,
/// pixel and sample), so paths of any depth stay correct; that stream is seeded at its first
/// use (paths that end before dimension 32 and integrators that never ask pay nothing for it).
class SobolSampler {
public:
    SobolSampler(const RngStream& stream, std::uint64_t sample_index)
        : m_stream(stream), m_key(static_cast<std::uint32_t>((stream.inc ^ stream.sample_key) >> 32)),
          m_index(static_cast<std::uint32_t>(sample_index)) {}

    float uniform() {
        if (m_dim >= kSobolDimensions) [[unlikely]] return fallback().uniform();
        const int dim = m_dim++;
        return static_cast<float>(scrambled_sobol(m_index, dim, dimension_seed(dim)) >> 8) * 0x1p-24f;
    }
    /// Makes `dim` the next dimension uniform() draws.
    void seek(int dim) { m_dim = dim; }
    /// The PCG stream behind the sampler (integrators that take their path's numbers from it):
    /// Rng(stream, sample), the same numbers whenever it is first asked for.
    Rng& fallback() {
        if (!m_fallback) [[unlikely]] m_fallback.emplace(m_stream, m_index);
        return *m_fallback;
    }

private:
    /// Owen scrambling needs an independent random permutation per (pixel, dimension): a
    /// hash of the pixel's key and the dimension (the golden-ratio step keeps the inputs of
    /// the dimensions apart before the hash mixes them).
    std::uint32_t dimension_seed(int dim) const {
        return hash32(m_key + static_cast<std::uint32_t>(dim) * 0x9e3779b9u);
    }
    RngStream m_stream;     ///< the pixel's PCG stream, for the fallback
    std::uint32_t m_key;    ///< the pixel's randomisation (from the seed and the pixel index)
    std::uint32_t m_index;  ///< the sample's index in the pixel's sequence
    int m_dim = 0;
    std::optional<Rng> m_fallback;
};

/// Moving to a dimension: the independent sampler has no dimensions (a no-op, so templated
/// integrators compile to the code of before for it).
inline void seek_dimension(Rng&, int) {}
inline void seek_dimension(SobolSampler& sampler, int dim) { sampler.seek(dim); }

/// The PCG stream of a sample, for integrators that draw everything from one.
inline Rng& pcg_stream(Rng& rng) { return rng; }
inline Rng& pcg_stream(SobolSampler& sampler) { return sampler.fallback(); }

}  // namespace spt

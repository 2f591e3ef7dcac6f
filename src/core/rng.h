// PCG32 random numbers, seeded per (seed, pixel, sample) so that every path sample draws the
// same numbers whichever thread runs it: images are bit-identical for any thread count.
#pragma once
#include <cstdint>

namespace spt {

/// SplitMix64 finaliser: a strong 64-bit mix used to derive PCG state from indices.
inline constexpr std::uint64_t mix64(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/// The part of Rng's seeding that all samples of a pixel share (two of its three hashes), to
/// be computed once per pixel rather than once per sample.
struct RngStream {
    RngStream(std::uint64_t seed, std::uint64_t pixel_index)
        : inc((mix64(seed * 0x9e3779b97f4a7c15ull + pixel_index) << 1u) | 1u),
          sample_key(mix64(seed + 0x632be59bd9b4e019ull)) {}
    std::uint64_t inc;         ///< the PCG stream (odd increment) of the pixel
    std::uint64_t sample_key;  ///< mixed into each sample's starting state
};

class Rng {
public:
    Rng(std::uint64_t seed, std::uint64_t pixel_index, std::uint64_t sample_index)
        : Rng(RngStream(seed, pixel_index), sample_index) {}
    Rng(const RngStream& stream, std::uint64_t sample_index) {
        m_inc = stream.inc;
        m_state = 0;
        next_u32();
        m_state += mix64(sample_index ^ stream.sample_key);
        next_u32();
    }

    std::uint32_t next_u32() {
        const std::uint64_t old = m_state;
        m_state = old * 6364136223846793005ull + m_inc;
        const auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
        const auto rot = static_cast<std::uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
    }

    /// Uniform float in [0, 1): 24 random bits, so 1 is never returned.
    float uniform() { return static_cast<float>(next_u32() >> 8) * 0x1p-24f; }

private:
    std::uint64_t m_state;
    std::uint64_t m_inc;
};

}  // namespace spt

// The directional half of the guiding field (Müller, Gross & Novák 2017, "Practical Path
// Guiding for Efficient Light-Transport Simulation", §3): a quadtree over the unit square onto
// which the sphere of directions maps with equal area (cylindrical coordinates:
// cos θ = 2u − 1, φ = 2πv), so a region's solid angle is 4π times its area and a density on
// the square converts to solid angle by a constant, p(ω) = p(u, v) / 4π.
//
// A node has four children (quadrant q = x + 2y, x = [u ≥ ½], y = [v ≥ ½] of its square) or
// none. A tree serves one of two roles in an iteration (render/guiding/guiding_field.h):
//  - recording: each path vertex adds its incident radiance over the density of the
//    direction it sampled (an estimate of the irradiance through the leaf's region) to the
//    leaf its direction falls in, one sum per channel, as fixed-point integers. Integer
//    addition is associative, so the sums, and every tree made from them, do not depend on
//    the order in which threads add.
//  - sampling: once the iteration ends, the sums are gathered up the tree; a direction is
//    drawn by descending from the root, a child chosen in proportion to its energy (first the
//    half in u, then the quadrant in v within it, so the two numbers keep their
//    stratification), then uniformly within the leaf; its density is the product of the
//    choices times 4^depth.
//  - sampling in product with a clamped cosine: at a vertex that only reflects, the field's
//    radiance matters only above the surface, and weighted by the cosine there. Each child's
//    energy is then weighted by the largest cosine with the normal over the child's region
//    (bounded through a cone around the region's centre direction), so regions below the
//    surface are never chosen and grazing ones seldom; the density is computed with the same
//    weights, level by level. (The product is approximate within a leaf, which is sampled
//    uniformly; what counts is that sample() and pdf() agree.)
// Channels: 1 (a luminance field) or several (a spectral field: one per wavelength band,
// render/guiding/guide_bands.h); the structure is shared, each channel has its energies.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "core/vec3.h"

namespace spt {

/// A point of the unit square, in double: a descent of 20 levels rescales the numbers 20
/// times, which float's 24 bits would not survive.
struct SquarePoint {
    double u = 0, v = 0;
};

/// Equal-area map between unit directions and the unit square.
SquarePoint direction_to_square(const Vec3& w);
Vec3 square_to_direction(const SquarePoint& s);

class DirectionalTree {
public:
    static constexpr int kMaxDepth = 20;

    /// A tree of `channels` channels, uniformly subdivided `depth` levels deep, sums 0.
    DirectionalTree(int channels, int depth);

    int channels() const { return m_channels; }
    int node_count() const { return static_cast<int>(m_nodes.size()); }

    // ---- Recording (thread-safe) ----
    /// Adds `units` (fixed point) to channel `channel` of the leaf that holds `s`.
    void record(const SquarePoint& s, int channel, std::uint64_t units);

    // ---- Between iterations ----
    /// Sets every node's energy from the recorded sums (`unit`: the value of one unit).
    void gather(double unit);
    /// The structure for the next iteration's recording, from this gathered tree: a node is
    /// subdivided while it holds more than `rho` of the tree's energy (each channel's energy
    /// taken relative to its total, so every channel counts the same) and more than
    /// kMinRecordsToSplit non-zero records (per channel), down to kMaxDepth; a region this tree
    /// did not subdivide is assumed to spread its energy and records evenly. Sums 0.
    /// (The record count is not in Müller et al.'s rule: where few paths find light, a
    /// region's energy may be one path's, and splitting to it makes a leaf of tiny area whose
    /// next estimate, from one or two records again, is a density spike at a direction
    /// nothing special lies in.)
    DirectionalTree refined(double rho) const;
    static constexpr double kMinRecordsToSplit = 32;

    // ---- Sampling (const, thread-safe) ----
    /// Whether channel c has energy: otherwise it gives no samples and density 0. With a
    /// normal `side` (the product with the clamped cosine), whether it has energy above the
    /// surface too.
    bool usable(int c, const Vec3* side = nullptr) const;
    /// A point of the square drawn from channel c (usable) with two uniform numbers, and its
    /// density on the square; in product with the clamped cosine around `side` if given.
    SquarePoint sample(int c, double u1, double u2, float& pdf, const Vec3* side = nullptr) const;
    /// The density on the square of channel c at s (0 for an unusable channel).
    float pdf(int c, const SquarePoint& s, const Vec3* side = nullptr) const;

    /// Equality of structure and energies (tests: trees made by different thread counts).
    bool operator==(const DirectionalTree& other) const;

private:
    struct Node {
        std::uint32_t first_child = 0;  ///< children at first_child..+3; 0: a leaf
        bool leaf() const { return first_child == 0; }
    };
    float energy(std::uint32_t node, int c) const {
        return m_energy[static_cast<std::size_t>(node) * m_channels + c];
    }
    /// A cone that holds a node's region: its centre direction and angular radius.
    struct Cone {
        Vec3 axis;
        float cos_radius = -1.f, sin_radius = 0.f;
    };
    /// The weight of a node in a descent: its energy, times the largest clamped cosine with
    /// `side` over its cone when given.
    float weight(std::uint32_t node, int c, const Vec3* side) const;
    /// The weights of the four children from `first`, as sample() and pdf() descend.
    std::array<double, 4> child_weights(std::uint32_t first, int c, const Vec3* side) const;
    /// Appends four leaves as the children of `node`.
    void subdivide(std::uint32_t node);

    int m_channels;
    std::vector<Node> m_nodes;
    std::vector<std::uint64_t> m_units;  ///< per node and channel (leaves), added atomically
    /// Non-zero records per node and channel (leaves while recording, every node once gathered)
    std::vector<std::uint64_t> m_records;
    std::vector<float> m_energy;         ///< per node and channel, set by gather()
    std::vector<Cone> m_cones;           ///< per node, set by gather()
};

}  // namespace spt

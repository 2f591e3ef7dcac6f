// The learned incident-radiance field of path guiding: Müller, Gross & Novák 2017's SD-tree
// ("Practical Path Guiding for Efficient Light-Transport Simulation", §3–4). A binary tree
// over space (a cube around the scene, each level halving the axis of depth mod 3) whose
// leaves each hold two directional quadtrees (render/guiding/directional_tree.h): one that
// the current iteration samples from, learnt in the iteration before, and one that it records
// into.
//
// Training runs in iterations of doubling sample counts (render/guiding/guiding_schedule.h).
// After an iteration (end_iteration):
//  1. each leaf's recording tree is gathered and becomes its sampling tree, and its refined
//     structure becomes the next recording tree (Müller's ρ = 0.01 of the energy per node);
//  2. each leaf chooses the probability α with which its vertices sample the guide (against
//     the BSDF) for the next iteration: the candidate of kGuideFractions whose estimated
//     second moment of the vertex's estimator was least (below);
//  3. a leaf that received more than c·√(spp of the iteration) records (Müller's c = 12000)
//     is split in two, and again while its halves would still exceed that; both halves copy
//     its trees and α.
//
// The second moment of a candidate α' is estimated from the same records, by importance
// sampling: a vertex whose direction ω was drawn with density p(ω) and contributed X (its
// radiance through ω over the throughput before the vertex) adds X²·p(ω)/p_α'(ω), with
// p_α' = α'·p_guide + (1 − α')·p_bsdf. A field that has learnt little, or learnt from
// surfaces that see other light (a cell across a wall), then costs nearly nothing: its leaf
// chooses α = 0. (Müller et al. 2019 learn α by gradient descent per record; a choice among
// candidates from summed moments keeps the field independent of the order of the records.)
//
// Recorded values are fixed-point integers (unit: set_unit), so the field after an iteration
// is the same whatever the thread count or order: the image is deterministic, and a resumed
// or split render rebuilds the exact field by replaying the training samples before its
// first sample (render/renderer.cpp).
//
// Channels: 1 (a luminance field: the mean over the path's live wavelengths) or kGuideBands
// (a spectral field, one per wavelength band: render/guiding/guide_bands.h).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "core/vec3.h"
#include "render/guiding/directional_tree.h"

namespace spt {

class GuidingField {
public:
    static constexpr double kSpatialThreshold = 12000;  ///< Müller's c
    static constexpr double kDirectionalThreshold = 0.01;  ///< Müller's ρ

    /// A field over the cube of half-side `radius` around `center` (points outside are
    /// assigned to the nearest leaf), with `channels` channels, nothing learnt yet.
    GuidingField(const Vec3& center, float radius, int channels);

    /// The candidates for α, and the one of a leaf that has not chosen yet.
    static constexpr float kGuideFractions[] = {0.f, 0.25f, 0.5f, 0.75f};
    static constexpr int kFirstFraction = 2;

    int channels() const { return m_channels; }
    /// Sets the value of one recorded unit (a small fraction of the scene's typical
    /// radiance, so that the fixed point resolves it: Renderer's pilot).
    void set_unit(double unit) { m_unit = unit; }
    double unit() const { return m_unit; }
    /// Iterations ended so far (0: nothing to sample from).
    int iterations() const { return m_iterations; }

    /// The leaf holding p.
    int leaf_of(const Vec3& p) const;
    const DirectionalTree& sampling_tree(int leaf) const { return m_leaves[static_cast<std::size_t>(leaf)].sampling; }

    /// Records `value` (radiance over density, ≥ 0) in channel `channel` of leaf `leaf` for
    /// the direction `s`. Thread-safe.
    void record(int leaf, const SquarePoint& s, int channel, float value);
    /// Counts one record in leaf `leaf` (once per vertex, whatever its channels). Thread-safe.
    void count(int leaf);
    /// Records a guided vertex's contribution `x` through a direction of density `pdf` (the
    /// mixture with the leaf's α), where the guide's density is `pdf_guide` and the BSDF's
    /// `pdf_bsdf`: the second moments of the candidates for α. Thread-safe.
    void record_moments(int leaf, float x, float pdf, float pdf_guide, float pdf_bsdf);
    /// The probability of sampling the guide at leaf `leaf` (α) in this iteration.
    float guide_fraction(int leaf) const { return m_leaves[static_cast<std::size_t>(leaf)].fraction; }

    /// Ends an iteration of `spp` samples per pixel (steps 1 and 2 above).
    void end_iteration(int spp);

    int leaf_count() const { return static_cast<int>(m_leaves.size()); }
    /// Equality of the spatial structure and every tree (tests).
    bool operator==(const GuidingField& other) const;

private:
    static constexpr int kFractionCount = 4;
    struct Leaf {
        DirectionalTree sampling, recording;
        std::uint64_t records = 0;  ///< added atomically
        std::array<std::uint64_t, kFractionCount> moments{};  ///< per candidate α, added atomically
        float fraction = kGuideFractions[kFirstFraction];
    };
    struct Node {
        int child = -1;  ///< children at child and child + 1; −1: a leaf
        int leaf = -1;
    };
    void split(int node, int depth, std::uint64_t records, double threshold);

    Vec3 m_lo, m_hi;
    int m_channels;
    double m_unit = 1.0;
    int m_iterations = 0;
    std::vector<Node> m_nodes;
    std::vector<Leaf> m_leaves;
};

}  // namespace spt

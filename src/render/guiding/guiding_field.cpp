#include "render/guiding/guiding_field.h"

#include <algorithm>
#include <atomic>
#include <cmath>

namespace spt {

namespace {

/// Directional trees start 2 levels deep (16 regions), so the first refinement has more to
/// go on than one root sum.
constexpr int kInitialDepth = 2;

/// A record above 2^44 units is clipped there: far above any sum's usual size, so that no sum
/// can overflow 64 bits. Clipping changes only where the guide samples, never the estimate.
constexpr double kMostUnits = 0x1p44;

}  // namespace

GuidingField::GuidingField(const Vec3& center, float radius, int channels)
    : m_lo(center - Vec3{radius, radius, radius}), m_hi(center + Vec3{radius, radius, radius}),
      m_channels(channels), m_nodes(1) {
    m_nodes[0].leaf = 0;
    m_leaves.push_back({DirectionalTree(channels, 0), DirectionalTree(channels, kInitialDepth)});
}

int GuidingField::leaf_of(const Vec3& p) const {
    Vec3 lo = m_lo, hi = m_hi;
    int n = 0;
    for (int depth = 0; m_nodes[static_cast<std::size_t>(n)].child >= 0; ++depth) {
        const int axis = depth % 3;
        const float mid = 0.5f * (lo[axis] + hi[axis]);
        const Node& node = m_nodes[static_cast<std::size_t>(n)];
        if (p[axis] < mid) {
            hi[axis] = mid;
            n = node.child;
        } else {
            lo[axis] = mid;
            n = node.child + 1;
        }
    }
    return m_nodes[static_cast<std::size_t>(n)].leaf;
}

void GuidingField::record(int leaf, const SquarePoint& s, int channel, float value) {
    if (!(value > 0.f)) return;
    const double units = std::min(std::round(double(value) / m_unit), kMostUnits);
    if (units < 1) return;
    m_leaves[static_cast<std::size_t>(leaf)].recording.record(s, channel, static_cast<std::uint64_t>(units));
}

void GuidingField::count(int leaf) {
    std::atomic_ref<std::uint64_t>(m_leaves[static_cast<std::size_t>(leaf)].records)
        .fetch_add(1, std::memory_order_relaxed);
}

void GuidingField::record_moments(int leaf, float x, float pdf, float pdf_guide, float pdf_bsdf) {
    if (!(x > 0.f) || !(pdf > 0.f)) return;
    // Moments are in units of (the radiance unit · 2^24)² · 2^-24: the same resolution relative
    // to a typical squared contribution as the field's records.
    const double unit = m_unit * m_unit * 0x1p24;
    const double x2 = double(x) * double(x) * pdf;
    Leaf& l = m_leaves[static_cast<std::size_t>(leaf)];
    for (int k = 0; k < kFractionCount; ++k) {
        const double alpha = kGuideFractions[k];
        const double p = alpha * pdf_guide + (1 - alpha) * pdf_bsdf;
        const double units = p > 0 ? std::min(std::round(x2 / p / unit), kMostUnits) : kMostUnits;
        std::atomic_ref<std::uint64_t>(l.moments[static_cast<std::size_t>(k)])
            .fetch_add(static_cast<std::uint64_t>(units), std::memory_order_relaxed);
    }
}

void GuidingField::end_iteration(int spp) {
    for (Leaf& leaf : m_leaves) {
        leaf.recording.gather(m_unit);
        leaf.sampling = std::move(leaf.recording);
        leaf.recording = leaf.sampling.refined(kDirectionalThreshold);
        // The candidate of least second moment (ties: the first, the smaller α); a leaf
        // without guided records keeps its α.
        if (std::any_of(leaf.moments.begin(), leaf.moments.end(), [](std::uint64_t m) { return m > 0; }))
            leaf.fraction = kGuideFractions[std::min_element(leaf.moments.begin(), leaf.moments.end()) -
                                            leaf.moments.begin()];
        leaf.moments = {};
    }
    const double threshold = kSpatialThreshold * std::sqrt(double(spp));
    // Depth first from the root, so a node's depth (its split axis) is known.
    struct Item {
        int node, depth;
    };
    std::vector<Item> stack{{0, 0}};
    while (!stack.empty()) {
        const Item item = stack.back();
        stack.pop_back();
        const Node node = m_nodes[static_cast<std::size_t>(item.node)];
        if (node.child >= 0) {
            stack.push_back({node.child, item.depth + 1});
            stack.push_back({node.child + 1, item.depth + 1});
            continue;
        }
        split(item.node, item.depth, m_leaves[static_cast<std::size_t>(node.leaf)].records, threshold);
    }
    for (Leaf& leaf : m_leaves) leaf.records = 0;
    ++m_iterations;
}

void GuidingField::split(int node, int depth, std::uint64_t records, double threshold) {
    // Depth 60 is a box 2^20 times smaller than the scene in every axis: far past usefulness,
    // and a bound on the recursion.
    if (!(double(records) > threshold) || depth >= 60) return;
    const int leaf = m_nodes[static_cast<std::size_t>(node)].leaf;
    const int child = static_cast<int>(m_nodes.size());
    m_nodes.resize(m_nodes.size() + 2);
    m_nodes[static_cast<std::size_t>(node)] = {child, -1};
    const Leaf copy = m_leaves[static_cast<std::size_t>(leaf)];
    m_nodes[static_cast<std::size_t>(child)].leaf = leaf;
    m_nodes[static_cast<std::size_t>(child) + 1].leaf = static_cast<int>(m_leaves.size());
    m_leaves.push_back(copy);
    split(child, depth + 1, records / 2, threshold);
    split(child + 1, depth + 1, records / 2, threshold);
}

bool GuidingField::operator==(const GuidingField& other) const {
    if (m_nodes.size() != other.m_nodes.size() || m_leaves.size() != other.m_leaves.size()) return false;
    for (std::size_t i = 0; i < m_nodes.size(); ++i)
        if (m_nodes[i].child != other.m_nodes[i].child || m_nodes[i].leaf != other.m_nodes[i].leaf) return false;
    for (std::size_t i = 0; i < m_leaves.size(); ++i)
        if (!(m_leaves[i].sampling == other.m_leaves[i].sampling) ||
            !(m_leaves[i].recording == other.m_leaves[i].recording) ||
            m_leaves[i].fraction != other.m_leaves[i].fraction)
            return false;
    return true;
}

}  // namespace spt

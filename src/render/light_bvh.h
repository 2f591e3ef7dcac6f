// A light BVH: next-event estimation's choice of an emitter by its likely contribution to the
// shading point rather than by power alone (Conty Estévez & Kulla 2018, "Importance Sampling
// of Many Lights with Adaptive Tree Splitting"; pbrt-v4's BVHLightSampler, Pharr, Jakob &
// Humphreys, "Physically Based Rendering", 4th ed., §12.6.3).
//
// Entries: every finite light of the next-event set, and each triangle of an emitting mesh
// as an entry of its own (a mesh of 10 000 small emitters is 10 000 choices, each by its
// own distance and orientation; a mesh as one entry would be bounded by its whole box and
// sampled by area). A quad, a sphere or a quadric is one entry. Each node holds the
// LightBounds (model/lights/light_bounds.h) of what lies under it.
//
// Sampling descends from the root: at a node, child c is taken with probability
// I_c / (I_0 + I_1) (light_importance at the shading point), the random number rescaled to
// the chosen interval and reused below; a node whose children both have importance 0 gives
// no sample (nothing below can light the point). The probability of an entry is the product
// of the choices on its path; pmf() recomputes exactly that product along the entry's
// recorded path (one bit per level), with the same operations in the same order, so it
// equals what sample() returned bit for bit (MIS of emission that BSDF sampling finds).
//
// Infinite lights (the environment, and the emitting infinite planes when they are sampled)
// have no box: as in pbrt-v4 each takes an equal share 1 / (n_infinite + 1), and the tree
// the rest.
//
// A triangle's choice is reported as an equivalent choice of its whole light: its
// probability times total_area / its area. The light then samples a point on that triangle
// (TriangleMeshLight::sample_li_on) and states its usual density (1 / total_area, in solid
// angle), so choice × density is the triangle's true density and emission weights keep the
// form choice × light_pdf_li.
//
// Light subpaths (bdpt, vcm) keep choosing their origin by power (render/light_sampling.h):
// they start from no shading point.
#pragma once
#include <cstdint>
#include <vector>

#include "model/lights/light.h"
#include "model/lights/light_bounds.h"
#include "model/lights/light_sample.h"

namespace spt {

class LightBvh {
public:
    /// One choice of the tree: light `light`, or its triangle `triangle` (−1: the whole light).
    struct Entry {
        int light = -1;
        int triangle = -1;
        float area_ratio = 1.f;  ///< total_area / the triangle's area (1 for whole lights)
        std::uint64_t path = 0;  ///< bit d: the child taken at depth d (1: the second)
    };

    /// Builds over `lights` (Scene::lights): the finite lights whose `weights` (their power,
    /// the bounds' φ) are > 0 go into the tree, each emitting mesh triangle by triangle, the
    /// infinite ones (light_type infinite, and PlaneLight when with_planes) into the infinite
    /// share.
    /// `first_triangle[i]`: the scene index of mesh light i's first triangle when its
    /// triangles are consecutive there (a hit's triangle is then known), else −1 (the mesh
    /// is one entry).
    void build(const std::vector<Light>& lights, const std::vector<float>& weights,
               const std::vector<int>& first_triangle);

    bool empty() const { return m_entries.empty() && m_infinite.empty(); }
    /// Entries in the tree (for tests).
    const std::vector<Entry>& entries() const { return m_entries; }
    /// The infinite share's lights: the environments first, then the planes.
    std::size_t infinite_count(bool with_planes) const { return with_planes ? m_infinite.size() : m_environments; }

    /// Samples an entry for the shading point ctx with u in [0, 1): the index of an entry
    /// (≥ 0) or of an infinite light as −2 − k (k-th of the infinite share), with its
    /// probability in `prob`; −1 when nothing can light the point.
    int sample(const LightSampleContext& ctx, float u, bool with_planes, float& prob) const;
    /// Probability that sample() returns entry e for ctx.
    float entry_pmf(const LightSampleContext& ctx, int e, bool with_planes) const;
    /// Probability of the k-th infinite light.
    float infinite_pmf(bool with_planes) const {
        const std::size_t n = infinite_count(with_planes);
        return n == 0 ? 0.f : 1.f / static_cast<float>(n + (m_nodes.empty() ? 0 : 1));
    }

    /// The light an index from sample() names (Scene::lights), and the triangle (−1: none).
    int light_of(int index, int& triangle) const {
        if (index >= 0) {
            triangle = m_entries[static_cast<std::size_t>(index)].triangle;
            return m_entries[static_cast<std::size_t>(index)].light;
        }
        triangle = -1;
        return m_infinite[static_cast<std::size_t>(-2 - index)];
    }

    /// The equivalent choice of light `light` (a whole-light probability: see the header)
    /// for ctx; `scene_triangle` is the scene index of the triangle a ray hit on it (−1:
    /// none). 0 when sample() never chooses it there.
    float light_choice(const LightSampleContext& ctx, int light, int scene_triangle, bool with_planes) const;

private:
    struct Node {
        LightBounds bounds;
        int child = -1;  ///< interior: index of the second child (the first follows the node)
        int entry = -1;  ///< leaf: the entry
    };
    int build_node(std::vector<int>& order, std::vector<LightBounds>& leaf_bounds, std::size_t begin,
                   std::size_t end, int depth, std::uint64_t path);

    std::vector<Node> m_nodes;          ///< depth first; the root is node 0
    std::vector<Entry> m_entries;
    std::vector<int> m_infinite;        ///< Scene::lights indices: environments, then planes
    std::size_t m_environments = 0;
    std::vector<int> m_light_entry;     ///< per light: its (first) entry, −1 for none
    std::vector<int> m_light_first_triangle;  ///< per light: its triangles' first scene index, or −1
    std::vector<int> m_infinite_slot;   ///< per light: its place in m_infinite, or −1
};

}  // namespace spt

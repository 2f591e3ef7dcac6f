// Bounding volume hierarchy over the bounded shapes of a scene (spheres and triangles;
// infinite planes stay outside). Binned SAH build (Wald 2007), nodes flattened depth-first
// into 32-byte records (pbrt-v4's LinearBVHNode), leaves of at most 4 primitives, iterative
// near-child-first traversal with a fixed stack: no allocation and no virtual call per ray.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/aabb.h"
#include "geometry/sphere.h"
#include "geometry/triangle.h"

namespace spt {

/// A primitive of the BVH: a triangle (top bit set) or a sphere, by index in its array.
using PrimRef = std::uint32_t;
inline constexpr PrimRef kTriangleBit = 0x80000000u;
inline bool is_triangle(PrimRef p) { return (p & kTriangleBit) != 0; }
inline std::uint32_t prim_index(PrimRef p) { return p & ~kTriangleBit; }

struct BvhNode {
    float lo[3], hi[3];
    bool hit_by(const RaySlabs& r, float t_max) const {
        const float* const b[2] = {lo, hi};
        return slab_hit(b, r, t_max);
    }
    /// Leaf: first entry in the primitive list. Interior: index of the second child (the
    /// first child is the next node).
    std::uint32_t offset;
    std::uint16_t count;  ///< primitives in a leaf; 0 for an interior node
    std::uint8_t axis;    ///< split axis of an interior node
    std::uint8_t pad = 0;
};
static_assert(sizeof(BvhNode) == 32, "BVH nodes are 32 bytes: two per cache line");

/// Nearest primitive found by Bvh::intersect.
struct BvhHit {
    double t = kInfinity;
    PrimRef prim = 0;
    TriangleIntersection tri{};  ///< filled for triangles
};

struct BvhBuildStats {
    int nodes = 0, leaves = 0, max_depth = 0;
};

class Bvh {
public:
    static constexpr int kMaxLeafSize = 4;
    static constexpr int kBins = 12;
    static constexpr int kStackSize = 128;  ///< the build keeps the depth below this

    /// Builds over all spheres and triangles (replacing any previous tree).
    BvhBuildStats build(std::span<const Sphere> spheres, std::span<const Triangle> triangles);

    bool empty() const { return m_nodes.empty(); }
    std::size_t node_count() const { return m_nodes.size(); }
    std::span<const BvhNode> nodes() const { return m_nodes; }

    /// Nearest hit with t in (0, t_best) among the primitives (the arrays the tree was built
    /// over). On a hit, `t_best` and `hit` are updated and true is returned.
    bool intersect(const Ray& ray, std::span<const Sphere> spheres, std::span<const Triangle> triangles,
                   double& t_best, BvhHit& hit) const;

    /// True if any primitive is hit with t in (0, ray.t_max) (shadow rays: first hit wins).
    bool occluded(const Ray& ray, std::span<const Sphere> spheres, std::span<const Triangle> triangles) const;

private:
    struct BuildPrim {
        Aabb box;
        Vec3 centroid;
        PrimRef ref;
    };
    int build_node(std::vector<BuildPrim>& prims, int begin, int end, int depth, BvhBuildStats& stats);

    std::vector<BvhNode> m_nodes;
    std::vector<PrimRef> m_prims;  ///< leaf primitive lists, in node order
};

/// Bounding box of a sphere, rounded outwards.
Aabb bounds(const Sphere& s);
/// Bounding box of a triangle (its vertices are exact, so no rounding).
Aabb bounds(const Triangle& t);

}  // namespace spt

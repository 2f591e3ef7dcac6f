// Bounding volume hierarchy over the bounded shapes of a scene (spheres, triangles, disks,
// cylinders and cones; infinite planes stay outside). Binned SAH build (Wald 2007), nodes flattened depth-first
// into 32-byte records (pbrt-v4's LinearBVHNode), leaves of at most 4 primitives, iterative
// near-child-first traversal with a fixed stack: no allocation and no virtual call per ray.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/aabb.h"
#include "geometry/cone.h"
#include "geometry/cylinder.h"
#include "geometry/disk.h"
#include "geometry/sphere.h"
#include "geometry/triangle.h"

namespace spt {

/// The shape arrays a BVH is built over and traversed with (the same arrays both times); its
/// primitives are PrimIds (kind and index) into them.
struct BvhShapes {
    std::span<const Sphere> spheres{};
    std::span<const Triangle> triangles{};
    std::span<const Disk> disks{};
    std::span<const Cylinder> cylinders{};
    std::span<const Cone> cones{};
};

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
    PrimId prim;
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

    /// Builds over all the shapes (replacing any previous tree).
    BvhBuildStats build(const BvhShapes& shapes);

    bool empty() const { return m_nodes.empty(); }
    std::size_t node_count() const { return m_nodes.size(); }
    std::span<const BvhNode> nodes() const { return m_nodes; }

    /// Nearest hit with t in (0, t_best) among the primitives (the arrays the tree was built
    /// over). On a hit, `t_best` and `hit` are updated and true is returned.
    bool intersect(const Ray& ray, const BvhShapes& shapes, double& t_best, BvhHit& hit) const;

    /// True if any primitive is hit with t in (0, ray.t_max) (shadow rays: first hit wins).
    bool occluded(const Ray& ray, const BvhShapes& shapes) const;

private:
    struct BuildPrim {
        Aabb box;
        Vec3 centroid;
        PrimId ref;
    };
    int build_node(std::vector<BuildPrim>& prims, int begin, int end, int depth, BvhBuildStats& stats);

    std::vector<BvhNode> m_nodes;
    std::vector<PrimId> m_prims;  ///< leaf primitive lists, in node order
};

/// Bounding box of a sphere, rounded outwards.
Aabb bounds(const Sphere& s);
/// Bounding box of a triangle (its vertices are exact, so no rounding).
Aabb bounds(const Triangle& t);
/// Bounding boxes of the quadrics, computed in double and rounded outwards.
Aabb bounds(const Disk& d);
Aabb bounds(const Cylinder& c);
Aabb bounds(const Cone& c);

}  // namespace spt

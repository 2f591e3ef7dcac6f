// Bounding volume hierarchy over the bounded shapes of a scene (every type of the set with
// bounds(), geometry/shape.h; infinite planes stay outside). A binary tree is built by binned SAH over
// all three axes (Wald 2007), in parallel for large subtrees, then collapsed into 8-wide nodes
// whose eight child boxes are tested at once (the layout of Embree's BVH8 and of Ylitie et al.
// 2017, without compression); leaves hold up to 8 primitives in packets of four, triangles
// copied in leaf order side by side (triangle_lanes.h) so that four are tested at once.
// Traversal is iterative with a fixed stack, nearest child first: no allocation and no
// virtual call per ray. Box tests are conservative (aabb.h), so the watertight triangle test
// decides every hit exactly as it would without the tree.
//
// The nearest hit does not depend on the tree: of the primitives whose distance is smallest,
// the one with the smallest (instance, PrimId) wins, whatever order the walk meets them in. A
// tree of another width or from another build therefore returns the same hit, as a loop over
// the primitives does, and an image does not change with the tree.
#pragma once
#include <concepts>
#include <cstdint>
#include <span>
#include <tuple>
#include <vector>

#include "core/simd.h"
#include "geometry/aabb.h"
#include "geometry/mesh_instance.h"
#include "geometry/shape.h"
#include "geometry/triangle_lanes.h"

namespace spt {

struct InstancedMesh;

/// Bounding box of a sphere, rounded outwards.
Aabb bounds(const Sphere& s);
/// Bounding box of a triangle (its vertices are exact, so no rounding).
Aabb bounds(const Triangle& t);
/// Bounding boxes of the quadrics, computed in double and rounded outwards.
Aabb bounds(const Disk& d);
Aabb bounds(const Cylinder& c);
Aabb bounds(const Cone& c);

/// Shape types with bounds() go into the tree; the others (infinite planes) stay beside it.
template <typename T>
concept BoundedShape = requires(const T& shape) {
    { bounds(shape) } -> std::same_as<Aabb>;
};

namespace detail {
template <typename Tuple>
struct SpansOf;
template <typename... Ts>
struct SpansOf<std::tuple<Ts...>> {
    using type = std::tuple<std::span<const Ts>...>;
};
}  // namespace detail

/// The shape arrays a BVH is built over and traversed with (the same arrays both times); its
/// primitives are PrimIds (kind and index) into them.
struct BvhShapes {
    /// One array per type of the set (geometry/shape.h); empty ones are simply absent.
    detail::SpansOf<ShapeTypes>::type arrays{};
    /// Placed meshes (a two-level BVH: their own trees are in `meshes`, indexed by
    /// MeshInstance::mesh).
    std::span<const MeshInstance> instances{};
    const InstancedMesh* meshes = nullptr;

    template <typename T>
    std::span<const T> of() const { return std::get<std::span<const T>>(arrays); }
    /// The given arrays (of distinct shape types), the others empty.
    template <typename... V>
    static BvhShapes of_arrays(const V&... arrays) {
        BvhShapes shapes;
        ((std::get<std::span<const typename V::value_type>>(shapes.arrays) = arrays), ...);
        return shapes;
    }
    /// Every array of `all`.
    template <typename A>
    static BvhShapes of_all(const A& all) {
        BvhShapes shapes;
        all.for_each_array([&](const auto& array) {
            std::get<std::span<const typename std::decay_t<decltype(array)>::value_type>>(shapes.arrays) = array;
        });
        return shapes;
    }
};

/// An 8-wide node: the boxes of its eight children side by side (lane k = child k), tested
/// against a ray at once with eight-lane float vectors. An unused slot has an empty box
/// (lo = +inf, hi = −inf), which no ray hits.
struct alignas(64) WideBvhNode {
    static constexpr int kWidth = 8;
    Float8 box[2][3];  ///< box[0][axis]: the children's lower bounds; box[1][axis]: upper
    /// Per child: (index << 4) | count. count 0: an inner node (index into the nodes);
    /// count 1–15: a leaf of `count` primitives in the leaf packets from index on (four to a
    /// packet, the last one padded).
    std::uint32_t child[kWidth];
};
static_assert(sizeof(WideBvhNode) == 256, "a wide node is four cache lines");

/// Four primitives of a leaf, in leaf order (lane k = the leaf's primitive 4·packet + k).
/// Triangles carry a copy of their vertices in `triangles` (so a leaf's triangles are read
/// from consecutive memory and tested four at once); other shapes are reached through `prim`
/// (their vertex lanes are zero). Lanes past the leaf's end are padding.
struct BvhLeafPacket {
    TriangleLanes triangles;
    PrimId prim[4];
};
static_assert(sizeof(BvhLeafPacket) == 160, "four primitives in 160 bytes, as four 40-byte entries were");

/// Nearest primitive found by Bvh::intersect.
struct BvhHit {
    double t = kInfinity;
    PrimId prim;
    TriangleIntersection tri{};  ///< filled for triangles
    /// The instance hit (an index into BvhShapes::instances), whose mesh's triangle `prim`
    /// is; kNoInstance when `prim` is one of the arrays' own shapes.
    std::uint32_t instance = kNoInstance;
    static constexpr std::uint32_t kNoInstance = ~0u;
};

struct BvhBuildStats {
    int nodes = 0;      ///< wide nodes
    int leaves = 0;     ///< leaves (each of up to Bvh::kMaxLeafSize primitives)
    int max_depth = 0;  ///< depth of the binary SAH tree the wide nodes are collapsed from
};

class Bvh {
public:
    static constexpr int kMaxLeafSize = 8;
    static constexpr int kBins = 16;
    static constexpr int kStackSize = 128;  ///< the build keeps the binary depth below this

    /// Builds over all the shapes (replacing any previous tree). Subtrees of many primitives
    /// are built on several threads; the tree does not depend on how many.
    BvhBuildStats build(const BvhShapes& shapes);

    bool empty() const { return m_nodes.empty(); }
    std::size_t node_count() const { return m_nodes.size(); }
    /// Bytes held by the tree (nodes and leaf copies), for the benchmark's memory per triangle.
    std::size_t memory_bytes() const {
        return m_nodes.capacity() * sizeof(WideBvhNode) + m_leaf.capacity() * sizeof(BvhLeafPacket);
    }

    /// Nearest hit with t in (0, t_best) among the primitives (the arrays the tree was built
    /// over). On a hit, `t_best` and `hit` are updated and true is returned. Children are
    /// visited nearest first.
    /// Of equally near primitives, the one with the smallest (instance, PrimId) wins (the
    /// arrays' own primitives count as instance kNoInstance). `hit` comes in empty; t_best may
    /// be a distance found elsewhere (the caller's planes), which a primitive must beat strictly.
    bool intersect(const Ray& ray, const BvhShapes& shapes, double& t_best, BvhHit& hit) const {
        return intersect(ray, shapes, t_best, hit, BvhHit::kNoInstance, t_best);
    }

    /// True if any primitive is hit with t in (0, ray.t_max) (shadow rays: the first hit
    /// found ends the walk, and children are not sorted).
    bool occluded(const Ray& ray, const BvhShapes& shapes) const;

private:
    /// intersect() for the primitives of `instance` (kNoInstance: the arrays' own), with
    /// distances below `limit` (the caller's t_best when the walk began).
    bool intersect(const Ray& ray, const BvhShapes& shapes, double& t_best, BvhHit& hit, std::uint32_t instance,
                   double limit) const;

    struct BuildPrim {
        Aabb box;
        Vec3 centroid;
        PrimId ref;
    };
    /// The binary SAH tree the wide nodes are collapsed from.
    struct BinaryNode {
        Aabb box;
        int child[2] = {-1, -1};  ///< −1: a leaf of prims [begin, end)
        int begin = 0, end = 0;
    };
    struct BuildContext;
    static int build_binary(BuildContext& ctx, int begin, int end, int depth, std::vector<BinaryNode>& out);
    std::uint32_t collapse(const std::vector<BinaryNode>& tree, int node, const std::vector<BuildPrim>& prims,
                           const BvhShapes& shapes, BvhBuildStats& stats);

    std::vector<WideBvhNode> m_nodes;  ///< depth-first; the root is node 0
    std::vector<BvhLeafPacket> m_leaf;  ///< the leaves' primitives, leaf after leaf
};

}  // namespace spt

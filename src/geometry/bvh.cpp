// BVH build (binned SAH) and traversal. See bvh.h.
#include "geometry/bvh.h"

#include "geometry/instanced_mesh.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <stdexcept>
#include <thread>

namespace spt {

Aabb bounds(const Sphere& s) {
    // c ± r rounds to nearest; one more ulp outwards makes the box conservative.
    const Vec3 r(s.radius, s.radius, s.radius);
    const Vec3 lo = s.center - r, hi = s.center + r;
    Aabb b;
    b.lo = {next_float_down(lo.x), next_float_down(lo.y), next_float_down(lo.z)};
    b.hi = {next_float_up(hi.x), next_float_up(hi.y), next_float_up(hi.z)};
    return b;
}

Aabb bounds(const Triangle& t) {
    Aabb b;
    b.expand(t.p0);
    b.expand(t.p1);
    b.expand(t.p2);
    return b;
}

namespace {

/// Half-extents per axis of a circle of radius r about the unit normal n: r·√(1 − nᵢ²).
DVec3 rim_extent(const DVec3& n, double r) {
    auto e = [r](double c) { return r * std::sqrt(std::max(0.0, 1.0 - c * c)); };
    return {e(n.x), e(n.y), e(n.z)};
}

/// The box [lo, hi] computed in double, grown by pad (the error of the double arithmetic,
/// which matters where lo or hi cancel to near 0) and rounded outwards to floats.
Aabb outward_box(const DVec3& lo, const DVec3& hi, double pad) {
    Aabb b;
    b.lo = {next_float_down(static_cast<float>(lo.x - pad)), next_float_down(static_cast<float>(lo.y - pad)),
            next_float_down(static_cast<float>(lo.z - pad))};
    b.hi = {next_float_up(static_cast<float>(hi.x + pad)), next_float_up(static_cast<float>(hi.y + pad)),
            next_float_up(static_cast<float>(hi.z + pad))};
    return b;
}

DVec3 min(const DVec3& a, const DVec3& b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
DVec3 max(const DVec3& a, const DVec3& b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }

}  // namespace

Aabb bounds(const Disk& d) {
    const DVec3 c(d.center), e = rim_extent(d.unit_normal(), d.radius);
    return outward_box(c - e, c + e, 32.0 * kDoubleEps * (max_abs(c) + d.radius));
}

Aabb bounds(const Cylinder& cyl) {
    // The hull of the two rims (a tube is convex in every axis direction's extremes).
    const DVec3 a = cyl.unit_axis(), b(cyl.base), top = b + double(cyl.height) * a;
    const DVec3 e = rim_extent(a, cyl.radius);
    return outward_box(min(b, top) - e, max(b, top) + e,
                       32.0 * kDoubleEps * (max_abs(b) + cyl.radius + cyl.height));
}

Aabb bounds(const Cone& cone) {
    // The hull of the base rim and the apex.
    const DVec3 a = cone.unit_axis(), b(cone.base), apex = b + double(cone.height) * a;
    const DVec3 e = rim_extent(a, cone.radius);
    return outward_box(min(b - e, apex), max(b + e, apex),
                       32.0 * kDoubleEps * (max_abs(b) + cone.radius + cone.height));
}

struct Bvh::BuildContext {
    std::vector<BuildPrim> prims;
    std::atomic<int> spare_threads{0};  ///< threads that may still be started
};

namespace {

/// Subtrees of fewer primitives are built on the thread that reaches them (a thread costs
/// tens of microseconds; a subtree of this size, milliseconds).
constexpr int kParallelMin = 16384;
/// The SAH's cost of visiting a node, relative to testing one leaf packet (four boxes in float
/// against four triangles in double). Measured (callgrind, generated 100 k mesh, diffuse and
/// shadow rays): 0.5 walks 6 % fewer instructions than 1.0 (and than 2.0: 5 % more); 0.25
/// no fewer than 0.5, with more nodes.
constexpr double kTraversalCost = 0.5;
/// Leaf packets of n primitives: a leaf's cost is in packets, not primitives (a leaf of 3
/// costs as much as one of 4), so the SAH fills packets instead of making leaves of 1 or 2.
constexpr int packets(int n) { return (n + 3) >> 2; }

}  // namespace

int Bvh::build_binary(BuildContext& ctx, int begin, int end, int depth, std::vector<BinaryNode>& out) {
    std::vector<BuildPrim>& prims = ctx.prims;
    const int index = static_cast<int>(out.size());
    out.emplace_back();
    Aabb box, centroids;
    for (int i = begin; i < end; ++i) {
        box.expand(prims[i].box);
        centroids.expand(prims[i].centroid);
    }
    out[index].box = box;
    out[index].begin = begin;
    out[index].end = end;
    const int n = end - begin;
    if (n == 1) return index;

    const int largest = centroids.largest_axis();
    auto median = [&](int axis) {
        const int mid = begin + n / 2;
        std::nth_element(prims.begin() + begin, prims.begin() + mid, prims.begin() + end,
                         [axis](const BuildPrim& a, const BuildPrim& b) { return a.centroid[axis] < b.centroid[axis]; });
        return mid;
    };
    int mid = begin + n / 2;
    if (!(centroids.hi[largest] - centroids.lo[largest] > 0.f)) {
        // All centroids coincide: no plane separates them; split the list in halves.
        if (n <= kMaxLeafSize) return index;
    } else if (depth >= kStackSize / 2) {
        // Pathological distributions: median splits bound the depth (and the traversal stack).
        mid = median(largest);
    } else {
        // Binned SAH on each axis: bin the centroids, sweep the kBins − 1 planes between bins.
        int best_axis = -1, best_bin = -1;
        double best_cost = kInfinity;
        auto bin_of = [&](const BuildPrim& p, int axis) {
            const float lo = centroids.lo[axis], extent = centroids.hi[axis] - lo;
            const int b = static_cast<int>(kBins * ((p.centroid[axis] - lo) / extent));
            return std::clamp(b, 0, kBins - 1);
        };
        int count[3][kBins] = {};
        Aabb bin_box[3][kBins];
        for (int i = begin; i < end; ++i)
            for (int axis = 0; axis < 3; ++axis) {
                if (!(centroids.hi[axis] - centroids.lo[axis] > 0.f)) continue;
                const int b = bin_of(prims[i], axis);
                ++count[axis][b];
                bin_box[axis][b].expand(prims[i].box);
            }
        for (int axis = 0; axis < 3; ++axis) {
            if (!(centroids.hi[axis] - centroids.lo[axis] > 0.f)) continue;
            double cost_below[kBins - 1];
            Aabb acc;
            int acc_count = 0;
            for (int b = 0; b < kBins - 1; ++b) {
                acc.expand(bin_box[axis][b]);
                acc_count += count[axis][b];
                cost_below[b] = packets(acc_count) * acc.surface_area();
            }
            acc = Aabb{};
            acc_count = 0;
            for (int b = kBins - 2; b >= 0; --b) {
                acc.expand(bin_box[axis][b + 1]);
                acc_count += count[axis][b + 1];
                const double cost = cost_below[b] + packets(acc_count) * acc.surface_area();
                if (cost < best_cost) best_cost = cost, best_axis = axis, best_bin = b;
            }
        }
        const double area = box.surface_area();
        const double split_cost = kTraversalCost + (area > 0.0 ? best_cost / area : packets(n));
        if (n <= kMaxLeafSize && double(packets(n)) <= split_cost) return index;
        const auto split = std::partition(prims.begin() + begin, prims.begin() + end, [&](const BuildPrim& p) {
            return bin_of(p, best_axis) <= best_bin;
        });
        mid = static_cast<int>(split - prims.begin());
        if (mid == begin || mid == end) mid = median(largest);
    }

    int left = -1, right = -1;
    if (n >= kParallelMin && ctx.spare_threads.fetch_sub(1) > 0) {
        // The second half on its own thread, into its own node list, appended afterwards.
        std::vector<BinaryNode> second;
        int second_root = -1;
        std::thread worker([&] { second_root = build_binary(ctx, mid, end, depth + 1, second); });
        left = build_binary(ctx, begin, mid, depth + 1, out);
        worker.join();
        ctx.spare_threads.fetch_add(1);
        const int offset = static_cast<int>(out.size());
        for (BinaryNode& node : second)
            for (int& c : node.child)
                if (c >= 0) c += offset;
        out.insert(out.end(), second.begin(), second.end());
        right = second_root + offset;
    } else {
        if (n >= kParallelMin) ctx.spare_threads.fetch_add(1);  // the failed claim
        left = build_binary(ctx, begin, mid, depth + 1, out);
        right = build_binary(ctx, mid, end, depth + 1, out);
    }
    out[index].child[0] = left;
    out[index].child[1] = right;
    return index;
}

std::uint32_t Bvh::collapse(const std::vector<BinaryNode>& tree, int node, const std::vector<BuildPrim>& prims,
                            const BvhShapes& shapes, BvhBuildStats& stats) {
    const auto index = static_cast<std::uint32_t>(m_nodes.size());
    m_nodes.emplace_back();
    for (int a = 0; a < 3; ++a) m_nodes[index].box[0][a] = Float8{} + kInfinity, m_nodes[index].box[1][a] = Float8{} - kInfinity;
    for (std::uint32_t& c : m_nodes[index].child) c = 0;
    // The children: open the largest inner node among them until there are kWidth.
    constexpr int kWidth = WideBvhNode::kWidth;
    int slots[kWidth] = {node}, n_slots = 1;
    if (tree[node].child[0] >= 0) slots[0] = tree[node].child[0], slots[1] = tree[node].child[1], n_slots = 2;
    while (n_slots < kWidth) {
        int open = -1;
        double open_area = -1.0;
        for (int k = 0; k < n_slots; ++k)
            if (tree[slots[k]].child[0] >= 0 && tree[slots[k]].box.surface_area() > open_area)
                open = k, open_area = tree[slots[k]].box.surface_area();
        if (open < 0) break;
        const BinaryNode& opened = tree[slots[open]];
        slots[open] = opened.child[0];
        slots[n_slots++] = opened.child[1];
    }
    for (int k = 0; k < n_slots; ++k) {
        const BinaryNode& c = tree[slots[k]];
        std::uint32_t ref = 0;
        if (c.child[0] >= 0) {
            ref = collapse(tree, slots[k], prims, shapes, stats) << 4;
        } else {
            // The leaf's primitives four to a packet, in leaf order.
            const auto offset = static_cast<std::uint32_t>(m_leaf.size());
            std::uint32_t count = 0;
            for (int i = c.begin; i < c.end; ++i) {
                const PrimId prim = prims[i].ref;
                const Triangle* t = prim.kind() == ShapeKind::triangle ? &shapes.of<Triangle>()[prim.index()] : nullptr;
                if (t && has_zero_float_area(t->p0, t->p1, t->p2)) continue;  // never hit
                const int lane = static_cast<int>(count++ % 4);
                if (lane == 0) m_leaf.emplace_back();
                m_leaf.back().prim[lane] = prim;
                if (t) m_leaf.back().triangles.set(lane, t->p0, t->p1, t->p2);
            }
            if (count == 0) continue;  // the slot stays empty
            ref = offset << 4 | count;
            ++stats.leaves;
        }
        WideBvhNode& wide = m_nodes[index];
        for (int a = 0; a < 3; ++a) wide.box[0][a][k] = c.box.lo[a], wide.box[1][a][k] = c.box.hi[a];
        wide.child[k] = ref;
    }
    return index;
}

BvhBuildStats Bvh::build(const BvhShapes& shapes) {
    BvhBuildStats stats;
    m_nodes.clear();
    m_leaf.clear();
    BuildContext ctx;
    std::vector<BuildPrim>& prims = ctx.prims;
    std::size_t count = shapes.instances.size();
    std::apply([&](const auto&... list) { ((count += list.size()), ...); }, shapes.arrays);
    prims.reserve(count);
    auto add = [&prims](auto list, ShapeKind kind) {
        for (std::size_t i = 0; i < list.size(); ++i) {
            const Aabb b = bounds(list[i]);
            prims.push_back({b, b.centroid(), PrimId(kind, static_cast<std::uint32_t>(i))});
        }
    };
    // In the order of ShapeTypes (the tree depends on the order of its primitives).
    std::apply([&]<typename... T>(const std::span<const T>&... list) {
        auto add_bounded = [&]<typename S>(std::span<const S> l) {
            if constexpr (BoundedShape<S>) add(l, shape_kind<S>);
        };
        (add_bounded(list), ...);
    }, shapes.arrays);
    add(shapes.instances, ShapeKind::instance);
    if (prims.empty()) return stats;
    // Leaf references keep the entry index in 28 bits (and a count in 4).
    if (prims.size() >= (std::size_t(1) << 28)) throw std::length_error("BVH: more than 2^28 primitives");
    ctx.spare_threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency())) - 1;
    std::vector<BinaryNode> tree;
    tree.reserve(prims.size() / 2);
    build_binary(ctx, 0, static_cast<int>(prims.size()), 0, tree);
    // Depth of the binary tree (a child is always stored after its parent).
    std::vector<int> depth(tree.size(), 0);
    for (std::size_t i = 0; i < tree.size(); ++i)
        for (const int c : tree[i].child)
            if (c >= 0) depth[c] = depth[i] + 1, stats.max_depth = std::max(stats.max_depth, depth[c]);
    m_leaf.reserve(prims.size() / 2);  // packets: leaves of 1 to 8 primitives, four to a packet
    m_nodes.reserve(tree.size() / 3 + 1);
    collapse(tree, 0, prims, shapes, stats);
    m_nodes.shrink_to_fit();
    m_leaf.shrink_to_fit();
    stats.nodes = static_cast<int>(m_nodes.size());
    return stats;
}

namespace {

/// Distance to a primitive other than a triangle (which needs t_max and returns barycentrics)
/// and an instance (handled apart), or infinity: one chain of kind tests per primitive test.
inline double quadric_t(const Ray& ray, const BvhShapes& shapes, PrimId p) {
    return visit_shape_kind(p.kind(), [&]<typename T>(std::type_identity<T>) -> double {
        if constexpr (std::is_same_v<T, Triangle> || !BoundedShape<T>) return kInfinity;  // never here
        else return shapes.of<T>()[p.index()].intersect_t(ray);
    });
}

/// The ray's slab constants in eight lanes (RaySlabs, splatted once per ray).
struct RayLanes {
    Float8 o[3], inv_d[3];
    /// Per axis, which of a node's bounds (0: lower, 1: upper) the ray meets first (the upper
    /// where the direction is negative), and which it leaves by.
    int near[3], far[3];
    explicit RayLanes(const Ray& ray) {
        const RaySlabs slabs(ray);
        for (int a = 0; a < 3; ++a) {
            for (int k = 0; k < WideBvhNode::kWidth; ++k) o[a][k] = slabs.o[a], inv_d[a][k] = slabs.inv_d[a];
            near[a] = slabs.near[a];
            far[a] = 1 - slabs.near[a];
        }
    }
};

/// slab_hit (aabb.h) for the eight children at once, lane by lane with the same operations
/// (so the same conservative result); returns one bit per child hit and, in t_entry, where the
/// ray enters each box.
inline unsigned hit_children(const WideBvhNode& node, const RayLanes& r, float t_max, Float8& t_entry) {
    constexpr float kGrow = 1.f + 2.f * gamma_bound(3);
    Float8 t0{}, t1 = Float8{} + t_max;
    for (int a = 0; a < 3; ++a) {
        const Float8 t_near = (node.box[r.near[a]][a] - r.o[a]) * r.inv_d[a];
        const Float8 t_far = (node.box[r.far[a]][a] - r.o[a]) * r.inv_d[a] * kGrow;
        t0 = t_near > t0 ? t_near : t0;  // a NaN never shrinks the interval
        t1 = t_far < t1 ? t_far : t1;
    }
    t_entry = t0;
    return lane_bits(t0 <= t1);
}

/// A child waiting on the traversal stack: its reference and where the ray enters its box.
struct StackEntry {
    std::uint32_t ref;
    float t;
};
constexpr std::uint32_t kCountMask = 15;

/// The lanes of a leaf packet to visit: the triangles among `valid` that the four-lane test
/// cannot reject, and every other valid primitive; one bit per lane.
inline unsigned lanes_to_test(const BvhLeafPacket& packet, unsigned valid, const ShearedRay& ray, double t_max) {
    constexpr auto kKindBits = static_cast<std::int32_t>(~0u << PrimId::kIndexBits);
    constexpr auto kTriangle = static_cast<std::int32_t>(std::uint32_t(ShapeKind::triangle) << PrimId::kIndexBits);
    const Int4 kinds = std::bit_cast<Int4>(packet.prim) & splat4(kKindBits);
    const unsigned triangles = lane_bits(kinds == splat4(kTriangle)) & valid;
    if (triangles == 0) return valid;
    return (triangle_candidates(packet.triangles, ray, t_max) & triangles) | (valid & ~triangles);
}

/// Asks for the memory of a child the walk will visit (an inner node's four lines, or a leaf's
/// first packet and a half) while the ray is tested against the node before it: a tree larger
/// than the caches spends most of its time waiting on these loads, and asked for all at once
/// they arrive together instead of one after another.
inline void prefetch_child(std::uint32_t ref, const WideBvhNode* nodes, const BvhLeafPacket* leaves) {
    const char* p = (ref & kCountMask) == 0 ? reinterpret_cast<const char*>(nodes + (ref >> 4))
                                     : reinterpret_cast<const char*>(leaves + (ref >> 4));
    for (int line = 0; line < 4; ++line) __builtin_prefetch(p + 64 * line);
}

/// The children of `node` in `mask` (hit, entered at t_entry) into `out`, nearest first,
/// their memory asked for; returns how many.
inline int nearest_first(const WideBvhNode& node, unsigned mask, const Float8& t_entry, const WideBvhNode* nodes,
                         const BvhLeafPacket* leaves, StackEntry* out) {
    int n = 0;
    for (; mask != 0; mask &= mask - 1) {
        const int k = __builtin_ctz(mask);
        prefetch_child(node.child[k], nodes, leaves);
        const StackEntry e{node.child[k], t_entry[k]};
        int j = n++;
        for (; j > 0 && out[j - 1].t > e.t; --j) out[j] = out[j - 1];
        out[j] = e;
    }
    return n;
}

/// The valid lanes of the packets of a leaf of `count` primitives, from `left` primitives on.
inline unsigned valid_lanes(int left) { return left >= 4 ? 15u : (1u << left) - 1u; }

}  // namespace

namespace {

/// The order among equally near primitives: the smaller key wins.
inline std::uint64_t tie_key(std::uint32_t instance, PrimId prim) {
    return std::uint64_t(instance) << 32 | prim.bits;
}

/// Once a hit is held, the candidate tests take its distance loosened by this factor, so that
/// a primitive at exactly that distance reaches the comparison that breaks the tie: the
/// triangle test compares its scaled distance with t_max·det before dividing, which can
/// differ from comparing t with t_max by a few rounding errors (each below 2⁻⁵³).
constexpr double kTieSlack = 1.0 + 0x1p-50;

/// The box tests' limit while the nearest hit is at t: above t by a margin for the rounding of
/// a box's entry distance (computed in float: a few errors of 2⁻²⁴ each, more where the origin
/// nearly cancels a bound), so that a box holding a primitive exactly as near is still
/// entered. It costs the rare box entered just beyond the hit.
inline float box_limit(double t) { return next_float_up(static_cast<float>(t * (1.0 + 0x1p-16))); }

}  // namespace

bool Bvh::intersect(const Ray& ray, const BvhShapes& shapes, double& t_best, BvhHit& hit, std::uint32_t instance,
                    double limit) const {
    if (m_nodes.empty()) return false;
    const RayLanes lanes(ray);
    const ShearedRay sheared(ray);
    float t_limit = box_limit(t_best);
    // The candidate tests' limit: t_best, or a little beyond it while a hit is held (ties),
    // never beyond the distance the walk began with.
    double t_test = hit.prim.valid() ? std::min(t_best * kTieSlack, limit) : t_best;
    bool found = false;
    // Whether a primitive at distance t beats the hit held (kept on equal keys: a primitive is
    // met once per walk).
    auto nearer = [&](double t, PrimId prim) {
        if (t != t_best) return t < t_best;
        return hit.prim.valid() && tie_key(instance, prim) < tie_key(hit.instance, hit.prim);
    };
    auto tighten = [&] {
        t_limit = box_limit(t_best);
        t_test = std::min(t_best * kTieSlack, limit);
        found = true;
    };
    auto take = [&](double t, PrimId prim) {
        t_best = t, hit.prim = prim, hit.instance = instance;
        tighten();
    };
    // Each node pushes at most kWidth − 1 children; the depth is below kStackSize.
    constexpr int kWidth = WideBvhNode::kWidth;
    StackEntry stack[(kWidth - 1) * kStackSize];
    int sp = 0;
    std::uint32_t ref = 0;  // the root
    while (true) {
        if ((ref & kCountMask) == 0) {
            Float8 t_entry;
            const WideBvhNode& node = m_nodes[ref >> 4];
            unsigned mask = hit_children(node, lanes, t_limit, t_entry);
            if (mask != 0) {
                // The children hit, nearest first: continue with the nearest, stack the others.
                StackEntry near[kWidth];
                const int n = nearest_first(node, mask, t_entry, m_nodes.data(), m_leaf.data(), near);
                for (int i = n - 1; i > 0; --i) stack[sp++] = near[i];
                ref = near[0].ref;
                continue;
            }
        } else {
            const BvhLeafPacket* packet = m_leaf.data() + (ref >> 4);
            for (int left = static_cast<int>(ref & kCountMask); left > 0; left -= 4, ++packet) {
                for (unsigned todo = lanes_to_test(*packet, valid_lanes(left), sheared, t_test); todo != 0;
                     todo &= todo - 1) {
                    const int k = __builtin_ctz(todo);
                    const PrimId prim = packet->prim[k];
                    if (prim.kind() == ShapeKind::triangle) {
                        const TriangleLanes& tri = packet->triangles;
                        if (const auto ti = intersect_triangle(tri.vertex(0, k), tri.vertex(1, k), tri.vertex(2, k),
                                                               sheared, t_test);
                            ti && nearer(ti->t, prim)) {
                            take(ti->t, prim);
                            hit.tri = *ti;
                        }
                    } else if (prim.kind() == ShapeKind::instance) [[unlikely]] {
                        // The instance's own tree, with the ray in its object space.
                        const MeshInstance& inst = shapes.instances[prim.index()];
                        const InstancedMesh& mesh = shapes.meshes[inst.mesh];
                        if (mesh.bvh.intersect(inst.to_object_ray(ray), mesh.shapes(), t_best, hit, prim.index(),
                                               limit))
                            tighten();
                    } else if (const double t = quadric_t(ray, shapes, prim); nearer(t, prim)) {
                        take(t, prim);
                    }
                }
            }
        }
        // The next stacked child the ray still enters before the nearest hit so far (a box
        // entered beyond t_limit would fail its test now).
        do {
            if (sp == 0) {
                if (found) hit.t = t_best;
                return found;
            }
            --sp;
        } while (stack[sp].t > t_limit);
        ref = stack[sp].ref;
    }
}

bool Bvh::occluded(const Ray& ray, const BvhShapes& shapes) const {
    if (m_nodes.empty()) return false;
    const RayLanes lanes(ray);
    const ShearedRay sheared(ray);
    const float t_limit = next_float_up(ray.t_max);
    std::uint32_t stack[(WideBvhNode::kWidth - 1) * kStackSize];
    int sp = 0;
    std::uint32_t ref = 0;
    while (true) {
        if ((ref & kCountMask) == 0) {
            Float8 t_entry;
            const WideBvhNode& node = m_nodes[ref >> 4];
            if (unsigned mask = hit_children(node, lanes, t_limit, t_entry); mask != 0) {
                // Any order will do: the first hit ends the walk (sorting them, measured, was
                // slower).
                for (unsigned m = mask; m != 0; m &= m - 1)
                    prefetch_child(node.child[__builtin_ctz(m)], m_nodes.data(), m_leaf.data());
                ref = node.child[__builtin_ctz(mask)];
                for (mask &= mask - 1; mask != 0; mask &= mask - 1) stack[sp++] = node.child[__builtin_ctz(mask)];
                continue;
            }
        } else {
            const BvhLeafPacket* packet = m_leaf.data() + (ref >> 4);
            for (int left = static_cast<int>(ref & kCountMask); left > 0; left -= 4, ++packet) {
                for (unsigned todo = lanes_to_test(*packet, valid_lanes(left), sheared, ray.t_max); todo != 0;
                     todo &= todo - 1) {
                    const int k = __builtin_ctz(todo);
                    const PrimId prim = packet->prim[k];
                    if (prim.kind() == ShapeKind::triangle) {
                        const TriangleLanes& tri = packet->triangles;
                        if (intersect_triangle(tri.vertex(0, k), tri.vertex(1, k), tri.vertex(2, k), sheared, ray.t_max))
                            return true;
                    } else if (prim.kind() == ShapeKind::instance) [[unlikely]] {
                        const MeshInstance& inst = shapes.instances[prim.index()];
                        const InstancedMesh& mesh = shapes.meshes[inst.mesh];
                        if (mesh.bvh.occluded(inst.to_object_ray(ray), mesh.shapes())) return true;
                    } else if (quadric_t(ray, shapes, prim) < ray.t_max) {
                        return true;
                    }
                }
            }
        }
        if (sp == 0) return false;
        ref = stack[--sp];
    }
}

}  // namespace spt

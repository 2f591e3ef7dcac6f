// BVH build (binned SAH) and traversal. See bvh.h.
#include "geometry/bvh.h"

#include <algorithm>

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

BvhBuildStats Bvh::build(const BvhShapes& shapes) {
    BvhBuildStats stats;
    m_nodes.clear();
    m_prims.clear();
    std::vector<BuildPrim> prims;
    prims.reserve(shapes.spheres.size() + shapes.triangles.size() + shapes.disks.size() +
                  shapes.cylinders.size() + shapes.cones.size());
    auto add = [&prims](auto list, ShapeKind kind) {
        for (std::size_t i = 0; i < list.size(); ++i) {
            const Aabb b = bounds(list[i]);
            prims.push_back({b, b.centroid(), PrimId(kind, static_cast<std::uint32_t>(i))});
        }
    };
    add(shapes.spheres, ShapeKind::sphere);
    add(shapes.triangles, ShapeKind::triangle);
    add(shapes.disks, ShapeKind::disk);
    add(shapes.cylinders, ShapeKind::cylinder);
    add(shapes.cones, ShapeKind::cone);
    if (prims.empty()) return stats;
    m_nodes.reserve(prims.size());  // about n nodes for leaves of ~2 primitives
    m_prims.reserve(prims.size());
    build_node(prims, 0, static_cast<int>(prims.size()), 0, stats);
    m_nodes.shrink_to_fit();
    stats.nodes = static_cast<int>(m_nodes.size());
    return stats;
}

int Bvh::build_node(std::vector<BuildPrim>& prims, int begin, int end, int depth, BvhBuildStats& stats) {
    const int index = static_cast<int>(m_nodes.size());
    m_nodes.emplace_back();
    Aabb box, centroids;
    for (int i = begin; i < end; ++i) {
        box.expand(prims[i].box);
        centroids.expand(prims[i].centroid);
    }
    for (int a = 0; a < 3; ++a) m_nodes[index].lo[a] = box.lo[a], m_nodes[index].hi[a] = box.hi[a];
    stats.max_depth = std::max(stats.max_depth, depth);
    const int n = end - begin;
    auto make_leaf = [&] {
        BvhNode& node = m_nodes[index];
        node.offset = static_cast<std::uint32_t>(m_prims.size());
        node.count = static_cast<std::uint16_t>(n);
        for (int i = begin; i < end; ++i) m_prims.push_back(prims[i].ref);
        ++stats.leaves;
        return index;
    };
    if (n == 1) return make_leaf();

    const int axis = centroids.largest_axis();
    const float c_lo = centroids.lo[axis], extent = centroids.hi[axis] - centroids.lo[axis];
    auto by_centroid = [axis](const BuildPrim& a, const BuildPrim& b) { return a.centroid[axis] < b.centroid[axis]; };
    int mid = begin + n / 2;
    if (!(extent > 0.f)) {
        // All centroids coincide: no plane separates them; split the list in halves.
        if (n <= kMaxLeafSize) return make_leaf();
    } else if (depth >= kStackSize / 2) {
        // Pathological distributions: median splits bound the depth (and the traversal stack).
        std::nth_element(prims.begin() + begin, prims.begin() + mid, prims.begin() + end, by_centroid);
    } else {
        // Binned SAH: bin the centroids along the axis, sweep the kBins − 1 planes between bins.
        auto bin_of = [&](const BuildPrim& p) {
            const int b = static_cast<int>(kBins * ((p.centroid[axis] - c_lo) / extent));
            return std::clamp(b, 0, kBins - 1);
        };
        int count[kBins] = {};
        Aabb bin_box[kBins];
        for (int i = begin; i < end; ++i) {
            const int b = bin_of(prims[i]);
            ++count[b];
            bin_box[b].expand(prims[i].box);
        }
        double cost_below[kBins - 1];
        Aabb acc;
        int acc_count = 0;
        for (int b = 0; b < kBins - 1; ++b) {
            acc.expand(bin_box[b]);
            acc_count += count[b];
            cost_below[b] = acc_count * acc.surface_area();
        }
        acc = Aabb{};
        acc_count = 0;
        int best = -1;
        double best_cost = kInfinity;
        for (int b = kBins - 2; b >= 0; --b) {
            acc.expand(bin_box[b + 1]);
            acc_count += count[b + 1];
            const double cost = cost_below[b] + acc_count * acc.surface_area();
            if (cost < best_cost) best_cost = cost, best = b;
        }
        // Relative costs (pbrt-v4): traversal 1/2, one unit per primitive test.
        const double area = box.surface_area();
        best_cost = 0.5 + (area > 0.0 ? best_cost / area : n);
        if (n <= kMaxLeafSize && double(n) <= best_cost) return make_leaf();
        const auto split = std::partition(prims.begin() + begin, prims.begin() + end,
                                          [&](const BuildPrim& p) { return bin_of(p) <= best; });
        mid = static_cast<int>(split - prims.begin());
        if (mid == begin || mid == end) {
            mid = begin + n / 2;
            std::nth_element(prims.begin() + begin, prims.begin() + mid, prims.begin() + end, by_centroid);
        }
    }
    build_node(prims, begin, mid, depth + 1, stats);
    const int second = build_node(prims, mid, end, depth + 1, stats);
    m_nodes[index].offset = static_cast<std::uint32_t>(second);
    m_nodes[index].count = 0;
    m_nodes[index].axis = static_cast<std::uint8_t>(axis);
    return index;
}

namespace {

/// Distance to a primitive other than a triangle (which needs t_max and returns barycentrics),
/// or infinity: one switch on the kind per primitive test.
inline double quadric_t(const Ray& ray, const BvhShapes& shapes, PrimId p) {
    switch (p.kind()) {
        case ShapeKind::sphere: return shapes.spheres[p.index()].intersect_t(ray);
        case ShapeKind::disk: return shapes.disks[p.index()].intersect_t(ray);
        case ShapeKind::cylinder: return shapes.cylinders[p.index()].intersect_t(ray);
        case ShapeKind::cone: return shapes.cones[p.index()].intersect_t(ray);
        default: return kInfinity;  // planes are never in the tree
    }
}

}  // namespace

bool Bvh::intersect(const Ray& ray, const BvhShapes& shapes, double& t_best, BvhHit& hit) const {
    if (m_nodes.empty()) return false;
    const RaySlabs slabs(ray);
    // The box test's limit in float, never below the double t_best.
    float t_limit = next_float_up(static_cast<float>(t_best));
    std::uint32_t stack[kStackSize];
    int sp = 0;
    std::uint32_t current = 0;
    bool found = false;
    while (true) {
        const BvhNode& node = m_nodes[current];
        if (node.hit_by(slabs, t_limit)) {
            if (node.count == 0) {
                // Visit the child on the near side of the split first.
                if (slabs.near[node.axis]) stack[sp++] = current + 1, current = node.offset;
                else stack[sp++] = node.offset, current = current + 1;
                continue;
            }
            for (std::uint32_t i = node.offset, e = node.offset + node.count; i < e; ++i) {
                const PrimId p = m_prims[i];
                if (p.kind() == ShapeKind::triangle) {
                    if (const auto ti = shapes.triangles[p.index()].intersect(ray, t_best)) {
                        t_best = ti->t, hit.prim = p, hit.tri = *ti, found = true;
                        t_limit = next_float_up(static_cast<float>(t_best));
                    }
                } else if (const double t = quadric_t(ray, shapes, p); t < t_best) {
                    t_best = t, hit.prim = p, found = true;
                    t_limit = next_float_up(static_cast<float>(t_best));
                }
            }
        }
        if (sp == 0) break;
        current = stack[--sp];
    }
    if (found) hit.t = t_best;
    return found;
}

bool Bvh::occluded(const Ray& ray, const BvhShapes& shapes) const {
    if (m_nodes.empty()) return false;
    const RaySlabs slabs(ray);
    const float t_limit = next_float_up(ray.t_max);
    std::uint32_t stack[kStackSize];
    int sp = 0;
    std::uint32_t current = 0;
    while (true) {
        const BvhNode& node = m_nodes[current];
        if (node.hit_by(slabs, t_limit)) {
            if (node.count == 0) {
                if (slabs.near[node.axis]) stack[sp++] = current + 1, current = node.offset;
                else stack[sp++] = node.offset, current = current + 1;
                continue;
            }
            for (std::uint32_t i = node.offset, e = node.offset + node.count; i < e; ++i) {
                const PrimId p = m_prims[i];
                if (p.kind() == ShapeKind::triangle ? shapes.triangles[p.index()].intersect(ray, ray.t_max).has_value()
                                                    : quadric_t(ray, shapes, p) < ray.t_max)
                    return true;  // any hit will do
            }
        }
        if (sp == 0) break;
        current = stack[--sp];
    }
    return false;
}

}  // namespace spt

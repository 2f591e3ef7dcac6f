#include "render/light_bvh.h"

#include <algorithm>
#include <array>
#include <numeric>
#include <limits>
#include <stdexcept>

namespace spt {

namespace {

constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;
constexpr int kBuckets = 12;
/// Beyond this depth the build splits at the median: the path bits (64) then always suffice.
constexpr int kSahDepth = 36;

/// The orientation measure of a cone (Conty Estévez & Kulla 2018, eq. 1): the solid angle
/// its normals emit into, weighted by cosine, which the split cost multiplies with power and
/// area.
float orientation_measure(const LightBounds& b) {
    const float theta_o = std::acos(std::clamp(b.cos_theta_o, -1.f, 1.f));
    const float theta_e = std::acos(std::clamp(b.cos_theta_e, -1.f, 1.f));
    const float theta_w = std::min(theta_o + theta_e, kPi);
    const float sin_o = std::sin(theta_o);
    return 2.f * kPi * (1.f - b.cos_theta_o) +
           0.5f * kPi * (2.f * theta_w * sin_o - std::cos(theta_o - 2.f * theta_w) - 2.f * theta_o * sin_o + b.cos_theta_o);
}

/// Split cost of a side: power × orientation × surface area, the box's elongation along the
/// split axis penalised (regularisation K_r of the paper).
double split_cost(const LightBounds& b, const Aabb& parent, int axis) {
    if (!(b.phi > 0.f)) return 0.0;
    const Vec3 d = parent.hi - parent.lo;
    const float kr = d[axis] > 0.f ? max_component(d) / d[axis] : 1.f;
    return double(kr) * b.phi * orientation_measure(b) * std::max(b.bounds.surface_area(), 1e-30);
}

}  // namespace

void LightBvh::build(const std::vector<Light>& lights, const std::vector<float>& weights,
                     const std::vector<int>& first_triangle) {
    m_nodes.clear();
    m_entries.clear();
    m_infinite.clear();
    m_light_entry.assign(lights.size(), -1);
    m_light_first_triangle.assign(lights.size(), -1);
    m_infinite_slot.assign(lights.size(), -1);
    std::vector<LightBounds> leaf_bounds;
    std::vector<int> planes;
    for (std::size_t i = 0; i < lights.size(); ++i) {
        if (!(i < weights.size() && weights[i] > 0.f)) continue;
        const Light& light = lights[i];
        const int index = static_cast<int>(i);
        if (light_type(light) == LightType::infinite) {
            m_infinite.push_back(index);
            continue;
        }
        if (std::holds_alternative<PlaneLight>(light)) {
            planes.push_back(index);
            continue;
        }
        const auto* mesh = std::get_if<TriangleMeshLight>(&light);
        if (mesh && mesh->triangles.size() > 1 && i < first_triangle.size() && first_triangle[i] >= 0) {
            m_light_entry[i] = static_cast<int>(m_entries.size());
            m_light_first_triangle[i] = first_triangle[i];
            const float phi = weights[i];
            for (std::size_t k = 0; k < mesh->triangles.size(); ++k) {
                const float area = TriangleMeshLight::triangle_area(mesh->triangles[k]);
                const bool emits = area > 0.f;
                m_entries.push_back({index, static_cast<int>(k), emits ? mesh->total_area / area : 0.f, 0});
                leaf_bounds.push_back(emits ? triangle_light_bounds(*mesh, k, phi) : LightBounds{});
            }
            continue;
        }
        const std::optional<LightBounds> b = light_bounds(light, weights[i]);
        if (!b) continue;
        m_light_entry[i] = static_cast<int>(m_entries.size());
        m_entries.push_back({index, -1, 1.f, 0});
        leaf_bounds.push_back(*b);
    }
    m_environments = m_infinite.size();
    m_infinite.insert(m_infinite.end(), planes.begin(), planes.end());
    for (std::size_t k = 0; k < m_infinite.size(); ++k) m_infinite_slot[static_cast<std::size_t>(m_infinite[k])] = static_cast<int>(k);
    if (m_entries.empty()) return;
    if (m_entries.size() >= (std::size_t(1) << 26)) throw std::length_error("too many emitters for the light BVH");
    std::vector<int> order(m_entries.size());
    std::iota(order.begin(), order.end(), 0);
    m_nodes.reserve(2 * m_entries.size());
    build_node(order, leaf_bounds, 0, order.size(), 0, 0);
}

int LightBvh::build_node(std::vector<int>& order, std::vector<LightBounds>& leaf_bounds, std::size_t begin,
                         std::size_t end, int depth, std::uint64_t path) {
    const int node = static_cast<int>(m_nodes.size());
    m_nodes.emplace_back();
    if (end - begin == 1) {
        const int e = order[begin];
        m_nodes[static_cast<std::size_t>(node)].bounds = leaf_bounds[static_cast<std::size_t>(e)];
        m_nodes[static_cast<std::size_t>(node)].entry = e;
        m_entries[static_cast<std::size_t>(e)].path = path;
        return node;
    }
    LightBounds all;
    Aabb centroids;
    for (std::size_t i = begin; i < end; ++i) {
        const LightBounds& b = leaf_bounds[static_cast<std::size_t>(order[i])];
        all = light_bounds_union(all, b);
        centroids.expand(b.bounds.empty() ? Vec3{} : b.bounds.centroid());
    }
    auto centroid_of = [&](int e) {
        const LightBounds& b = leaf_bounds[static_cast<std::size_t>(e)];
        return b.bounds.empty() ? Vec3{} : b.bounds.centroid();
    };

    // The split of least cost over kBuckets buckets of the centroids along each axis.
    int best_axis = -1, best_bucket = -1;
    double best_cost = std::numeric_limits<double>::infinity();
    if (depth < kSahDepth) {
        for (int axis = 0; axis < 3; ++axis) {
            const float lo = centroids.lo[axis], extent = centroids.hi[axis] - lo;
            if (!(extent > 0.f)) continue;
            std::array<LightBounds, kBuckets> buckets{};
            for (std::size_t i = begin; i < end; ++i) {
                const int e = order[i];
                const int k = std::min(kBuckets - 1, static_cast<int>(kBuckets * ((centroid_of(e)[axis] - lo) / extent)));
                buckets[static_cast<std::size_t>(k)] =
                    light_bounds_union(buckets[static_cast<std::size_t>(k)], leaf_bounds[static_cast<std::size_t>(e)]);
            }
            for (int split = 0; split < kBuckets - 1; ++split) {
                LightBounds below, above;
                for (int k = 0; k <= split; ++k) below = light_bounds_union(below, buckets[static_cast<std::size_t>(k)]);
                for (int k = split + 1; k < kBuckets; ++k)
                    above = light_bounds_union(above, buckets[static_cast<std::size_t>(k)]);
                const double cost = split_cost(below, all.bounds, axis) + split_cost(above, all.bounds, axis);
                if (cost < best_cost) best_cost = cost, best_axis = axis, best_bucket = split;
            }
        }
    }
    std::size_t mid = begin;
    if (best_axis >= 0) {
        const float lo = centroids.lo[best_axis], extent = centroids.hi[best_axis] - lo;
        mid = static_cast<std::size_t>(
            std::partition(order.begin() + static_cast<std::ptrdiff_t>(begin), order.begin() + static_cast<std::ptrdiff_t>(end),
                           [&](int e) {
                               const int k = std::min(
                                   kBuckets - 1, static_cast<int>(kBuckets * ((centroid_of(e)[best_axis] - lo) / extent)));
                               return k <= best_bucket;
                           }) -
            order.begin());
    }
    if (mid == begin || mid == end) {
        // No useful split (every centroid in one place, or deep): halves along the widest axis.
        const int axis = centroids.largest_axis();
        mid = (begin + end) / 2;
        std::nth_element(order.begin() + static_cast<std::ptrdiff_t>(begin), order.begin() + static_cast<std::ptrdiff_t>(mid),
                         order.begin() + static_cast<std::ptrdiff_t>(end),
                         [&](int a, int b) { return centroid_of(a)[axis] < centroid_of(b)[axis]; });
    }
    build_node(order, leaf_bounds, begin, mid, depth + 1, path);
    const int second = build_node(order, leaf_bounds, mid, end, depth + 1, path | (std::uint64_t(1) << depth));
    m_nodes[static_cast<std::size_t>(node)].bounds = all;
    m_nodes[static_cast<std::size_t>(node)].child = second;
    return node;
}

namespace {
/// The share of the tree against the infinite lights (1 when there are none).
inline float tree_share(std::size_t n_infinite) {
    return n_infinite == 0 ? 1.f : 1.f - static_cast<float>(n_infinite) / static_cast<float>(n_infinite + 1);
}
}  // namespace

int LightBvh::sample(const LightSampleContext& ctx, float u, bool with_planes, float& prob) const {
    const std::size_t n_inf = infinite_count(with_planes);
    prob = 0.f;
    if (n_inf > 0) {
        const float share = infinite_pmf(with_planes);
        const float all_infinite = m_nodes.empty() ? 1.f : static_cast<float>(n_inf) / static_cast<float>(n_inf + 1);
        if (u < all_infinite) {
            const std::size_t k = std::min(static_cast<std::size_t>(u / share), n_inf - 1);
            prob = share;
            return -2 - static_cast<int>(k);
        }
        u = std::min((u - all_infinite) / (1.f - all_infinite), kOneMinusEpsilon);
    }
    if (m_nodes.empty()) return -1;
    float p = tree_share(n_inf);
    std::size_t node = 0;
    while (m_nodes[node].entry < 0) {
        const std::size_t c0 = node + 1, c1 = static_cast<std::size_t>(m_nodes[node].child);
        const float i0 = light_importance(m_nodes[c0].bounds, ctx.p, ctx.ns);
        const float i1 = light_importance(m_nodes[c1].bounds, ctx.p, ctx.ns);
        if (!(i0 > 0.f) && !(i1 > 0.f)) return -1;
        const float total = i0 + i1;
        const float p0 = i0 / total;
        if (u < p0) {
            p *= p0;
            u = std::min(u / p0, kOneMinusEpsilon);
            node = c0;
        } else {
            const float p1 = i1 / total;
            p *= p1;
            u = std::min((u - p0) / p1, kOneMinusEpsilon);
            node = c1;
        }
    }
    prob = p;
    return m_nodes[node].entry;
}

float LightBvh::entry_pmf(const LightSampleContext& ctx, int e, bool with_planes) const {
    if (e < 0 || static_cast<std::size_t>(e) >= m_entries.size()) return 0.f;
    const std::uint64_t path = m_entries[static_cast<std::size_t>(e)].path;
    float p = tree_share(infinite_count(with_planes));
    std::size_t node = 0;
    for (int depth = 0; m_nodes[node].entry < 0; ++depth) {
        const std::size_t c0 = node + 1, c1 = static_cast<std::size_t>(m_nodes[node].child);
        const float i0 = light_importance(m_nodes[c0].bounds, ctx.p, ctx.ns);
        const float i1 = light_importance(m_nodes[c1].bounds, ctx.p, ctx.ns);
        if (!(i0 > 0.f) && !(i1 > 0.f)) return 0.f;
        const float total = i0 + i1;
        if (((path >> depth) & 1u) == 0) {
            p *= i0 / total;
            node = c0;
        } else {
            p *= i1 / total;
            node = c1;
        }
    }
    return p;
}

float LightBvh::light_choice(const LightSampleContext& ctx, int light, int scene_triangle, bool with_planes) const {
    if (light < 0 || static_cast<std::size_t>(light) >= m_light_entry.size()) return 0.f;
    const std::size_t l = static_cast<std::size_t>(light);
    if (const int slot = m_infinite_slot[l]; slot >= 0)
        return static_cast<std::size_t>(slot) < infinite_count(with_planes) ? infinite_pmf(with_planes) : 0.f;
    int e = m_light_entry[l];
    if (e < 0) return 0.f;
    if (m_light_first_triangle[l] >= 0) {
        const int k = scene_triangle - m_light_first_triangle[l];
        if (scene_triangle < 0 || k < 0 || m_entries.size() <= static_cast<std::size_t>(e + k) ||
            m_entries[static_cast<std::size_t>(e + k)].light != light)
            return 0.f;
        e += k;
    }
    return entry_pmf(ctx, e, with_planes) * m_entries[static_cast<std::size_t>(e)].area_ratio;
}

}  // namespace spt

#include "render/guiding/directional_tree.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "core/math.h"

namespace spt {

SquarePoint direction_to_square(const Vec3& w) {
    const double z = std::clamp(double(w.z), -1.0, 1.0);
    double phi = std::atan2(w.y, w.x);
    if (phi < 0) phi += 2 * 3.14159265358979323846;
    const double v = phi / (2 * 3.14159265358979323846);
    return {std::clamp((z + 1) * 0.5, 0.0, 1.0), v < 1.0 ? v : 0.0};
}

Vec3 square_to_direction(const SquarePoint& s) {
    const double z = 2 * s.u - 1;
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    const double phi = 2 * 3.14159265358979323846 * s.v;
    return {float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)};
}

DirectionalTree::DirectionalTree(int channels, int depth) : m_channels(channels), m_nodes(1) {
    // Breadth first: every node of a level before the next.
    std::uint32_t level_begin = 0;
    for (int d = 0; d < depth; ++d) {
        const auto level_end = static_cast<std::uint32_t>(m_nodes.size());
        for (std::uint32_t n = level_begin; n < level_end; ++n) subdivide(n);
        level_begin = level_end;
    }
    m_units.assign(m_nodes.size() * static_cast<std::size_t>(channels), 0);
    m_records.assign(m_nodes.size() * static_cast<std::size_t>(channels), 0);
    m_energy.assign(m_nodes.size() * static_cast<std::size_t>(channels), 0.f);
}

void DirectionalTree::subdivide(std::uint32_t node) {
    m_nodes[node].first_child = static_cast<std::uint32_t>(m_nodes.size());
    m_nodes.resize(m_nodes.size() + 4);
}

namespace {

/// The quadrant of a node's square that holds s, and s in that quadrant's coordinates.
int descend(SquarePoint& s) {
    const int x = s.u >= 0.5 ? 1 : 0, y = s.v >= 0.5 ? 1 : 0;
    s.u = s.u * 2 - x;
    s.v = s.v * 2 - y;
    return x + 2 * y;
}

}  // namespace

void DirectionalTree::record(const SquarePoint& point, int channel, std::uint64_t units) {
    SquarePoint s = point;
    std::uint32_t n = 0;
    while (!m_nodes[n].leaf()) n = m_nodes[n].first_child + static_cast<std::uint32_t>(descend(s));
    const std::size_t i = static_cast<std::size_t>(n) * m_channels + channel;
    std::atomic_ref<std::uint64_t>(m_units[i]).fetch_add(units, std::memory_order_relaxed);
    std::atomic_ref<std::uint64_t>(m_records[i]).fetch_add(1, std::memory_order_relaxed);
}

void DirectionalTree::gather(double unit) {
    // Children come after their parents, so a backward sweep sees every child before its parent.
    std::vector<double> sums(m_units.size(), 0.0);
    for (std::size_t n = m_nodes.size(); n-- > 0;) {
        for (int c = 0; c < m_channels; ++c) {
            double& sum = sums[n * m_channels + c];
            if (m_nodes[n].leaf()) {
                sum = double(m_units[n * m_channels + c]) * unit;
            } else {
                std::uint64_t& records = m_records[n * m_channels + c];
                records = 0;
                for (std::uint32_t k = 0; k < 4; ++k) {
                    sum += sums[(m_nodes[n].first_child + k) * m_channels + c];
                    records += m_records[(m_nodes[n].first_child + k) * m_channels + c];
                }
            }
        }
    }
    for (std::size_t i = 0; i < sums.size(); ++i) m_energy[i] = static_cast<float>(sums[i]);

    // Each node's cone: the centre direction of its region and the largest angle from it to
    // the region's corners and edge midpoints; a region wider than a quarter turn in φ gets
    // the whole sphere (its farthest point may lie inside an edge).
    m_cones.assign(m_nodes.size(), Cone{});
    struct Region {
        std::uint32_t node;
        double u0, v0, size;
    };
    std::vector<Region> stack{{0, 0.0, 0.0, 1.0}};
    while (!stack.empty()) {
        const Region r = stack.back();
        stack.pop_back();
        Cone& cone = m_cones[r.node];
        cone.axis = square_to_direction({r.u0 + r.size / 2, r.v0 + r.size / 2});
        cone.cos_radius = -1.f, cone.sin_radius = 0.f;
        if (r.size <= 0.25) {
            float cos_r = 1.f;
            for (int j = 0; j <= 2; ++j)
                for (int i = 0; i <= 2; ++i)
                    if (i != 1 || j != 1) {
                        const SquarePoint corner{r.u0 + r.size * i / 2, r.v0 + r.size * j / 2};
                        cos_r = std::min(cos_r, dot(cone.axis, square_to_direction(corner)));
                    }
            cone.cos_radius = std::clamp(cos_r, -1.f, 1.f);
            cone.sin_radius = std::sqrt(std::max(0.f, 1.f - cone.cos_radius * cone.cos_radius));
        }
        if (!m_nodes[r.node].leaf())
            for (std::uint32_t k = 0; k < 4; ++k)
                stack.push_back({m_nodes[r.node].first_child + k, r.u0 + (k & 1) * r.size / 2,
                                 r.v0 + (k >> 1) * r.size / 2, r.size / 2});
    }
}

float DirectionalTree::weight(std::uint32_t node, int c, const Vec3* side) const {
    const float e = energy(node, c);
    if (!side) return e;
    const Cone& cone = m_cones[node];
    // cos(θ − r) = cos θ cos r + sin θ sin r, the cosine at the cone's edge nearest the normal,
    // bounded above with sin θ ≤ 1 (no square root: this runs four times per level of every
    // descent).
    const float cos_t = dot(cone.axis, *side);
    if (cos_t >= cone.cos_radius) return e;  // the normal lies within the cone
    return e * std::clamp(cos_t * cone.cos_radius + cone.sin_radius, 0.f, 1.f);
}

bool DirectionalTree::usable(int c, const Vec3* side) const {
    if (!(m_energy[static_cast<std::size_t>(c)] > 0.f)) return false;
    if (!side || m_nodes[0].leaf()) return true;
    float total = 0.f;
    for (std::uint32_t k = 0; k < 4; ++k) total += weight(m_nodes[0].first_child + k, c, side);
    return total > 0.f;
}

DirectionalTree DirectionalTree::refined(double rho) const {
    DirectionalTree out(m_channels, 0);
    std::array<double, 16> total{};
    for (int c = 0; c < std::min(m_channels, 16); ++c) total[c] = energy(0, c);
    // The share of the tree's energy in a node of this tree, the channels averaged.
    auto share = [&](std::uint32_t node) {
        double s = 0;
        int counted = 0;
        for (int c = 0; c < m_channels; ++c)
            if (total[c] > 0) s += energy(node, c) / total[c], ++counted;
        return counted > 0 ? s / counted : 0.0;
    };
    // Non-zero records of a node of this tree, per channel.
    auto records = [&](std::uint32_t node) {
        double r = 0;
        for (int c = 0; c < m_channels; ++c) r += double(m_records[node * static_cast<std::size_t>(m_channels) + c]);
        return r / m_channels;
    };
    struct Item {
        std::uint32_t out_node;
        std::int64_t in_node;  ///< the node of this tree covering the same region, or −1 (below a leaf)
        double share;          ///< its share of the energy
        double records;        ///< its non-zero records per channel
        int depth;
    };
    std::vector<Item> stack{{0, 0, 1.0, records(0), 0}};
    while (!stack.empty()) {
        const Item item = stack.back();
        stack.pop_back();
        if (item.depth >= kMaxDepth || !(item.share > rho) || !(item.records > kMinRecordsToSplit)) continue;
        out.subdivide(item.out_node);
        const std::uint32_t first_out = out.m_nodes[item.out_node].first_child;
        for (std::uint32_t k = 0; k < 4; ++k) {
            std::int64_t in_child = -1;
            double child_share = item.share / 4, child_records = item.records / 4;
            if (item.in_node >= 0 && !m_nodes[static_cast<std::size_t>(item.in_node)].leaf()) {
                in_child = m_nodes[static_cast<std::size_t>(item.in_node)].first_child + k;
                child_share = share(static_cast<std::uint32_t>(in_child));
                child_records = records(static_cast<std::uint32_t>(in_child));
            }
            stack.push_back({first_out + k, in_child, child_share, child_records, item.depth + 1});
        }
    }
    out.m_units.assign(out.m_nodes.size() * static_cast<std::size_t>(m_channels), 0);
    out.m_records.assign(out.m_nodes.size() * static_cast<std::size_t>(m_channels), 0);
    out.m_energy.assign(out.m_nodes.size() * static_cast<std::size_t>(m_channels), 0.f);
    return out;
}

std::array<double, 4> DirectionalTree::child_weights(std::uint32_t first, int c, const Vec3* side) const {
    return {weight(first, c, side), weight(first + 1, c, side), weight(first + 2, c, side),
            weight(first + 3, c, side)};
}

SquarePoint DirectionalTree::sample(int c, double u1, double u2, float& pdf, const Vec3* side) const {
    double scale = 1;  // product of 4·(child weight / children's total weight) along the way
    SquarePoint origin;
    double size = 1;
    std::uint32_t n = 0;
    while (!m_nodes[n].leaf()) {
        const std::uint32_t first = m_nodes[n].first_child;
        const std::array<double, 4> e = child_weights(first, c, side);
        const double total = e[0] + e[1] + e[2] + e[3];
        // Children that all weigh 0 (a region wholly below `side`, reached because the parent's
        // cone bound is looser than theirs): the node is sampled as a leaf; pdf() stops there too.
        if (!(total > 0)) break;
        // The half in u, then the quadrant in v within it.
        const double left = e[0] + e[2];
        int x = 0;
        if (u1 * total < left) {
            u1 = u1 * total / left;
        } else {
            x = 1;
            u1 = (u1 * total - left) / (total - left);
        }
        const double column = e[x] + e[x + 2];
        int y = 0;
        if (u2 * column < e[x]) {
            u2 = u2 * column / e[x];
        } else {
            y = 1;
            u2 = (u2 * column - e[x]) / (column - e[x]);
        }
        u1 = std::min(u1, 0x1.fffffffffffffp-1);
        u2 = std::min(u2, 0x1.fffffffffffffp-1);
        const int q = x + 2 * y;
        scale *= 4 * e[q] / total;
        size *= 0.5;
        origin.u += x * size;
        origin.v += y * size;
        n = first + static_cast<std::uint32_t>(q);
    }
    pdf = static_cast<float>(scale);
    return {origin.u + u1 * size, origin.v + u2 * size};
}

float DirectionalTree::pdf(int c, const SquarePoint& point, const Vec3* side) const {
    if (!usable(c, side)) return 0.f;
    SquarePoint s = point;
    double scale = 1;
    std::uint32_t n = 0;
    while (!m_nodes[n].leaf()) {
        const std::uint32_t first = m_nodes[n].first_child;
        const std::array<double, 4> e = child_weights(first, c, side);
        const double total = e[0] + e[1] + e[2] + e[3];
        if (!(total > 0)) break;  // sampled as a leaf (see sample())
        const int q = descend(s);
        scale *= 4 * e[q] / total;
        if (scale == 0) return 0.f;
        n = first + static_cast<std::uint32_t>(q);
    }
    return static_cast<float>(scale);
}

bool DirectionalTree::operator==(const DirectionalTree& other) const {
    if (m_channels != other.m_channels || m_nodes.size() != other.m_nodes.size()) return false;
    for (std::size_t i = 0; i < m_nodes.size(); ++i)
        if (m_nodes[i].first_child != other.m_nodes[i].first_child) return false;
    return m_units == other.m_units && m_energy == other.m_energy;
}

}  // namespace spt

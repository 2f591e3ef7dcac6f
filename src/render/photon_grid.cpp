#include "render/photon_grid.h"

#include <bit>
#include <cmath>

namespace spt {

std::uint32_t PhotonGrid::cell_bucket(const Vec3& p) const {
    return bucket(cell(p.x * m_inv_cell), cell(p.y * m_inv_cell), cell(p.z * m_inv_cell));
}

void PhotonGrid::build(const std::vector<Vec3>& points, float radius) {
    m_radius = radius;
    m_radius2 = radius * radius;
    m_inv_cell = 0.5f / radius;
    const std::size_t buckets = std::bit_ceil(std::max<std::size_t>(points.size(), 1));
    m_mask = buckets - 1;
    m_begin.assign(buckets + 1, 0);
    std::vector<std::uint32_t> of(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) ++m_begin[(of[i] = cell_bucket(points[i])) + 1];
    for (std::size_t b = 0; b < buckets; ++b) m_begin[b + 1] += m_begin[b];
    m_points.resize(points.size());
    m_index.resize(points.size());
    std::vector<std::uint32_t> next(m_begin.begin(), m_begin.end() - 1);
    for (std::size_t i = 0; i < points.size(); ++i) {
        const std::uint32_t j = next[of[i]]++;
        m_points[j] = points[i];
        m_index[j] = static_cast<std::uint32_t>(i);
    }
}

}  // namespace spt

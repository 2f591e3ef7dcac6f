// A hashed uniform grid over points for fixed-radius searches (vertex merging's photons).
// Cells are 2r wide, so the ball of radius r around any point overlaps at most 2×2×2 cells
// (a third along an axis only where rounding could put a point in its neighbour);
// cells are hashed into a table about as large as the point count and the points are sorted
// by bucket (counting sort), so a query reads a few contiguous runs. Two of the eight cells
// may share a bucket: those buckets are visited once.
#pragma once
#include <cmath>
#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/vec3.h"

namespace spt {

class PhotonGrid {
public:
    /// Indexes `points` (copied) for queries of radius `radius` > 0.
    void build(const std::vector<Vec3>& points, float radius);

    /// Calls visit(j, distance²) for every point within the radius of p, j being its slot in
    /// the grid's own order (order()[j] is its index in the built vector).
    template <class Visit>
    void query(const Vec3& p, Visit&& visit) const {
        if (m_points.empty()) return;
        // The cells overlapping [p − r, p + r] on each axis, widened by a little more than the
        // rounding of the cell coordinates, so that no point within r whose own (rounded) cell
        // lies just past the ends is missed: usually 1 or 2 cells per axis, rarely 3.
        std::int64_t lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            const float from = (p[a] - m_radius) * m_inv_cell, to = (p[a] + m_radius) * m_inv_cell;
            // (At most half a cell, so at most three cells per axis.)
            const float slack = std::min(0.5f, 1e-4f + 0x1p-20f * std::max(std::fabs(from), std::fabs(to)));
            lo[a] = cell(from - slack);
            // Past ~2^24 cells from the origin adjacent floats are more than a cell apart and
            // the range could span any number of cells: there the grid keeps three (a query
            // that far out, e.g. on the horizon of an infinite plane, is beyond resolving r).
            hi[a] = std::min(cell(to + slack), lo[a] + 2);
        }
        std::uint32_t buckets[27];
        int n = 0;
        for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
            for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
                for (std::int64_t x = lo[0]; x <= hi[0]; ++x) {
                    const std::uint32_t b = bucket(x, y, z);
                    bool seen = false;
                    for (int k = 0; k < n; ++k) seen |= buckets[k] == b;
                    if (!seen) buckets[n++] = b;
                }
        for (int k = 0; k < n; ++k) {
            for (std::uint32_t j = m_begin[buckets[k]]; j < m_begin[buckets[k] + 1]; ++j) {
                const Vec3 d = m_points[j] - p;
                const float d2 = dot(d, d);
                if (d2 <= m_radius2) visit(j, d2);
            }
        }
    }

    std::size_t size() const { return m_points.size(); }
    /// order()[j]: index in the built vector of the point in slot j.
    const std::vector<std::uint32_t>& order() const { return m_index; }
    float radius() const { return m_radius; }

    /// Integer cell coordinate of x (in cell units), saturated so that the conversion is
    /// defined for any float (huge coordinates, ±inf, NaN) and x + 1 cannot overflow.
    static std::int64_t cell(float x) {
        constexpr float kLimit = 0x1p62f;
        if (!(x > -kLimit)) return -static_cast<std::int64_t>(kLimit);
        if (!(x < kLimit)) return static_cast<std::int64_t>(kLimit);
        return static_cast<std::int64_t>(std::floor(x));
    }

private:
    std::uint32_t bucket(std::int64_t x, std::int64_t y, std::int64_t z) const {
        const auto h = static_cast<std::uint64_t>(x) * 73856093u ^ static_cast<std::uint64_t>(y) * 19349663u ^
                       static_cast<std::uint64_t>(z) * 83492791u;
        return static_cast<std::uint32_t>(h & m_mask);
    }
    std::uint32_t cell_bucket(const Vec3& p) const;

    float m_radius = 0.f, m_radius2 = 0.f, m_inv_cell = 0.f;
    std::uint64_t m_mask = 0;
    std::vector<std::uint32_t> m_begin;  ///< bucket b holds sorted entries [m_begin[b], m_begin[b+1])
    std::vector<Vec3> m_points;          ///< points sorted by bucket
    std::vector<std::uint32_t> m_index;  ///< their indices in the built vector
};

}  // namespace spt

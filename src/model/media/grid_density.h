// Heterogeneous medium from a density grid (io/density_grid_reader.h reads the file):
// nx·ny·nz values at the cell centres of an axis-aligned box, interpolated trilinearly;
// zero outside the box.
#pragma once
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "geometry/ray.h"

namespace spt {

struct DensityGrid {
    int nx = 0, ny = 0, nz = 0;
    std::vector<float> values;  ///< x fastest, then y, then z; every value finite and ≥ 0
    float at(int x, int y, int z) const {
        return values[(static_cast<std::size_t>(z) * ny + y) * nx + x];
    }
};

struct GridDensity {
    static constexpr bool kUniform = false;
    std::shared_ptr<const DensityGrid> grid;  ///< shared: media are copied with the scene
    Vec3 lo, hi;                              ///< the box the grid fills (lo < hi per axis)
    float scale = 1.f;                        ///< multiplies every value
    float max_value = 0.f;                    ///< scale × the largest value (the majorant)

    float density(const Vec3& p) const {
        const DensityGrid& g = *grid;
        // Continuous cell coordinates: value (i, j, k) sits at the centre of its cell.
        const float fx = (p.x - lo.x) / (hi.x - lo.x) * g.nx - 0.5f;
        const float fy = (p.y - lo.y) / (hi.y - lo.y) * g.ny - 0.5f;
        const float fz = (p.z - lo.z) / (hi.z - lo.z) * g.nz - 0.5f;
        if (!(fx > -1.f && fy > -1.f && fz > -1.f && fx < g.nx && fy < g.ny && fz < g.nz)) return 0.f;
        auto split = [](float f, int n, int& i0, int& i1, float& w) {
            const float c = std::clamp(f, 0.f, static_cast<float>(n - 1));
            i0 = std::min(static_cast<int>(c), n - 1);
            i1 = std::min(i0 + 1, n - 1);
            w = c - static_cast<float>(i0);
        };
        int x0, x1, y0, y1, z0, z1;
        float wx, wy, wz;
        split(fx, g.nx, x0, x1, wx), split(fy, g.ny, y0, y1, wy), split(fz, g.nz, z0, z1, wz);
        auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
        const float c00 = lerp(g.at(x0, y0, z0), g.at(x1, y0, z0), wx);
        const float c10 = lerp(g.at(x0, y1, z0), g.at(x1, y1, z0), wx);
        const float c01 = lerp(g.at(x0, y0, z1), g.at(x1, y0, z1), wx);
        const float c11 = lerp(g.at(x0, y1, z1), g.at(x1, y1, z1), wx);
        return scale * lerp(lerp(c00, c10, wy), lerp(c01, c11, wy), wz);
    }
    /// A global majorant: the grid's largest value.
    float max_density(const Ray&, float, float) const { return max_value; }

    /// Narrows [t0, t1] to the box (slab test); false if the ray misses it there.
    bool clip(const Ray& ray, float& t0, float& t1) const {
        for (int a = 0; a < 3; ++a) {
            const float inv = 1.f / ray.d[a];
            float ta = (lo[a] - ray.o[a]) * inv, tb = (hi[a] - ray.o[a]) * inv;
            if (ta > tb) std::swap(ta, tb);
            if (std::isnan(ta) || std::isnan(tb)) {  // parallel to the slab, on its plane
                if (ray.o[a] < lo[a] || ray.o[a] > hi[a]) return false;
                continue;
            }
            t0 = std::max(t0, ta);
            t1 = std::min(t1, tb);
        }
        return t0 < t1;
    }
};

}  // namespace spt

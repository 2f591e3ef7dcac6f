// The spheres of a small scene (no BVH) in groups of four, for the float rejection test of
// Sphere::intersect_t made on four spheres at once. Most rays miss every sphere; only the
// spheres that pass (rarely more than one) get the exact double-precision test.
#pragma once
#include <bit>
#include <cstdint>
#include <vector>

#include "core/simd.h"
#include "geometry/sphere.h"

namespace spt {

class SphereLanes {
public:
    void build(const std::vector<Sphere>& spheres) {
        m_groups.clear();
        for (std::size_t i = 0; i < spheres.size(); ++i) {
            if (i % 4 == 0) m_groups.push_back(Group{});
            Group& g = m_groups.back();
            const int k = static_cast<int>(i % 4);
            const Sphere& s = spheres[i];
            g.cx[k] = s.center.x, g.cy[k] = s.center.y, g.cz[k] = s.center.z;
            g.radius[k] = s.radius;
            g.valid[k] = -1;
        }
    }

    /// Calls visit(i) for each sphere i that the float test cannot reject, in index order.
    template <typename Visit>
    [[gnu::always_inline]] void candidates(const Ray& ray, Visit&& visit) const {
        const Float4 ox = splat4(ray.o.x), oy = splat4(ray.o.y), oz = splat4(ray.o.z);
        const Float4 dx = splat4(ray.d.x), dy = splat4(ray.d.y), dz = splat4(ray.d.z);
        int base = 0;
        for (const Group& g : m_groups) {
            const Int4 pass = g.valid & ~sphere_surely_missed(g.cx - ox, g.cy - oy, g.cz - oz, dx, dy, dz, g.radius);
            // Most rays pass no sphere: one test of the whole mask (as two 64-bit halves).
            using Long2 = std::int64_t __attribute__((vector_size(16)));
            const Long2 halves = std::bit_cast<Long2>(pass);
            if ((halves[0] | halves[1]) == 0) {
                base += 4;
                continue;
            }
            unsigned bits = (pass[0] & 1u) | (pass[1] & 2u) | (pass[2] & 4u) | (pass[3] & 8u);
            while (bits != 0) {
                visit(base + __builtin_ctz(bits));
                bits &= bits - 1;
            }
            base += 4;
        }
    }

private:
    struct Group {
        Float4 cx{}, cy{}, cz{}, radius{};
        Int4 valid{};  ///< −1 for real spheres, 0 for padding
    };
    std::vector<Group> m_groups;
};

}  // namespace spt

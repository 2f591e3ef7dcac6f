// Four triangles side by side (structure of arrays) and the rejection part of the watertight
// test (triangle.h) made on all four at once: the BVH's leaves hold their triangles this way,
// and only the triangles that survive it (rarely more than one per leaf) get the one-triangle
// test, which then decides the hit exactly as it does without the lanes.
#pragma once
#include <cstdint>

#include "core/simd.h"
#include "geometry/triangle.h"

namespace spt {

/// The vertices of four triangles: v[vertex][axis], lane k = triangle k.
struct TriangleLanes {
    Float4 v[3][3]{};

    void set(int lane, const Vec3& p0, const Vec3& p1, const Vec3& p2) {
        const Vec3* p[3] = {&p0, &p1, &p2};
        for (int i = 0; i < 3; ++i)
            for (int a = 0; a < 3; ++a) v[i][a][lane] = (*p[i])[a];
    }
    /// Vertex i (0–2) of the triangle in `lane`.
    Vec3 vertex(int i, int lane) const { return {v[i][0][lane], v[i][1][lane], v[i][2][lane]}; }
};

/// One bit per lane (lane k → bit k), clear for each triangle that
/// intersect_triangle(its vertices, r, t_max) certainly rejects: its edge functions have
/// mixed signs or sum to 0, or its scaled distance lies outside (0, t_max). A set bit says
/// nothing yet (the t > δt test and the hit itself are intersect_triangle's).
///
/// No error margin is needed because there is no new rounding: each lane repeats
/// intersect_triangle's operations one for one (the float shear, the edge functions from
/// exact products in double, the determinant and the scaled distance, in the same order), and
/// vector lanes round exactly as scalar operations do (IEEE, FMA contraction off: see
/// CMakeLists.txt). So every value compared here is bit for bit the value intersect_triangle
/// compares, on any instruction set, and a triangle is rejected here only where it is
/// rejected there. Double lanes, not a float pre-test: the edge functions cost 3 conversions
/// and 2 products each in double, fewer operations than a float product with its error bound.
/// A smaller t_max rejects a superset (t_max·det rounds monotonically), so lanes computed
/// with an earlier, larger nearest distance stay valid candidates as the walk shrinks it.
[[gnu::always_inline]] inline unsigned triangle_candidates(const TriangleLanes& tri, const ShearedRay& r,
                                                           double t_max) {
    if (!r.valid) return 0;
    const int kx = r.kx, ky = r.ky, kz = r.kz;
    const Float4 ox = splat4(r.o[kx]), oy = splat4(r.o[ky]), oz = splat4(r.o[kz]);
    const Float4 sx = splat4(r.sx), sy = splat4(r.sy);
    // The shear of each vertex (triangle.h: q = p − o, z = q_kz, x = q_kx + sx·z, y = ...).
    Double4 x[3], y[3], z[3];
    for (int i = 0; i < 3; ++i) {
        const Float4 zf = tri.v[i][kz] - oz;
        const Float4 xf = (tri.v[i][kx] - ox) + sx * zf;
        const Float4 yf = (tri.v[i][ky] - oy) + sy * zf;
        x[i] = __builtin_convertvector(xf, Double4);
        y[i] = __builtin_convertvector(yf, Double4);
        z[i] = __builtin_convertvector(zf, Double4);
    }
    const Double4 e0 = x[1] * y[2] - y[1] * x[2];
    const Double4 e1 = x[2] * y[0] - y[2] * x[0];
    const Double4 e2 = x[0] * y[1] - y[0] * x[1];
    const Double4 zero{};
    const Long4 mixed = ((e0 < zero) | (e1 < zero) | (e2 < zero)) & ((e0 > zero) | (e1 > zero) | (e2 > zero));
    const Double4 det = e0 + e1 + e2;
    const double sz = r.sz;
    const Double4 t_scaled = e0 * (sz * z[0]) + e1 * (sz * z[1]) + e2 * (sz * z[2]);
    const Double4 limit = t_max * det;
    const Long4 outside = ((det < zero) & ((t_scaled >= zero) | (t_scaled < limit))) |
                          ((det > zero) & ((t_scaled <= zero) | (t_scaled > limit)));
    const Long4 keep = ~(mixed | (det == zero) | outside);
    return unsigned(keep[0] & 1) | unsigned(keep[1] & 2) | unsigned(keep[2] & 4) | unsigned(keep[3] & 8);
}

}  // namespace spt

// A mesh placed in the scene by an affine map (instancing). The mesh's triangles and their
// BVH are stored once, in the mesh's own (object) space (InstancedMesh); an instance holds only
// its maps. Rays are taken into object space (o and d mapped, so t is the same parameter) and
// hits brought back with error bounds that include the map's rounding.
#pragma once
#include <algorithm>
#include <cmath>

#include "geometry/aabb.h"
#include "geometry/dvec3.h"

namespace spt {

/// x ↦ A·x + b in double: a[i][0..2] is row i of A, a[i][3] is b_i.
struct AffineMap {
    double a[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};

    DVec3 point(const DVec3& p) const {
        return {a[0][0] * p.x + a[0][1] * p.y + a[0][2] * p.z + a[0][3],
                a[1][0] * p.x + a[1][1] * p.y + a[1][2] * p.z + a[1][3],
                a[2][0] * p.x + a[2][1] * p.y + a[2][2] * p.z + a[2][3]};
    }
    DVec3 vector(const DVec3& v) const {
        return {a[0][0] * v.x + a[0][1] * v.y + a[0][2] * v.z, a[1][0] * v.x + a[1][1] * v.y + a[1][2] * v.z,
                a[2][0] * v.x + a[2][1] * v.y + a[2][2] * v.z};
    }
    /// |A|·e for e ≥ 0: how far an error box e is carried by the map, per axis.
    DVec3 abs_vector(const DVec3& e) const {
        auto row = [&](int i) { return std::fabs(a[i][0]) * e.x + std::fabs(a[i][1]) * e.y + std::fabs(a[i][2]) * e.z; };
        return {row(0), row(1), row(2)};
    }
    /// Cofactor matrix of A applied to n: a normal carried by the map (det(A)·A⁻ᵀ·n), which is
    /// the cross product of mapped edges, so mirroring maps turn it as they turn the winding.
    DVec3 cofactor_vector(const DVec3& n) const {
        const auto& m = a;
        const double c[3][3] = {{m[1][1] * m[2][2] - m[1][2] * m[2][1], m[1][2] * m[2][0] - m[1][0] * m[2][2],
                                 m[1][0] * m[2][1] - m[1][1] * m[2][0]},
                                {m[0][2] * m[2][1] - m[0][1] * m[2][2], m[0][0] * m[2][2] - m[0][2] * m[2][0],
                                 m[0][1] * m[2][0] - m[0][0] * m[2][1]},
                                {m[0][1] * m[1][2] - m[0][2] * m[1][1], m[0][2] * m[1][0] - m[0][0] * m[1][2],
                                 m[0][0] * m[1][1] - m[0][1] * m[1][0]}};
        return {c[0][0] * n.x + c[0][1] * n.y + c[0][2] * n.z, c[1][0] * n.x + c[1][1] * n.y + c[1][2] * n.z,
                c[2][0] * n.x + c[2][1] * n.y + c[2][2] * n.z};
    }
    double determinant() const {
        return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
               a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    }
    /// The inverse map (A must be invertible: det ≠ 0).
    AffineMap inverse() const {
        AffineMap r;
        const double inv_det = 1.0 / determinant();
        // A⁻¹ = cofactor(A)ᵀ / det.
        for (int j = 0; j < 3; ++j) {
            DVec3 e{j == 0 ? 1.0 : 0.0, j == 1 ? 1.0 : 0.0, j == 2 ? 1.0 : 0.0};
            const DVec3 c = cofactor_vector(e);  // column j of cofactor(A) = row j of its transpose
            r.a[j][0] = c.x * inv_det, r.a[j][1] = c.y * inv_det, r.a[j][2] = c.z * inv_det;
        }
        const DVec3 t = r.vector(DVec3(a[0][3], a[1][3], a[2][3]));
        r.a[0][3] = -t.x, r.a[1][3] = -t.y, r.a[2][3] = -t.z;
        return r;
    }
    /// Largest |A·x + b| component for x in the box (bounds the map's arithmetic error).
    double magnitude(const Aabb& box) const {
        const DVec3 e = abs_vector(DVec3(std::max(std::fabs(box.lo.x), std::fabs(box.hi.x)),
                                         std::max(std::fabs(box.lo.y), std::fabs(box.hi.y)),
                                         std::max(std::fabs(box.lo.z), std::fabs(box.hi.z))));
        return std::max({e.x + std::fabs(a[0][3]), e.y + std::fabs(a[1][3]), e.z + std::fabs(a[2][3])});
    }
};

/// One placement of an InstancedMesh (Scene::instanced_meshes[mesh]).
struct MeshInstance {
    int mesh = 0;
    AffineMap to_world, to_object;  ///< to_object is to_world's inverse
    Aabb world_bounds;              ///< set by Scene::finalize (instance_bounds)

    MeshInstance() = default;
    MeshInstance(int mesh_index, const AffineMap& map) : mesh(mesh_index), to_world(map), to_object(map.inverse()) {}

    /// The ray in object space: o and d mapped (d is not renormalised), so a hit at t there is
    /// the hit at t here.
    Ray to_object_ray(const Ray& r) const {
        return {to_object.point(DVec3(r.o)).to_float(), to_object.vector(DVec3(r.d)).to_float(), r.t_max};
    }
};

/// World box of an instance whose mesh has object-space box `b`: the eight corners mapped in
/// double, padded for the rays' mapping into object space (rounded to float there: a relative
/// error of a few 2⁻²⁴ of the coordinates) and rounded outwards.
inline Aabb instance_bounds(const AffineMap& to_world, const Aabb& b) {
    DVec3 lo{kInfinity, kInfinity, kInfinity}, hi{-kInfinity, -kInfinity, -kInfinity};
    for (int k = 0; k < 8; ++k) {
        const DVec3 c = to_world.point(DVec3(k & 1 ? b.hi.x : b.lo.x, k & 2 ? b.hi.y : b.lo.y, k & 4 ? b.hi.z : b.lo.z));
        lo = {std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z)};
        hi = {std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z)};
    }
    const double pad = 1e-5 * std::max(max_abs(lo), max_abs(hi));
    Aabb out;
    out.lo = {next_float_down(static_cast<float>(lo.x - pad)), next_float_down(static_cast<float>(lo.y - pad)),
              next_float_down(static_cast<float>(lo.z - pad))};
    out.hi = {next_float_up(static_cast<float>(hi.x + pad)), next_float_up(static_cast<float>(hi.y + pad)),
              next_float_up(static_cast<float>(hi.z + pad))};
    return out;
}

inline Aabb bounds(const MeshInstance& i) { return i.world_bounds; }

}  // namespace spt

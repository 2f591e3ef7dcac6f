// The closed set of shapes and the one contract every type in it fulfils. Adding a type is
// one header in this folder (the shape and its ShapeArray, see shape_array.h), its kind in
// ShapeKind (ray.h) and one entry in ShapeTypes; the scene's arrays, the medium table, the
// primitive ids, the BVH, motion, validation and the loops over every shape follow from the
// list (docs/DESIGN.md, "How to add a shape").
//
// Conventions: rays have unit directions; distances are doubles (the tests run in double and
// only the winner's hit record is built); points and normals of records are floats with a
// conservative per-axis error bound p_err (rays spawned from them cannot re-hit the surface).
//
///  intersect_t(ray)              distance to the nearest hit with t > 0 (beyond the bound of
///                                t's own rounding), or kInfinity: the candidate comparison
///                                of the nearest-hit search. Occlusion is intersect_t(ray) <
///                                ray.t_max, so the two always agree. (Triangle: intersect
///                                (ray, t_max) keeps its barycentrics for the record.)
///  make_hit(ray, t)              the hit record at t from intersect_t: the point reprojected
///                                onto the surface and its error bound, the unit geometric
///                                normal n (outward for closed shapes), the shading normal ns
///                                (n itself; meshes with vertex normals replace it), the
///                                material and light. (Triangle: make_hit(intersection).)
///  uv(p, u, v)                   surface coordinates of a point on the surface, in [0, 1]
///                                for bounded shapes (textures read them).
///  dpdu(p)                       the direction of growing u at p (not normalised; tangent to
///                                the surface): anisotropic BSDFs' tangent. (Triangle: the
///                                scene's vertex (u, v) decide it, Scene::surface_tangent.)
///  bounds(shape)                 a box containing every point the shape can be hit at,
///                                rounded outwards (the BVH builds on it); not for Plane,
///                                which is infinite and tested beside the BVH.
///  area(), sample_area(u1, u2)   the surface area and a point drawn uniformly by area (its
///                                density 1 / area()), with its error bound and unit normal
///                                (area lights sample their shapes through it); not for Plane.
///  kName, defect()               the type's name for messages, and what makes a shape of it
///                                unrenderable (non-finite or non-positive values), or nullptr:
///                                Scene::finalize checks every shape, static or moving, by it.
///
/// Every type with bounds can move (kCanMove, moving_shape.h; the loader refuses "motion" on a
/// plane with a message). Instances place meshes only (InstancedMesh holds triangles;
/// "instances" is a key of meshes alone, an unknown key elsewhere).
#pragma once
#include <array>
#include <cstddef>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "geometry/cone.h"
#include "geometry/cylinder.h"
#include "geometry/disk.h"
#include "geometry/plane.h"
#include "geometry/ray.h"
#include "geometry/shape_array.h"
#include "geometry/sphere.h"
#include "geometry/triangle.h"

namespace spt {

/// The set, in the order of ShapeKind (a primitive's kind is its type's index here).
using ShapeTypes = std::tuple<Sphere, Plane, Triangle, Disk, Cylinder, Cone>;
inline constexpr std::size_t kShapeTypeCount = std::tuple_size_v<ShapeTypes>;

namespace detail {
template <typename T, typename Tuple>
struct TypeIndex;
template <typename T, typename... Ts>
struct TypeIndex<T, std::tuple<Ts...>> {
    static constexpr std::size_t value = [] {
        constexpr bool same[] = {std::is_same_v<T, Ts>...};
        for (std::size_t i = 0; i < sizeof...(Ts); ++i)
            if (same[i]) return i;
        return sizeof...(Ts);
    }();
};
}  // namespace detail

/// The kind of primitive ids of shape type T.
template <typename T>
inline constexpr ShapeKind shape_kind = static_cast<ShapeKind>(detail::TypeIndex<T, ShapeTypes>::value);

static_assert(shape_kind<Sphere> == ShapeKind::sphere && shape_kind<Plane> == ShapeKind::plane &&
                  shape_kind<Triangle> == ShapeKind::triangle && shape_kind<Disk> == ShapeKind::disk &&
                  shape_kind<Cylinder> == ShapeKind::cylinder && shape_kind<Cone> == ShapeKind::cone,
              "ShapeKind names the types of ShapeTypes in its order");
static_assert(static_cast<std::size_t>(ShapeKind::moving) == kShapeTypeCount,
              "ShapeKind: the shape types first, then moving and instance");

/// Calls f(std::type_identity<T>{}) for the shape type T whose kind is k (a chain of tests,
/// inlined); k must be a shape type's kind (not moving or instance).
template <std::size_t I = 0, typename F>
[[gnu::always_inline]] inline decltype(auto) visit_shape_kind(ShapeKind k, F&& f) {
    if constexpr (I + 1 < kShapeTypeCount) {
        if (static_cast<std::size_t>(k) != I) return visit_shape_kind<I + 1>(k, std::forward<F>(f));
    }
    return f(std::type_identity<std::tuple_element_t<I, ShapeTypes>>{});
}

/// One array per shape type (each named by its ShapeArray: spheres, planes, ...).
template <typename Tuple>
struct ShapeArraysOf;
template <typename... Ts>
struct ShapeArraysOf<std::tuple<Ts...>> : ShapeArray<Ts>... {
    template <typename T>
    std::vector<T>& shapes_of() { return ShapeArray<T>::array(); }
    template <typename T>
    const std::vector<T>& shapes_of() const { return ShapeArray<T>::array(); }
    /// Calls f with each array, in the order of ShapeTypes.
    template <typename F>
    void for_each_array(F&& f) { (f(ShapeArray<Ts>::array()), ...); }
    template <typename F>
    void for_each_array(F&& f) const { (f(ShapeArray<Ts>::array()), ...); }
    /// How many shapes of each type, in the order of ShapeTypes (indexed by ShapeKind).
    std::array<std::size_t, sizeof...(Ts)> shape_counts() const { return {ShapeArray<Ts>::array().size()...}; }
};
using ShapeArrays = ShapeArraysOf<ShapeTypes>;
/// A count per shape type (ShapeArrays::shape_counts), e.g. where the shapes a loader just
/// added begin.
using ShapeCounts = std::array<std::size_t, kShapeTypeCount>;

}  // namespace spt

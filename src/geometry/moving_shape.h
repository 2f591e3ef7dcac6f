// A shape that moves while the shutter is open: its shapes at rest (as the scene file gives
// them, in one array per type of the set) and their rigid motion. A ray at time t is taken
// into the shape's rest frame (the inverse of the motion at t), meets the shapes there, and
// the hit comes back to the world. Nothing of this runs for static scenes (Scene::intersect
// tests it only when the scene has moving shapes).
#pragma once
#include <vector>

#include "geometry/aabb.h"
#include "geometry/bvh.h"
#include "geometry/motion.h"
#include "geometry/shape.h"

namespace spt {

/// Shape types that can move: those with bounds (the swept box and the rest-frame BVH are
/// built on them). An infinite plane cannot.
template <typename T>
inline constexpr bool kCanMove = BoundedShape<T>;

/// A shape's box in float: a sphere's and a triangle's exact extents, other shapes' bounds()
/// (a motion's default pivot is the centre of the moving shapes' box).
inline Aabb extent_box(const Sphere& s) {
    const Vec3 r(s.radius, s.radius, s.radius);
    return Aabb{s.center - r, s.center + r};
}
inline Aabb extent_box(const Triangle& t) {
    Aabb b;
    b.expand(t.p0), b.expand(t.p1), b.expand(t.p2);
    return b;
}
template <BoundedShape T>
Aabb extent_box(const T& shape) {
    return bounds(shape);
}

struct MovingShape : ShapeArrays {
    RigidMotion motion;
    Aabb swept;  ///< world box over every time (finish())
    Bvh bvh;     ///< over the rest shapes, past a handful of them (finish())

    /// Computes the swept box and, past a handful of primitives, the rest-frame BVH.
    void finish() {
        Aabb rest;
        std::size_t count = 0;
        for_each_array([&](const auto& shapes) {
            for (const auto& shape : shapes)
                if constexpr (kCanMove<std::decay_t<decltype(shape)>>) rest.expand(extent_box(shape));
            count += shapes.size();
        });
        swept = motion.swept_bounds(rest);
        if (count > 8) bvh.build(shapes());
    }
    BvhShapes shapes() const { return BvhShapes::of_all(*this); }
};

}  // namespace spt

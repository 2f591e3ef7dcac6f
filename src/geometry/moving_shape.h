// A shape that moves while the shutter is open: its spheres and triangles at rest (as the
// scene file gives them) and their rigid motion. A ray at time t is taken into the shape's
// rest frame (the inverse of the motion at t), meets the shapes there, and the hit comes
// back to the world. Nothing of this runs for static scenes (Scene::intersect tests it
// only when the scene has moving shapes).
#pragma once
#include <vector>

#include "geometry/aabb.h"
#include "geometry/bvh.h"
#include "geometry/motion.h"
#include "geometry/sphere.h"
#include "geometry/triangle.h"

namespace spt {

struct MovingShape {
    RigidMotion motion;
    std::vector<Sphere> spheres;      ///< at rest
    std::vector<Triangle> triangles;  ///< at rest (a quad's two, a mesh's all)
    Aabb swept;                       ///< world box over every time (finish())
    Bvh bvh;                          ///< over the rest shapes, for meshes (finish())

    /// Computes the swept box and, past a handful of primitives, the rest-frame BVH.
    void finish() {
        Aabb rest;
        for (const Sphere& s : spheres) {
            const Vec3 r(s.radius, s.radius, s.radius);
            rest.expand(Aabb{s.center - r, s.center + r});
        }
        for (const Triangle& t : triangles) rest.expand(t.p0), rest.expand(t.p1), rest.expand(t.p2);
        swept = motion.swept_bounds(rest);
        if (spheres.size() + triangles.size() > 8) bvh.build(shapes());
    }
    BvhShapes shapes() const { return {spheres, triangles, {}, {}, {}}; }
};

}  // namespace spt

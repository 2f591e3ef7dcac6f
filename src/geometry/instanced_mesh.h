// A mesh stored once for all its instances (MeshInstance): triangles in object space and
// their BVH.
#pragma once
#include <vector>

#include "geometry/bvh.h"

namespace spt {

struct InstancedMesh {
    std::vector<Triangle> triangles;  ///< object space; light −1 (instances do not emit)
    Bvh bvh;                          ///< over `triangles`, built by Scene::finalize
    Aabb bounds;                      ///< object-space box of the triangles

    BvhShapes shapes() const { return BvhShapes::of_arrays(triangles); }
};

}  // namespace spt

// The scene's array of one shape type. Each shape's header specialises ShapeArray with the
// array's name (Scene::spheres, Scene::triangles, ...) and array() returning it; ShapeArrays
// (shape.h) holds one for every type of the set, so the scene's per-type arrays, the moving
// shapes' rest arrays and every loop over them follow the one type list.
#pragma once
#include <vector>

namespace spt {

template <typename T>
struct ShapeArray;

}  // namespace spt

// The reference for intersection tests: every sphere and triangle tested in turn, the nearest
// hit distance kept (ray.t_max when nothing is hit).
#pragma once
#include <algorithm>
#include <vector>

#include "geometry/ray.h"
#include "geometry/sphere.h"
#include "geometry/triangle.h"

namespace spt::test {

inline double nearest_t_by_loop(const std::vector<Sphere>& spheres, const std::vector<Triangle>& triangles,
                                const Ray& ray) {
    double t_best = ray.t_max;
    for (const Sphere& s : spheres) t_best = std::min(t_best, s.intersect_t(ray));
    for (const Triangle& tri : triangles)
        if (auto ti = tri.intersect(ray, t_best)) t_best = ti->t;
    return t_best;
}

}  // namespace spt::test

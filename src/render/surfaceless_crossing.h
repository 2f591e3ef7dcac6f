// Rays through shapes without a surface (a medium's boundary, scenes/README.md `media`): the
// one step every walk through media takes at such a shape, the path tracer's
// (volumetric_path.cpp) and bdpt's (bdpt_media.cpp) alike.
#pragma once
#include "scene/scene.h"

namespace spt {

/// Rays cross at most this many surfaceless shapes in a row (a guard against a ray caught
/// between coincident interfaces).
inline constexpr int kMaxSurfacelessCrossings = 256;

/// Continues `ray` straight on past `hit`, a hit on a shape without a surface: `ray` becomes
/// the ray from just behind the shape with what was left of its t_max (kInfinity stays
/// kInfinity). Returns the medium behind the shape (MediumInterface::after).
inline int cross_surfaceless(const Scene& scene, const Hit& hit, Ray& ray) {
    const int medium = scene.medium_interface(hit.prim).after(hit.n, ray.d);
    const float t_left = ray.t_max - hit.t;
    ray = spawn_ray(hit, ray.d);
    ray.t_max = t_left;
    return medium;
}

}  // namespace spt

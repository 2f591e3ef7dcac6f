// A renderable scene: camera, shapes in flat typed arrays, materials by index, lights.
#pragma once
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "geometry/plane.h"
#include "geometry/sphere.h"
#include "render/camera.h"
#include "render/material.h"
#include "render/point_light.h"
#include "scene/effects.h"

namespace spt {

/// A scene that cannot be rendered as described (bad values, inconsistent materials).
struct SceneError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct Scene {
    std::string name;
    CameraSpec camera;
    int width = 512, height = 512, spp = 64;  ///< defaults the command line may override

    std::vector<Material> materials;
    std::vector<Sphere> spheres;
    std::vector<Plane> planes;
    std::vector<PointLight> point_lights;
    Spectrum background;  ///< radiance of rays that escape (zero: black)

    Effects effects;  ///< filled by finalize()

    /// Adds a material and returns its index.
    int add_material(Material m);
    /// Checks every value (throws SceneError naming the culprit) and analyses the effects.
    void finalize();

    /// Nearest surface along the ray, t in (0, ray.t_max). Candidates are compared by distance
    /// only; the hit record (the costly part) is built once, for the winner.
    std::optional<Hit> intersect(const Ray& ray) const {
        double t_best = ray.t_max;
        const Plane* best_plane = nullptr;
        const Sphere* best_sphere = nullptr;
        for (const Plane& plane : planes)
            if (const double t = plane.intersect_t(ray); t < t_best) t_best = t, best_plane = &plane;
        for (const Sphere& sphere : spheres)
            if (const double t = sphere.intersect_t(ray); t < t_best) t_best = t, best_sphere = &sphere;
        if (best_sphere) return best_sphere->make_hit(ray, t_best);
        if (best_plane) return best_plane->make_hit(ray, t_best);
        return std::nullopt;
    }

    /// True if anything blocks the ray before ray.t_max (shadow rays; glass is opaque to them).
    bool occluded(const Ray& ray) const {
        for (const Sphere& sphere : spheres)
            if (sphere.intersect_t(ray) < ray.t_max) return true;
        for (const Plane& plane : planes)
            if (plane.intersect_t(ray) < ray.t_max) return true;
        return false;
    }
};

}  // namespace spt

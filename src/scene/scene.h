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

    /// Nearest surface along the ray, t in (0, ray.t_max).
    std::optional<Hit> intersect(const Ray& ray) const {
        std::optional<Hit> best;
        Ray r = ray;
        for (const Plane& plane : planes)
            if (auto h = plane.intersect(r)) best = h, r.t_max = h->t;
        for (const Sphere& sphere : spheres)
            if (auto h = sphere.intersect(r)) best = h, r.t_max = h->t;
        return best;
    }

    /// True if anything blocks the ray before ray.t_max (shadow rays; glass is opaque to them).
    bool occluded(const Ray& ray) const {
        for (const Sphere& sphere : spheres)
            if (sphere.intersect(ray)) return true;
        for (const Plane& plane : planes)
            if (plane.intersect(ray)) return true;
        return false;
    }
};

}  // namespace spt

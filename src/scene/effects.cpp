#include "scene/effects.h"

namespace spt {

std::string Effects::describe() const {
    std::string s;
    auto add = [&](bool on, const char* name) {
        if (!on) return;
        if (!s.empty()) s += ", ";
        s += name;
    };
    add(point_lights, "point lights (shadow rays)");
    add(emissive_surfaces, "emissive surfaces");
    add(background, "environment light");
    add(mirror, "mirror reflection");
    add(transmission, "dielectric transmission");
    add(dispersion, "dispersion");
    add(shading_normals, "smooth shading (vertex normals)");
    add(depth_of_field, "depth of field");
    add(motion_blur, "motion blur");
    add(media, "participating media");
    add(textures, "textures");
    add(fluorescence, "fluorescence");
    add(caustic_spheres, "caustics through glass spheres or off reflecting ones");
    return s.empty() ? "none" : s;
}

}  // namespace spt

// The set of effects a scene calls for, found once at load time. The integrator runs only
// what is in the set and the program prints it.
#pragma once
#include <string>

namespace spt {

struct Effects {
    bool point_lights = false;       ///< next-event estimation with shadow rays
    bool emissive_surfaces = false;  ///< emission found by paths that hit surfaces
    bool background = false;         ///< constant environment for escaping rays
    bool mirror = false;             ///< perfect specular reflection
    bool transmission = false;       ///< Fresnel dielectrics
    bool dispersion = false;         ///< wavelength-dependent index: hero set splits
    bool shading_normals = false;    ///< meshes with vertex normals: smooth shading
    bool depth_of_field = false;     ///< thin-lens camera: rays start on the aperture
    bool motion_blur = false;        ///< something moves while the shutter is open
    bool media = false;              ///< participating media: the volumetric path tracer
    bool textures = false;           ///< a material or emitter bound to a texture
    /// Fluorescent materials: the path integrator's loop that re-emits at other wavelengths
    /// (model/fluorescence.h), spectra evaluated exactly (bins stop at 380 nm).
    bool fluorescence = false;
    /// Smooth glass spheres or spheres with a delta reflection lobe, and emitting spheres or
    /// quads, without media: the path tracer's specular next-event estimation through the
    /// spheres (render/caustic_nee.h) or off them (render/reflection_nee.h) applies.
    bool caustic_spheres = false;

    std::string describe() const;
};

}  // namespace spt

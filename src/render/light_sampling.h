// Light sources as the origins of light subpaths (bidirectional path tracing).
//
// What can start a light subpath:
//   - point lights: a delta position, directions uniform over the sphere;
//   - spot lights: a delta position, directions uniform over the cone (its falloff in the
//     emitted intensity);
//   - emitting shapes (spheres, quads, triangles, meshes, disks, cylinders, cones: one light
//     per shape): a point uniform over the area, then a side (both sides emit) with
//     probability 1/2 and a cosine-weighted direction on it;
//   - the constant environment (pbrt's infinite lights): a direction d uniform over the
//     sphere, then a point uniform on a disk of radius R perpendicular to d, one radius
//     upstream of the centre of the scene's bounding sphere (centre c, radius R); the ray
//     leaves the disk along d.
// A light is chosen with probability proportional to its power (mean over 380–780 nm of
// 4π·I for points, the cone's share of it for spots, 2π·A·Le for two-sided area emitters, 4π·πR²·Le for the environment: the
// flux through the disk from every direction). A camera path that hits an emitter finds its
// light through the hit (Hit::light), and with it the density of that point.
//
// The environment as a vertex lies at infinity: it is measured by direction. Its density is
// P(choose it)/(4π) in solid angle (environment_pdf), and the first vertex x of its subpath
// has the area density (1/(πR²))·|cos θx| (environment_position_pdf times the cosine at x),
// with no 1/r² (pbrt-v3's InfiniteLightDensity and PdfLight).
//
// The bounding sphere covers the finite shapes, the camera and the point lights (so that what
// the camera sees around itself, on planes too, is reached by light subpaths: efficiency, not
// correctness); infinite planes are unbounded and cannot be covered. This stays unbiased
// everywhere:
//   - a ray from the disk stands for the light arriving from infinity along its line. Only an
//     unbounded plane can cross the line upstream of the disk (outside the sphere); then that
//     light never arrives, and sample() flags the origin `blocked` (no subpath from it);
//   - a point that no ray from the disk can reach (a far part of a plane outside the
//     cylinder the disk sweeps) has environment_position_pdf 0: the strategies that would
//     need the environment's subpath to land there have density 0, and the MIS weights
//     leave them out (bdpt.cpp). The other strategies (the camera path escaping, the
//     connection towards a sampled direction) cover such points on their own.
// The direction of the environment's origin is valid whether or not the disk ray is
// blocked: bidirectional s = 1 connections use it (a direction uniform over the sphere).
//
// What cannot start a light subpath: emitting infinite planes (a ceiling light) have no
// finite area to sample. Like pbrt's lights that cannot be sampled, they are reached only by
// camera subpaths that hit them (the s = 0 strategies); their light-origin density is 0, and
// the MIS weight of such a path is 1 since no other strategy can produce it.
//
// A scene without an environment (background zero) has no environment entry and pays nothing.
#pragma once
#include <optional>
#include <vector>

#include "model/lights/area_emission.h"
#include "model/lights/light_sample.h"
#include "scene/scene.h"
#include "spectral/sampled.h"

namespace spt {

class LightSampler {
public:
    explicit LightSampler(const Scene& scene);

    bool empty() const { return m_choice.empty(); }
    bool has_environment() const { return m_environment_choice > 0.f; }

    /// Samples a light ∝ power, a point on it and a direction (a moving point light where it
    /// is at `time`); nullopt when there is none.
    std::optional<LightOrigin> sample(const SampledWavelengths& lambda, float u_light, float u1,
                                      float u2, float u_side, float u3, float u4, float time = 0.f) const;

    /// Area density (choice included) with which sample() would produce this emitting hit
    /// point; 0 for emitters that cannot be sampled (infinite planes) and non-emitters.
    float origin_pdf(const Hit& hit) const;

    /// Solid-angle density (choice included) with which sample() produces the environment in
    /// a given direction; 0 when the scene has no environment.
    float environment_pdf() const { return m_environment_choice * (0.25f * kInvPi); }

    /// Planar density of the disk point through which a ray from the environment travelling
    /// along `d` (unit) reaches `p`: 1/(πR²), or 0 when no ray leaving the disk passes
    /// through p (p outside the cylinder the disk sweeps, or upstream of the disk).
    float environment_position_pdf(const Vec3& p, const Vec3& d) const;

    /// Radius of the bounding sphere of the finite shapes, the camera and the point lights.
    float scene_radius() const { return m_radius; }

private:
    const Scene& m_scene;
    LightDistribution m_choice;  ///< over Scene::lights: those that can start a subpath, by power
    Vec3 m_center;                ///< bounding sphere of the environment's disk
    float m_radius = 0.f;
    float m_environment_choice = 0.f;  ///< its choice probability (0: no environment)
};

}  // namespace spt

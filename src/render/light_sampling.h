// Light sources as the origins of light subpaths (bidirectional path tracing): one light
// chosen with probability proportional to its power among those that can start a subpath,
// then its own sample_le (model/lights/light.h's contract; each light's header says how it
// emits). A camera path that hits an emitter finds its light through the hit (Hit::light),
// and with it the density of that point.
//
// An infinite light as a vertex lies at infinity and is measured by direction
// (model/lights/light.h): its choice goes with the direction's density (infinite_pdf), and
// its point is on a disk facing the scene's bounding sphere. The bounding sphere covers the
// finite shapes, the camera and the point lights (so that what the camera sees around itself,
// on planes too, is reached by light subpaths: efficiency, not correctness); infinite planes
// are unbounded and cannot be covered. This stays unbiased everywhere:
//   - a ray from the disk stands for the light arriving from infinity along its line. Only an
//     unbounded plane can cross the line upstream of the disk (outside the sphere); then that
//     light never arrives, and sample() flags the origin `blocked` (no subpath from it);
//   - a point that no ray from the disk can reach (a far part of a plane outside the
//     cylinder the disk sweeps) has infinite_position_pdf 0: the strategies that would need
//     the infinite light's subpath to land there have density 0, and the MIS weights leave
//     them out (bdpt.cpp). The other strategies (the camera path escaping, the connection
//     towards a sampled direction) cover such points on their own.
// The direction of an infinite light's origin is valid whether or not the disk ray is
// blocked: bidirectional s = 1 connections use it.
//
// What cannot start a light subpath: emitting infinite planes have no finite area to sample.
// Like pbrt's lights that cannot be sampled, they are reached only by camera subpaths that
// hit them (the s = 0 strategies); their light-origin density is 0, and the MIS weight of
// such a path is 1 since no other strategy can produce it.
//
// A scene without infinite lights pays nothing for them.
#pragma once
#include <optional>
#include <vector>

#include "model/lights/light.h"
#include "scene/scene.h"
#include "spectral/sampled.h"

namespace spt {

class LightSampler {
public:
    explicit LightSampler(const Scene& scene);

    bool empty() const { return m_choice.empty(); }

    /// Samples a light ∝ power, a point on it and a direction (a moving point light where it
    /// is at `time`); nullopt when there is none.
    std::optional<LightOrigin> sample(const SampledWavelengths& lambda, float u_light, float u1,
                                      float u2, float u_side, float u3, float u4, float time = 0.f) const;

    /// Area density (choice included) with which sample() would produce this emitting hit
    /// point; 0 for emitters that cannot be sampled (infinite planes) and non-emitters.
    float origin_pdf(const Hit& hit) const;

    /// Solid-angle density (choice included) with which sample() produces infinite light
    /// `light`'s origin travelling along `d` (unit, into the scene); 0 when it is not chosen.
    float infinite_pdf(int light, const Vec3& d) const;

    /// Planar density of the disk point through which a ray from infinite light `light`
    /// travelling along `d` (unit) reaches `p` (its pdf_le_pos): 0 when no ray leaving the
    /// disk passes through p (p outside the cylinder the disk sweeps, or upstream of the disk).
    float infinite_position_pdf(int light, const Vec3& p, const Vec3& d) const;

    /// Radius of the bounding sphere of the finite shapes, the camera and the point lights.
    float scene_radius() const { return m_radius; }

private:
    const Scene& m_scene;
    LightDistribution m_choice;  ///< over Scene::lights: those that can start a subpath, by power
    float m_radius = 0.f;         ///< the scene's bounding sphere
};

}  // namespace spt

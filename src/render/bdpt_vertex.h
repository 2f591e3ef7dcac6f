// A vertex of a bidirectional subpath (bdpt.h): the camera, a light origin, a surface hit, a
// scattering point in a medium or an infinite light's vertex at infinity, with its throughput and its area densities in both directions.
// Shared by the connection code (bdpt.cpp) and vertex merging, which keeps the light
// subpaths of a whole pass (vertex_merging.h).
#pragma once
#include "geometry/ray.h"
#include "spectral/sampled.h"

namespace spt {

enum class BdptVertexType : unsigned char { camera, light, surface, medium };

struct BdptVertex {
    BdptVertexType type = BdptVertexType::surface;
    Hit hit;  ///< position, error bound, normal (zero: camera, point light, medium), material;
              ///< a light origin's `light` is its index in Scene::lights
    Vec3 wo;  ///< towards the previous vertex of its own subpath (surface and medium vertices)
    SampledSpectrum beta;
    float pdf_fwd = 0.f;  ///< area density of this vertex, sampled from its predecessor
    float pdf_rev = 0.f;  ///< area density of this vertex, sampled from its successor
    bool delta = false;          ///< a specular lobe was sampled here
    bool delta_light = false;    ///< point light origin (delta position)
    bool terminated = false;     ///< a dispersive refraction happened before this vertex
    /// An infinite light (a light vertex at infinity, measured by direction): `dir` is the
    /// unit direction from the scene towards it, hit.light the light (for an escaped camera
    /// path, set by connect() for each infinite light in turn), and hit.p is not used.
    bool infinite = false;
    Vec3 dir;
    /// Vertex merging: the other strategies' densities summed along the subpath up to this
    /// vertex, relative to the strategy that ends the subpath here (Bdpt::prefix_sums).
    float mis_sum = 0.f;
    /// Media (bdpt_media.h): the hero's transmittance of the segment from the previous vertex
    /// of its subpath (a factor of both vertices' densities along it); at a medium vertex
    /// the hero's σt (its density factor in place of a surface's |cos|); the medium the
    /// vertex is in (a surface vertex: the one its subpath arrived in).
    float edge_T = 1.f;
    float sigma_t = 0.f;
    int medium = -1;

    const Vec3& p() const { return hit.p; }
    bool on_surface() const { return hit.n.x != 0.f || hit.n.y != 0.f || hit.n.z != 0.f; }
};

}  // namespace spt

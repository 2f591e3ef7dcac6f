// Does a triangle mesh bound a volume, and which way do its faces point? A refracting mesh
// must: a ray that enters glass through an open or inward-facing mesh leaves with the wrong
// relative index (the dielectric takes "inside" from the side its normal points away from).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "core/vec3.h"

namespace spt {

struct MeshClosure {
    /// Every edge is shared by exactly two faces that traverse it in opposite directions
    /// (a closed, consistently oriented surface). Vertices are matched by exact position, so
    /// meshes that repeat a vertex per face count as connected.
    bool closed = false;
    /// Volume enclosed, with the sign of the orientation: positive when the faces' normals
    /// (p1 − p0) × (p2 − p0) point outward (divergence theorem: V = Σ p0 · (p1 × p2) / 6,
    /// taken about the vertices' centroid to keep the terms small). Meaningful when closed.
    double signed_volume = 0;
};

MeshClosure mesh_closure(const std::vector<Vec3>& positions,
                         const std::vector<std::array<std::uint32_t, 3>>& triangles);

}  // namespace spt

// PLY triangle-mesh reader: ASCII and binary little-endian; vertex x y z (float or double),
// optional vertex normals nx ny nz and surface coordinates (u v, s t or texture_u texture_v),
// and face vertex_indices lists (uchar/ushort/int/uint count; char..uint indices). Other
// properties and elements are skipped. Polygons are fan-triangulated. Sizes are checked
// against the file length before anything is allocated, so absurd counts fail cleanly.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/vec3.h"

namespace spt {

struct PlyMesh {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;                  ///< per vertex, or empty (no nx ny nz)
    std::vector<std::array<float, 2>> uvs;      ///< per vertex, or empty (no u v)
    std::vector<std::array<std::uint32_t, 3>> triangles;  ///< indices into positions
};

/// Parses PLY bytes; throws LocatedError ("origin:line:column: ...") on any defect,
/// including non-finite coordinates and indices outside the vertex list.
PlyMesh parse_ply(std::string_view bytes, const std::string& origin);

}  // namespace spt

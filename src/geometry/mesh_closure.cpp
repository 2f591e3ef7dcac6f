// Closedness by directed-edge counting; volume by the divergence theorem.
#include "geometry/mesh_closure.h"

#include <map>
#include <tuple>

namespace spt {

MeshClosure mesh_closure(const std::vector<Vec3>& positions,
                         const std::vector<std::array<std::uint32_t, 3>>& triangles) {
    // One id per distinct position (exact equality: welded and unwelded meshes agree).
    std::map<std::tuple<float, float, float>, std::uint32_t> ids;
    std::vector<std::uint32_t> id(positions.size());
    double cx = 0, cy = 0, cz = 0;
    for (std::size_t i = 0; i < positions.size(); ++i) {
        const Vec3& p = positions[i];
        id[i] = ids.emplace(std::tuple{p.x, p.y, p.z}, static_cast<std::uint32_t>(ids.size())).first->second;
        cx += p.x, cy += p.y, cz += p.z;
    }
    const double n = positions.empty() ? 1.0 : double(positions.size());
    cx /= n, cy /= n, cz /= n;

    // Each directed edge must occur once, and its reverse once.
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    MeshClosure result;
    for (const auto& t : triangles) {
        // A face with a repeated vertex has no area and bounds nothing: its edges would pair
        // with themselves.
        if (id[t[0]] == id[t[1]] || id[t[1]] == id[t[2]] || id[t[2]] == id[t[0]]) continue;
        double q[3][3];
        for (int k = 0; k < 3; ++k) {
            const Vec3& p = positions[t[k]];
            q[k][0] = p.x - cx, q[k][1] = p.y - cy, q[k][2] = p.z - cz;
            ++directed[{id[t[k]], id[t[(k + 1) % 3]]}];
        }
        const double cross[3] = {q[1][1] * q[2][2] - q[1][2] * q[2][1], q[1][2] * q[2][0] - q[1][0] * q[2][2],
                                 q[1][0] * q[2][1] - q[1][1] * q[2][0]};
        result.signed_volume += (q[0][0] * cross[0] + q[0][1] * cross[1] + q[0][2] * cross[2]) / 6.0;
    }
    result.closed = !triangles.empty();
    for (const auto& [edge, count] : directed) {
        const auto reverse = directed.find({edge.second, edge.first});
        if (count != 1 || reverse == directed.end() || reverse->second != 1) {
            result.closed = false;
            break;
        }
    }
    return result;
}

}  // namespace spt

#include "model/aperture.h"

#include <algorithm>
#include <cmath>

#include "core/sampling.h"

namespace spt {

AperturePoint Aperture::sample(float u1, float u2) const {
    if (blades == 0) {
        // The concentric disc: the x, y of the cosine-hemisphere warp (Shirley–Chiu).
        const Vec3 d = sample_cosine_hemisphere(u1, u2);
        return {radius * d.x, radius * d.y};
    }
    // One of the N equal triangles (centre, corner k, corner k + 1) chosen by u1, whose
    // remainder and u2 place the point uniformly inside it.
    const float n = static_cast<float>(blades);
    const float scaled = u1 * n;
    const float k = std::min(std::floor(scaled), n - 1.f);
    const float u = std::min(scaled - k, 1.f);
    const float first = (rotation_degrees + 90.f) * (kPi / 180.f) + k * (2.f * kPi / n);
    const float second = first + 2.f * kPi / n;
    const float a = std::sqrt(u) * radius;  // distance along the triangle's height, ∝ √u
    return {a * ((1.f - u2) * std::cos(first) + u2 * std::cos(second)),
            a * ((1.f - u2) * std::sin(first) + u2 * std::sin(second))};
}

}  // namespace spt

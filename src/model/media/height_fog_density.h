// Procedural density: ground fog, 1 below a height and falling off exponentially above it,
// d(p) = exp(−max(0, h − base)/scale_height) with h = p·up, up to the height `top` and 0
// above (so that rays leaving upwards end). Its integral along a vertical ray is analytic,
// which the tests use. The majorant of a segment is the density at its lowest point, so
// horizontal rays see no null collisions and rays rising into thin fog few.
#pragma once
#include <algorithm>
#include <cmath>

#include "geometry/ray.h"

namespace spt {

struct HeightFogDensity {
    static constexpr bool kUniform = false;
    Vec3 up{0.f, 1.f, 0.f};    ///< unit direction of increasing height
    float base = 0.f;          ///< height below which the density is 1
    float scale_height = 1.f;  ///< height over which the density falls by e (> 0)
    float top = 20.f;          ///< the fog ends here (> base)

    float density(const Vec3& p) const {
        const float h = dot(p, up);
        return h > top ? 0.f : std::exp(-std::max(0.f, h - base) / scale_height);
    }
    float max_density(const Ray& ray, float t0, float t1) const {
        const float rate = dot(ray.d, up);
        const float h_low = dot(ray.o, up) + rate * (rate >= 0.f ? t0 : t1);  // −inf for a ray falling forever
        return std::exp(-std::max(0.f, h_low - base) / scale_height);
    }
    /// Narrows [t0, t1] to the part below `top`.
    bool clip(const Ray& ray, float& t0, float& t1) const {
        const float h0 = dot(ray.o, up), rate = dot(ray.d, up);
        if (rate > 0.f) t1 = std::min(t1, (top - h0) / rate);
        else if (rate < 0.f) t0 = std::max(t0, (top - h0) / rate);
        else if (h0 > top) return false;
        return t0 < t1;
    }
};

}  // namespace spt

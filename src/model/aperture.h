// The lens aperture of a thin-lens camera: a disc, or the regular polygon that N straight
// blades leave open (the shape of out-of-focus highlights, "bokeh").
#pragma once
#include <cmath>

#include "core/math.h"
#include "core/sampling.h"

namespace spt {

/// A point of the aperture in lens coordinates (x right, y up, the camera's axes).
struct AperturePoint {
    float x, y;
};

struct Aperture {
    float radius = 0.f;  ///< of the disc, or circumradius of the polygon (its corners); 0: pinhole
    int blades = 0;      ///< 0: a disc; 3 or more: a regular polygon with that many sides
    /// Polygon: angle of one corner from the camera's up axis, counter-clockwise as seen
    /// looking along the view direction with x right and y up (0: a corner straight up).
    float rotation_degrees = 0.f;

    /// Area of the opening.
    float area() const {
        if (blades == 0) return kPi * radius * radius;
        const float n = static_cast<float>(blades);
        return 0.5f * n * radius * radius * std::sin(2.f * kPi / n);
    }

    /// Uniform point of the opening (density 1/area()) from two uniform numbers.
    AperturePoint sample(float u1, float u2) const {
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
};

}  // namespace spt

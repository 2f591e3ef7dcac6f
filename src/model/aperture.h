// The lens aperture of a thin-lens camera: a disc, or the regular polygon that N straight
// blades leave open (the shape of out-of-focus highlights, "bokeh").
#pragma once
#include <cmath>

#include "core/math.h"
#include "core/vec3.h"

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

    /// Uniform point of the opening (density 1/area()) from two uniform numbers. Out of line:
    /// inlined into the render loop, it made the loop big enough that GCC stopped inlining
    /// the cosine warp and Film::add_sample on the pinhole path (4.6 % slower per path).
    AperturePoint sample(float u1, float u2) const;
};

}  // namespace spt

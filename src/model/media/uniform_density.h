// Homogeneous medium: the same density (1) everywhere, so transmittance is exp(−σt·d) in
// closed form and free-flight sampling needs no null collisions.
#pragma once
#include "geometry/ray.h"

namespace spt {

struct UniformDensity {
    static constexpr bool kUniform = true;
    float density(const Vec3&) const { return 1.f; }
    float max_density(const Ray&, float, float) const { return 1.f; }
    /// The part [t0, t1] of the ray where the density may be non-zero: all of it.
    bool clip(const Ray&, float&, float&) const { return true; }
};

}  // namespace spt

// A point sampled on a shape's surface (area lights sample their shapes through this).
#pragma once
#include "core/vec3.h"

namespace spt {

/// A point drawn uniformly by area on a shape: the point, a conservative per-axis bound on its
/// distance to the true surface point (as Hit::p_err, so rays can be spawned from it), and
/// the shape's unit outward normal there.
struct SurfaceSample {
    Vec3 p, p_err, n;
};

}  // namespace spt

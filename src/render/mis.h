// Multiple importance sampling weights (Veach 1997, ch. 9).
#pragma once
#include <cmath>

namespace spt {

/// Power heuristic (β = 2) for a strategy of density `a` against one of density `b`, written
/// as 1/(1 + (b/a)²): a²/(a² + b²) overflows to ∞/∞ for densities above 1.8e19 (an area light
/// seen almost edge-on), which put NaN samples on the film.
inline float power_heuristic(float a, float b) {
    if (!(a > 0.f)) return 0.f;
    if (std::isinf(a)) return std::isinf(b) ? 0.5f : 1.f;
    const float r = b / a;
    return 1.f / (1.f + r * r);
}

}  // namespace spt

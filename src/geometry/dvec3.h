// Double-precision vectors for the shapes' exact arithmetic: float inputs are converted once,
// every intermediate stays in double, and only the final point or normal is rounded to float.
#pragma once
#include <algorithm>
#include <cmath>

#include "geometry/ray.h"

namespace spt {

struct DVec3 {
    double x = 0, y = 0, z = 0;

    constexpr DVec3() = default;
    constexpr DVec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
    explicit constexpr DVec3(const Vec3& v) : x(v.x), y(v.y), z(v.z) {}

    constexpr DVec3 operator-() const { return {-x, -y, -z}; }
    constexpr DVec3 operator+(const DVec3& b) const { return {x + b.x, y + b.y, z + b.z}; }
    constexpr DVec3 operator-(const DVec3& b) const { return {x - b.x, y - b.y, z - b.z}; }
    constexpr DVec3 operator*(double s) const { return {x * s, y * s, z * s}; }
    /// Rounded to the nearest floats.
    Vec3 to_float() const { return {static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)}; }
};

inline constexpr DVec3 operator*(double s, const DVec3& v) { return v * s; }
inline constexpr double dot(const DVec3& a, const DVec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline constexpr DVec3 cross(const DVec3& a, const DVec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(const DVec3& v) { return std::sqrt(dot(v, v)); }
inline DVec3 normalize(const DVec3& v) { return v * (1.0 / length(v)); }
inline double max_abs(const DVec3& v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }
inline double sum_abs(const DVec3& v) { return std::fabs(v.x) + std::fabs(v.y) + std::fabs(v.z); }

inline constexpr double kPiDouble = 3.14159265358979323846;

/// Unit roundoff of double, for the error bounds of double computations (float inputs).
inline constexpr double kDoubleEps = 0x1p-53;

/// Error bound of a point computed in double (about 16 operations on magnitudes up to
/// `magnitude`, doubled: the shapes' reprojections and samples) and rounded to float.
inline Vec3 double_point_error(const Vec3& p, double magnitude) {
    const float e = next_float_up(static_cast<float>(32.0 * kDoubleEps * magnitude));
    return rounded_point_error(p) + Vec3(e, e, e);
}

/// Tangents s, t with (s, t, n) orthonormal and right-handed, for a unit n: Frame's basis
/// (Duff et al. 2017) in double, so that points built on it stay on the shape to double
/// precision. The shapes measure their angle φ from s towards t.
inline void tangent_basis(const DVec3& n, DVec3& s, DVec3& t) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double b = n.x * n.y * a;
    s = {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
    t = {b, sign + n.y * n.y * a, -n.y};
}

/// Angle of the vector (x, y) in [0, 1) turns: the u coordinate of the shapes of revolution.
inline float turns(double x, double y) {
    double phi = std::atan2(y, x);
    if (phi < 0.0) phi += 2.0 * kPiDouble;
    return std::min(static_cast<float>(phi / (2.0 * kPiDouble)), 1.f);
}

}  // namespace spt

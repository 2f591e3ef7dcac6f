// Ray roots of the open surfaces of revolution about an axis, cylinders and cones, in double
// with conservative error bounds. One solver serves both: they are the quadric
// |x⊥|² − k²·x_z² = ρ² in coordinates x along (z) and across (⊥) a unit axis, with k = 0 for a
// cylinder of radius ρ (origin on its axis) and ρ = 0 for a cone of slope k (origin at its apex).
//
// Two cancellations of the textbook formula are avoided, as for the sphere (Ray Tracing Gems
// ch. 7; ROBUSTNESS.md §2): the discriminant B² − A·C is computed from g × d (the cross product
// of origin and direction: the (g·d)² terms, huge for far origins, cancel analytically), and
// the roots as q/A and C/q with q = −(B + sign(B)·√Δ), so that neither root subtracts nearly
// equal numbers. The identity, for the quadratic form Q = diag(1, 1, −k²) with A = Q(d),
// B = Q(g, d), C = Q(g) − ρ²: B² − A·C = k²·|c⊥|² − c_z² + A·ρ², c = g × d (Lagrange's
// identity generalised to a diagonal form: the cofactors of Q weight the components of c).
#pragma once
#include <algorithm>
#include <cmath>

#include "geometry/dvec3.h"

namespace spt {

/// Surface coordinates of a point p of a surface of revolution with unit axis a from `base`,
/// of the given height: u = φ/2π, the angle about the axis from the tangent s of
/// tangent_basis(a) towards t; v = the axial position from the base (0) to height (1). Both
/// clamped to [0, 1].
inline void axial_uv(const Vec3& p, const Vec3& base, const DVec3& a, double height, float& u, float& v) {
    DVec3 s, t;
    tangent_basis(a, s, t);
    const DVec3 q = DVec3(p) - DVec3(base);
    u = turns(dot(q, s), dot(q, t));
    v = static_cast<float>(std::clamp(dot(q, a) / height, 0.0, 1.0));
}

/// The unit vector at angle φ about the unit axis a, from the tangent s of tangent_basis(a)
/// towards t: the angle axial_uv measures.
inline DVec3 direction_about_axis(const DVec3& a, double phi) {
    DVec3 s, t;
    tangent_basis(a, s, t);
    return std::cos(phi) * s + std::sin(phi) * t;
}

/// The unit vector along r, the part of a point across the unit axis a; on the axis itself
/// (r = 0), where every direction across is as good, the tangent s of tangent_basis(a).
inline DVec3 radial_direction(const DVec3& r, const DVec3& a) {
    const double len = length(r);
    if (len > 0.0) return r * (1.0 / len);
    DVec3 s, t;
    tangent_basis(a, s, t);
    return s;
}

/// The roots of an axial quadric along a ray, each with a bound on its rounding error.
struct AxialRoots {
    int count = 0;                ///< 0, 1 or 2 (A = 0: one root)
    double t[2] = {0.0, 0.0};     ///< in no particular order
    double err[2] = {0.0, 0.0};   ///< |computed − exact root| ≤ err, exact for the float inputs
};

/// Roots t of |g⊥ + t·d⊥|² − k²·(g_z + t·d_z)² = ρ², where g is the ray origin relative to a
/// point of the axis (with a per-component error bound g_err from computing it), d the ray
/// direction and a the unit axis (in double: the surface is defined by this a). Requires
/// k = 0 or ρ = 0 (cylinder or cone). The error bounds follow each operation's rounding to
/// first order (u = 2⁻⁵³ per operation, magnitudes bounded by G = Σ|gᵢ|, D = Σ|dᵢ|) and are
/// then doubled to cover the higher-order terms: they are conservative, and about 10⁸ times
/// smaller than the float rounding of hit points, so they cost no real hits.
inline AxialRoots solve_axial_quadric(const DVec3& g, double g_err, const DVec3& d, const DVec3& a, double k,
                                      double rho) {
    constexpr double u = kDoubleEps;
    AxialRoots roots;
    const double gz = dot(g, a), dz = dot(d, a);
    const DVec3 gp = g - gz * a, dp = d - dz * a;
    const double len_gp = length(gp), len_dp = length(dp);
    // A, B, C with the difference of squares factored (no cancellation of the squares).
    const double A = (len_dp - k * std::fabs(dz)) * (len_dp + k * std::fabs(dz));
    const double B = dot(gp, dp) - k * k * gz * dz;
    const double R = std::sqrt(k * k * gz * gz + rho * rho);  // the surface's radius at g_z
    const double C = (len_gp - R) * (len_gp + R);
    const DVec3 c = cross(g, d);
    const double cz = dot(c, a);
    const double sqrt_p = k > 0.0 ? k * length(c - cz * a) : rho * len_dp;  // √(k²|c⊥|² + Aρ²)
    const double disc = (sqrt_p - std::fabs(cz)) * (sqrt_p + std::fabs(cz));

    // Error bounds. e_g bounds g_z and each component of g⊥ (similarly e_d, e_c for d and c).
    const double G = sum_abs(g), D = sum_abs(d), M = 1.0 + k, W = M * G + rho;
    const double e_g = 3.0 * g_err + 8.0 * u * G, e_d = 8.0 * u * D, e_c = 4.0 * D * e_g;
    const double err_a = 8.0 * M * M * D * e_d;
    const double err_b = 3.0 * M * M * (e_g * D + G * e_d);
    const double err_c = W * (6.0 * M * e_g + 9.0 * u * W);
    const double err_disc = W * D * (2.0 * (3.0 * k * e_c + 3.0 * rho * e_d + e_c) + 3.0 * u * W * D);
    if (disc < 0.0) return roots;  // misses (tangent rays within err_disc may go either way)

    const double s = std::sqrt(disc);
    const double err_s = (s * s > err_disc ? err_disc / s : std::sqrt(err_disc)) + u * s;
    const double q = -(B + std::copysign(s, B));
    if (q == 0.0) return roots;  // B = Δ = 0: the ray touches at t = 0 at most
    const double err_q = err_b + err_s + 2.0 * u * std::fabs(q);
    roots.t[roots.count] = C / q;
    roots.err[roots.count++] =
        2.0 * ((err_c + std::fabs(C / q) * err_q) / std::fabs(q) + 2.0 * u * std::fabs(C / q));
    if (A != 0.0) {
        roots.t[roots.count] = q / A;
        roots.err[roots.count++] =
            2.0 * ((err_q + std::fabs(q / A) * err_a) / std::fabs(A) + 2.0 * u * std::fabs(q / A));
    }
    return roots;
}

}  // namespace spt

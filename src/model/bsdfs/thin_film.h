// Reflectance of interfaces with complex indices, bare or coated with one thin film, from the
// Airy summation of the amplitudes reflected inside the film (Born & Wolf, §1.6 and §7.6):
//   r = (r01 + r12·e^{2iδ}) / (1 + r01·r12·e^{2iδ}),   δ = 2π·d·n1·cos θ1 / λ,
// per polarisation, the reflectance |r|² averaged over s and p (unpolarised light). Every
// cosine is carried as q_j = n_j·cos θ_j = √(n_j² − n_0²·sin² θ_0) on the principal branch,
// which is the decaying wave for an absorbing substrate (k > 0) and beyond total internal
// reflection (q imaginary), so one formula covers metals, glass from either side and TIR.
// A film of thickness 0 gives the bare interface 0|2 exactly.
#pragma once
#include <algorithm>
#include <cmath>
#include <complex>

#include "core/math.h"

namespace spt {

using Complex = std::complex<float>;

namespace thin_film_detail {
// std::sqrt, std::norm and the division of std::complex<float> are library calls (csqrtf, a
// hypot, __divsc3) that cost a conductor's Fresnel term several times its arithmetic; the
// bare interface needs only |r|², a quotient of two squared moduli, and the root and the
// modulus are written out here.

/// x² + y² (std::norm of a float complex goes through a hypot).
inline float squared_modulus(Complex z) { return z.real() * z.real() + z.imag() * z.imag(); }
/// The principal square root (real part ≥ 0; the branch cut along the negative reals, whose
/// root is +i·√|x| for imaginary part +0). Each branch takes the root of a sum of two
/// non-negative terms, so neither cancels.
inline Complex principal_sqrt(Complex z) {
    const float x = z.real(), y = z.imag(), r = std::sqrt(squared_modulus(z));
    if (r == 0.f) return {0.f, 0.f};
    if (x >= 0.f) {
        const float t = std::sqrt(0.5f * (r + x));
        return {t, y / (2.f * t)};
    }
    const float t = std::sqrt(0.5f * (r - x));
    return {std::fabs(y) / (2.f * t), std::copysign(t, y)};
}
inline Complex q_of(Complex n, float n0_sin2) { return principal_sqrt(n * n - Complex(n0_sin2)); }
inline Complex r_s(Complex qa, Complex qb) { return (qa - qb) / (qa + qb); }
/// p-polarised amplitude with n_a² and n_b² (the cosines are q/n).
inline Complex r_p(Complex na2, Complex qa, Complex nb2, Complex qb) {
    return (nb2 * qa - na2 * qb) / (nb2 * qa + na2 * qb);
}
}  // namespace thin_film_detail

/// Unpolarised reflectance of the interface from a medium of real index n0 into one of complex
/// index n2 (η + ik), for light arriving at cos_i = cos θ0 in [0, 1].
inline float interface_reflectance(float cos_i, float n0, Complex n2) {
    using namespace thin_film_detail;
    cos_i = std::clamp(cos_i, 0.f, 1.f);
    const float s2 = n0 * n0 * (1.f - cos_i * cos_i);
    const Complex q0(n0 * cos_i), q2 = q_of(n2, s2), na2(n0 * n0), nb2 = n2 * n2;
    // |r_s|² and |r_p|² as |numerator|² / |denominator|² of r_s and r_p.
    const float rs2 = squared_modulus(q0 - q2) / squared_modulus(q0 + q2);
    const float rp2 = squared_modulus(nb2 * q0 - na2 * q2) / squared_modulus(nb2 * q0 + na2 * q2);
    return std::min(1.f, 0.5f * (rs2 + rp2));
}

/// Exact Fresnel reflectance of a conductor η + ik seen from a medium of index 1.
inline float fresnel_conductor(float cos_i, float eta, float k) { return interface_reflectance(cos_i, 1.f, {eta, k}); }

/// Unpolarised reflectance of a film of real index n1 and thickness `thickness_nm` between an
/// incident medium of real index n0 and a substrate of complex index n2, at wavelength
/// `lambda_nm`, for light arriving at cos_i = cos θ0 in [0, 1].
inline float thin_film_reflectance(float cos_i, float n0, float n1, Complex n2, float thickness_nm,
                                   float lambda_nm) {
    using namespace thin_film_detail;
    cos_i = std::clamp(cos_i, 0.f, 1.f);
    const float s2 = n0 * n0 * (1.f - cos_i * cos_i);
    const Complex q0(n0 * cos_i), q1 = q_of(Complex(n1), s2), q2 = q_of(n2, s2);
    const Complex n0c(n0 * n0), n1c(n1 * n1), n2c = n2 * n2;
    // e^{2iδ}: the round trip through the film (decays when q1 is imaginary: frustrated TIR).
    const Complex phase = std::exp(Complex(0.f, 4.f * kPi * thickness_nm / lambda_nm) * q1);
    const Complex r01s = r_s(q0, q1), r12s = r_s(q1, q2);
    const Complex r01p = r_p(n0c, q0, n1c, q1), r12p = r_p(n1c, q1, n2c, q2);
    const Complex rs = (r01s + r12s * phase) / (1.f + r01s * r12s * phase);
    const Complex rp = (r01p + r12p * phase) / (1.f + r01p * r12p * phase);
    return std::min(1.f, 0.5f * (squared_modulus(rs) + squared_modulus(rp)));
}

}  // namespace spt

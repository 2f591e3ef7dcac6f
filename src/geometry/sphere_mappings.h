// Maps between unit directions and the unit square [0,1]², for environment images: the
// equal-area octahedral square (Clarberg 2008, "Fast Equal-Area Mapping of the (Hemi)Sphere
// using SIMD"; the layout of pbrt-v4's square environment maps) and the equirectangular
// lat-long image in Mitsuba 3's `envmap` convention. Directions are in the map's own frame;
// the light applies its transform.
//
// Equal-area square (pbrt-v4's EqualAreaSquareToSphere / EqualAreaSphereToSquare /
// WrapEqualAreaSquare layout, checked against pbrt-v4 src/pbrt/util/math.cpp):
//   (a, b) = (2u − 1, 2v − 1). The diamond |a| + |b| = 1 is the equator z = 0; inside it the
//   +z hemisphere (centre (½, ½) = +z), outside it −z (all four corners = −z). With
//   s = |a| + |b|, the ring radius is r = s (north) or 2 − s (south), z = ±(1 − r²), and φ
//   runs linearly along the ring within each quadrant, from the a axis to the b axis; the
//   signs of a and b are those of x and y. So +x = (1, ½), +y = (½, 1), −x = (0, ½),
//   −y = (½, 0). Area is preserved: the diamond s ≤ r has area 2r² in (a, b) and its cap
//   z ≥ 1 − r² has area 2π(1 − z) = 2πr², and φ is uniform along each ring; so a density p
//   on the unit square is p/(4π) per steradian. pbrt-v4's ImageInfiniteLight reads the
//   nearest texel (Image::LookupNearestChannel: texel (⌊u·n⌋, ⌊v·n⌋), v = 0 the first
//   stored row; u or v = 1 mirrored back by its octahedral wrap).
//   pbrt-v4 evaluates the inverse's arctangent by a degree-6 polynomial (Clarberg's; its
//   error is up to 4.1e-6 of the quarter turn, so up to 2e-6 in u or v: 1 % of a texel of a
//   4096² map); an arctangent good to 1e-10 here (core/fast_math.h, a series without a
//   library call) makes the two maps inverses to float rounding (1e-6, tested).
//   Near the poles 1 − |z| is formed as (x² + y²)/(1 + |z|), which does not cancel.
//
// Equirectangular (checked against Mitsuba 3 src/emitters/envmap.cpp at 0179ad9,
// direction_to_uv and uv_to_direction): +Y up, u = atan2(d.x, −d.z)/(2π) wrapped to [0,1), v = acos(d.y)/π; so
// v = 0 at +Y (the top row of the image), −Z at u = 0, +X at u = ¼, +Z at u = ½, −X at u = ¾,
// and d = (sin φ sin θ, cos θ, −cos φ sin θ) with φ = 2πu, θ = πv. θ is computed as
// atan2(√(x² + z²), y), equal to acos(y) for unit d and accurate near the poles. The solid-
// angle density of a density p on the unit square is p/(2π² sin θ) (Mitsuba's
// sample_direction / pdf_direction use the same factor).
//   How Mitsuba places texels on (u, v) is the light's business, not these maps': its
//   eval_spectrum interpolates bilinearly with column j centred at u = (j + ½)/W (it adds a
//   copy of column 0 after the last for the seam) but row i at v = i/(H − 1): the first and
//   last rows lie on the poles, not half a row inside them.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "core/fast_math.h"
#include "core/math.h"
#include "core/vec3.h"

namespace spt {

// ---------------------------------------------------------------- equal-area octahedral square

/// The unit direction at (u, v) in [0,1]² of the equal-area square. Points outside the square
/// go through wrap_equal_area_square first.
inline Vec3 equal_area_square_to_sphere(float u, float v) {
    const float a = 2.f * u - 1.f, b = 2.f * v - 1.f;
    const float abs_a = std::fabs(a), abs_b = std::fabs(b);
    const float s = abs_a + abs_b;
    const bool north = s <= 1.f;
    // Ring radius: 0 at the pole of the hemisphere, 1 on the equator (formed without
    // cancellation near either pole).
    const float r = north ? s : 2.f - s;
    const float one_minus_r2 = 1.f - r * r;
    const float z = north ? one_minus_r2 : -one_minus_r2;
    // Angle within the quadrant, linear along the ring: 0 where |b| = 0, π/2 where |a| = 0.
    const float phi = r > 0.f ? (kPi / 4.f) * (1.f + (abs_b - abs_a) / r) : kPi / 4.f;
    // sin θ = √(1 − z²) = r·√(2 − r²).
    const float sin_theta = r * safe_sqrt(2.f - r * r);
    return {std::copysign(std::cos(phi) * sin_theta, a), std::copysign(std::sin(phi) * sin_theta, b), z};
}

/// The z component of equal_area_square_to_sphere(u, v) (the same operations, the same bits)
/// without the azimuth's sine and cosine.
inline float equal_area_square_z(float u, float v) {
    const float s = std::fabs(2.f * u - 1.f) + std::fabs(2.f * v - 1.f);
    const bool north = s <= 1.f;
    const float r = north ? s : 2.f - s;
    const float one_minus_r2 = 1.f - r * r;
    return north ? one_minus_r2 : -one_minus_r2;
}

/// The point of [0,1]² of the equal-area square for a unit direction (the inverse of
/// equal_area_square_to_sphere; edge points that share a direction come back as one of them).
inline std::array<float, 2> equal_area_sphere_to_square(const Vec3& d) {
    const float x = std::fabs(d.x), y = std::fabs(d.y), z = std::fabs(d.z);
    const float one_minus_z = z > 0.5f ? (x * x + y * y) / (1.f + z) : 1.f - z;
    const float r = safe_sqrt(one_minus_z);
    // Fraction of the quadrant's quarter turn: 0 on the x axis, 1 on the y axis.
    const float t = std::min(static_cast<float>(atan2_nonnegative(y, x) * (2.0 / std::numbers::pi)), 1.f);
    float b = t * r, a = r - b;  // north: |a| + |b| = r
    if (d.z < 0.f) {             // south: |a| + |b| = 2 − r, the same ring mirrored outward
        const float a_south = 1.f - b, b_south = 1.f - a;
        a = a_south, b = b_south;
    }
    return {0.5f * (std::copysign(a, d.x) + 1.f), 0.5f * (std::copysign(b, d.y) + 1.f)};
}

/// Brings a point up to one square outside [0,1]² back into it along the sphere: across an
/// edge the square continues mirrored (crossing u = 0 or u = 1 flips v to 1 − v; crossing
/// v = 0 or v = 1 flips u to 1 − u), for filtering across the edges.
inline std::array<float, 2> wrap_equal_area_square(float u, float v) {
    if (u < 0.f) {
        u = -u, v = 1.f - v;
    } else if (u > 1.f) {
        u = 2.f - u, v = 1.f - v;
    }
    if (v < 0.f) {
        u = 1.f - u, v = -v;
    } else if (v > 1.f) {
        u = 1.f - u, v = 2.f - v;
    }
    return {u, v};
}

/// The same mirror for texel indices of an n × n equal-area image (texel i centred at
/// (i + ½)/n), for indices up to n outside: texel −1 is texel 0 mirrored. (pbrt-v4's
/// RemapPixelCoords maps texel −1 to texel 1 on the low edges, half a texel off the
/// continuous mirror; it matters only to filtering of the outermost texels.)
inline void wrap_equal_area_texel(int& i, int& j, int n) {
    if (i < 0) {
        i = -i - 1, j = n - 1 - j;
    } else if (i >= n) {
        i = 2 * n - 1 - i, j = n - 1 - j;
    }
    if (j < 0) {
        i = n - 1 - i, j = -j - 1;
    } else if (j >= n) {
        i = n - 1 - i, j = 2 * n - 1 - j;
    }
}

/// Solid-angle density of a direction drawn with density square_pdf over the equal-area
/// square: the map preserves area, 1 unit of square per 4π steradians.
inline float equal_area_solid_angle_pdf(float square_pdf) { return square_pdf * (0.25f * kInvPi); }

// ---------------------------------------------------------------- equirectangular (lat-long)

/// The unit direction at (u, v) of a lat-long image (Mitsuba 3 convention, +Y up).
inline Vec3 equirect_to_direction(float u, float v) {
    const float phi = 2.f * kPi * u, theta = kPi * v;
    const float sin_theta = std::sin(theta), cos_theta = std::cos(theta);
    return {std::sin(phi) * sin_theta, cos_theta, -std::cos(phi) * sin_theta};
}

/// (u, v) of a unit direction in a lat-long image: u in [0,1) (the seam u = 1 returns 0),
/// v in [0,1] (v = 1 only at −Y exactly).
inline std::array<float, 2> direction_to_equirect(const Vec3& d) {
    // The arctangents in double by a series (core/fast_math.h): std::atan2f, a library call,
    // was a tenth of the time of a path under an environment map.
    double phi = atan2_signed(d.x, -double(d.z)) * (0.5 / std::numbers::pi);  // [−½, ½]
    if (phi < 0.0) phi += 1.0;
    float u = static_cast<float>(phi);
    if (!(u < 1.f) || u == 0.f) u = 0.f;  // −tiny + 1 rounds to 1; −0 becomes +0
    const double theta = atan2_nonnegative(std::sqrt(double(d.x) * d.x + double(d.z) * d.z), d.y);
    const float v = std::min(static_cast<float>(theta / std::numbers::pi), 1.f);
    return {u, v};
}

/// Solid-angle density of a direction drawn with density square_pdf over the lat-long
/// square, at row coordinate v: square_pdf/(2π² sin θ), θ = πv; 0 at the poles (sin θ = 0)
/// and outside [0,1].
inline float equirect_solid_angle_pdf(float square_pdf, float v) {
    // sin(π·v) = sin(π·(1 − v)): take the smaller argument so that the south pole keeps
    // its precision too (1 − v is exact for v in [½, 1]).
    const float sin_theta = std::sin(kPi * std::min(v, 1.f - v));
    return sin_theta > 0.f ? square_pdf / (2.f * kPi * kPi * sin_theta) : 0.f;
}

}  // namespace spt

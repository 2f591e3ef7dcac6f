// Where light subpaths from infinity start (the environment, a map, the sky, the sun): on the
// disk of the scene's bounding sphere (centre c, radius R) perpendicular to the direction w
// the light travels, one radius upstream of c, at a point uniform over the disk (pbrt's
// infinite lights). Every ray along w that can reach the scene crosses that disk once, so
// the disk point's planar density 1/(πR²) goes to the subpath's first vertex x times |cos θx|
// (pbrt-v3's InfiniteLightDensity and PdfLight).
#pragma once
#include <cmath>

#include "core/frame.h"
#include "model/lights/light_sample.h"

namespace spt {

/// Sets o.p (from u3, u4), o.p_err and o.pdf_pos for an origin that travels along o.w.
inline void place_on_bounding_disk(LightOrigin& o, const Vec3& center, float radius, float u3, float u4) {
    const Frame frame(o.w);
    const float r = radius * std::sqrt(u3), phi = 2.f * kPi * u4;
    o.p = center - o.w * radius + frame.s * (r * std::cos(phi)) + frame.t * (r * std::sin(phi));
    o.p_err = Vec3(0, 0, 0);
    o.pdf_pos = 1.f / (kPi * radius * radius);
}

/// Planar density of the disk point through which a ray travelling along d (unit) reaches
/// p: 1/(πR²), or 0 when no ray leaving the disk passes through p (p outside the cylinder
/// the disk sweeps, or upstream of the disk).
inline float bounding_disk_pdf_pos(const Vec3& center, float radius, const Vec3& p, const Vec3& d) {
    const Vec3 v = p - center;
    const float along = dot(v, d);
    if (along < -radius || length_squared(v - d * along) > radius * radius) return 0.f;
    return 1.f / (kPi * radius * radius);
}

}  // namespace spt

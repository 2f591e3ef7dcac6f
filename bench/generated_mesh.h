// Generated test content for the benchmarks: a closed, displaced blob on a displaced terrain,
// tessellated unevenly (triangle areas vary by two orders of magnitude within each part), in
// place of a scanned model. Deterministic for a given triangle count.
#pragma once
#include <cmath>
#include <numbers>
#include <vector>

#include "geometry/triangle.h"

namespace spt::bench {

/// Sum of sines along fixed directions at doubling frequencies: a cheap fractal bump field.
inline double bumps(double x, double y, double z, int octaves) {
    double sum = 0.0, amplitude = 1.0, frequency = 2.0;
    for (int k = 0; k < octaves; ++k) {
        const double a = 1.3 * k + 0.4, b = 2.1 * k + 1.1;  // a direction per octave
        const double dx = std::sin(a) * std::cos(b), dy = std::cos(a), dz = std::sin(a) * std::sin(b);
        sum += amplitude * std::sin(frequency * (dx * x + dy * y + dz * z) + 0.7 * k);
        amplitude *= 0.5, frequency *= 2.03;
    }
    return sum;
}

/// About n triangles: 70 % on the blob (radius about 1 around the origin, rings bunched
/// towards one pole), 30 % on the terrain below it (y ≈ −1.2, |x|, |z| ≤ 3, finer at the centre).
inline std::vector<Triangle> generated_mesh(int n) {
    std::vector<Triangle> out;
    out.reserve(static_cast<std::size_t>(n) + 16);
    auto quad = [&out](const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
        const Triangle t0{a, b, c, 0}, t1{a, c, d, 0};
        if (!t0.is_degenerate()) out.push_back(t0);
        if (!t1.is_degenerate()) out.push_back(t1);
    };
    // The blob: a UV sphere with ring angle θ = π·s^1.7 (dense near one pole), displaced.
    const int rings = std::max(4, static_cast<int>(std::sqrt(0.7 * n / 4.0))), segments = 2 * rings;
    auto blob = [&](int i, int j) {
        const double th = std::numbers::pi * std::pow(double(i) / rings, 1.7);
        const double ph = 2 * std::numbers::pi * (j % segments) / segments;
        const double x = std::sin(th) * std::cos(ph), y = std::cos(th), z = std::sin(th) * std::sin(ph);
        const double r = 1.0 + 0.12 * bumps(x, y, z, 7);
        return Vec3(float(r * x), float(r * y), float(r * z));
    };
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) quad(blob(i, j), blob(i + 1, j), blob(i + 1, j + 1), blob(i, j + 1));
    // The terrain: a grid whose spacing grows away from the centre (x = 3·s·|s|), displaced.
    const int cells = std::max(2, static_cast<int>(std::sqrt(0.3 * n / 2.0)));
    auto terrain = [&](int i, int j) {
        const double s = 2.0 * i / cells - 1.0, t = 2.0 * j / cells - 1.0;
        const double x = 3.0 * s * std::fabs(s), z = 3.0 * t * std::fabs(t);
        return Vec3(float(x), float(-1.2 + 0.15 * bumps(x, 0.0, z, 6)), float(z));
    };
    for (int i = 0; i < cells; ++i)
        for (int j = 0; j < cells; ++j) quad(terrain(i, j), terrain(i, j + 1), terrain(i + 1, j + 1), terrain(i + 1, j));
    return out;
}

}  // namespace spt::bench

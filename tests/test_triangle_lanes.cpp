// The four-lane rejection test (triangle_lanes.h) against the one-triangle watertight test: it
// never rejects a triangle that intersect_triangle hits, and it keeps almost only those, on
// random and adversarial triangles and rays (through vertices and edges, degenerate
// triangles, coordinates near 1e±30, t_max cutting through the hits). A planted imprecise
// variant (edge functions rounded in float, no margin) must be caught by the same check.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "core/rng.h"
#include "core/sampling.h"
#include "geometry/triangle_lanes.h"

namespace spt {
namespace {

struct LaneCase {
    TriangleLanes tri;
    Ray ray;
    double t_max;
    bool from_surface;  ///< the ray leaves one of the triangles (the t > δt test may reject it)
};

using Candidates = std::function<unsigned(const TriangleLanes&, const ShearedRay&, double)>;

struct Agreement {
    int wrong_rejections = 0;  ///< lanes rejected that intersect_triangle hits (must be 0)
    int extra_candidates = 0;  ///< lanes kept that it misses (off the surface, nonzero area)
    int hits = 0, misses = 0;  ///< what intersect_triangle said, to show that both occur
};

/// Each lane of each case by `candidates` and by intersect_triangle.
Agreement compare(const std::vector<LaneCase>& cases, const Candidates& candidates) {
    Agreement a;
    for (const LaneCase& c : cases) {
        const ShearedRay sheared(c.ray);
        const unsigned bits = candidates(c.tri, sheared, c.t_max);
        for (int k = 0; k < 4; ++k) {
            const bool hit = intersect_triangle(c.tri.vertex(0, k), c.tri.vertex(1, k), c.tri.vertex(2, k), sheared,
                                                c.t_max)
                                 .has_value();
            const bool kept = (bits >> k) & 1u;
            ++(hit ? a.hits : a.misses);
            if (hit && !kept) ++a.wrong_rejections;
            const bool zero_area = has_zero_float_area(c.tri.vertex(0, k), c.tri.vertex(1, k), c.tri.vertex(2, k));
            if (!hit && kept && !c.from_surface && !zero_area) ++a.extra_candidates;
        }
    }
    return a;
}

/// Packets of four triangles at scale 1e−30, 1, 1e30 (some degenerate: a repeated vertex, three
/// collinear or coincident points), and rays aimed at a point inside one of them, exactly at
/// a vertex, at an edge's midpoint (rounded to float), in a random or an axis direction, or
/// leaving a triangle's surface; t_max infinite or cutting the aimed-at hit.
std::vector<LaneCase> adversarial_cases(int count) {
    Rng rng(2024, 0, 0);
    std::vector<LaneCase> cases;
    const float scales[] = {1e-30f, 1.f, 1e30f};
    for (int n = 0; n < count; ++n) {
        const float s = scales[n % 3];
        auto point = [&] { return (Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 2.f - Vec3(1, 1, 1)) * s; };
        LaneCase c{};
        Vec3 p[4][3];
        for (int k = 0; k < 4; ++k) {
            p[k][0] = point(), p[k][1] = point(), p[k][2] = point();
            // Neighbours sharing an edge with lane 0, so that edge rays meet both.
            if (k == 1 && n % 2) p[k][0] = p[0][1], p[k][1] = p[0][0];
            const int degenerate = static_cast<int>(rng.uniform() * 12);
            if (degenerate == 0) p[k][2] = p[k][0];
            if (degenerate == 1) p[k][2] = p[k][0] + (p[k][1] - p[k][0]) * 2.f;
            if (degenerate == 2) p[k][1] = p[k][2] = p[k][0];
            c.tri.set(k, p[k][0], p[k][1], p[k][2]);
        }
        const int aim = static_cast<int>(rng.uniform() * 4);
        const Vec3* t = p[aim];
        const float b1 = rng.uniform(), b2 = rng.uniform() * (1.f - b1);
        Vec3 target = t[0] * (1.f - b1 - b2) + t[1] * b1 + t[2] * b2;
        const int kind = n % 7;
        if (kind == 1) target = t[static_cast<int>(rng.uniform() * 3) % 3];
        if (kind == 2) target = t[0] + (t[1] - t[0]) * 0.5f;
        Vec3 o = point() * 3.f;
        Vec3 d = normalize(target - o);
        if (kind == 3) d = sample_uniform_sphere(rng.uniform(), rng.uniform());
        if (kind == 4) d = Vec3(0, 0, rng.uniform() < 0.5f ? -1.f : 1.f), o = target - d * s;
        c.from_surface = kind == 5;
        if (c.from_surface) {
            // Leaving the aimed-at point along a random direction (it starts on that triangle).
            o = target;
            d = sample_uniform_sphere(rng.uniform(), rng.uniform());
        }
        if (!(length(d) > 0.f) || !std::isfinite(length(d))) continue;
        c.ray = {o, d, kInfinity};
        // t_max: infinite, or about the aimed-at distance so that it cuts through the hits.
        c.t_max = n % 3 == 1 ? double(length(target - o)) * (0.9 + 0.2 * rng.uniform()) : double(kInfinity);
        cases.push_back(c);
    }
    return cases;
}

TEST(TriangleLanes, RejectsExactlyWhatTheWatertightTestRejects) {
    const std::vector<LaneCase> cases = adversarial_cases(60000);
    const Agreement a = compare(cases, triangle_candidates);
    EXPECT_EQ(a.wrong_rejections, 0);
    // What the lanes keep and intersect_triangle then rejects fails only its t > δt test: off
    // the surface, thin triangles met close to the origin relative to their extent; rare.
    EXPECT_LT(a.extra_candidates, (a.hits + a.misses) / 1000);
    EXPECT_GT(a.hits, 10000);
    EXPECT_GT(a.misses, 100000);
}

TEST(TriangleLanes, ANonRayRejectsEverything) {
    TriangleLanes tri;
    tri.set(0, {-1, -1, 1}, {1, -1, 1}, {0, 1, 1});
    EXPECT_EQ(triangle_candidates(tri, ShearedRay({{0, 0, 0}, {0, 0, 1}, kInfinity}), kInfinity), 1u);
    EXPECT_EQ(triangle_candidates(tri, ShearedRay({{0, 0, 0}, {0, 0, 0}, kInfinity}), kInfinity), 0u);
}

/// The planted bug: the edge functions rounded in float (products and difference), the rest
/// as in triangle_candidates. Their signs are then wrong near an edge or a vertex.
unsigned float_edge_candidates(const TriangleLanes& tri, const ShearedRay& r, double t_max) {
    unsigned bits = 0;
    for (int k = 0; k < 4; ++k) {
        float x[3], y[3], z[3];
        for (int i = 0; i < 3; ++i) {
            const Vec3 q = tri.vertex(i, k) - r.o;
            z[i] = q[r.kz], x[i] = q[r.kx] + r.sx * z[i], y[i] = q[r.ky] + r.sy * z[i];
        }
        const float e[3] = {x[1] * y[2] - y[1] * x[2], x[2] * y[0] - y[2] * x[0], x[0] * y[1] - y[0] * x[1]};
        if ((e[0] < 0 || e[1] < 0 || e[2] < 0) && (e[0] > 0 || e[1] > 0 || e[2] > 0)) continue;
        const double det = double(e[0]) + e[1] + e[2];
        if (det == 0.0) continue;
        const double t_scaled = e[0] * (double(r.sz) * z[0]) + e[1] * (double(r.sz) * z[1]) + e[2] * (double(r.sz) * z[2]);
        if (det < 0 && (t_scaled >= 0 || t_scaled < t_max * det)) continue;
        if (det > 0 && (t_scaled <= 0 || t_scaled > t_max * det)) continue;
        bits |= 1u << k;
    }
    return bits;
}

TEST(TriangleLanes, APlantedFloatEdgeTestIsCaught) {
    const Agreement a = compare(adversarial_cases(60000), float_edge_candidates);
    EXPECT_GT(a.wrong_rejections, 0);
}

}  // namespace
}  // namespace spt

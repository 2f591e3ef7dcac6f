// PhotonGrid (render/photon_grid.h), the fixed-radius search of vertex merging: every query
// must visit exactly the points within the radius (distance ≤ r, the same float test as a
// brute-force scan), each once, whatever the coordinates' signs, clustering or count; and
// the bookkeeping of MergePass (photons, subpath bounds, eta).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <algorithm>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "render/photon_grid.h"
#include "render/vertex_merging.h"
#include "test_scenes.h"

namespace spt {
namespace {

/// Visits per point index for one query (a point visited twice shows up as 2).
std::vector<int> visits(const PhotonGrid& grid, std::size_t n, const Vec3& p) {
    std::vector<int> count(n, 0);
    grid.query(p, [&](std::uint32_t j, float d2) {
        const std::uint32_t i = grid.order()[j];
        EXPECT_LT(i, n);
        if (i < n) ++count[i];
        EXPECT_GE(d2, 0.f);
    });
    return count;
}

/// The brute-force answer, with the grid's own test (float, d = point − p, d·d ≤ r·r).
std::vector<int> brute_force(const std::vector<Vec3>& points, const Vec3& p, float radius) {
    const float r2 = radius * radius;
    std::vector<int> inside(points.size(), 0);
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec3 d = points[i] - p;
        inside[i] = dot(d, d) <= r2 ? 1 : 0;
    }
    return inside;
}

/// Compares grid and brute force for every query; returns the number of queries that differ
/// (and reports the first few).
int check_queries(const std::vector<Vec3>& points, float radius, const std::vector<Vec3>& queries,
                  const std::string& what) {
    PhotonGrid grid;
    grid.build(points, radius);
    EXPECT_EQ(grid.size(), points.size());
    int wrong = 0;
    for (const Vec3& q : queries) {
        const std::vector<int> got = visits(grid, points.size(), q), want = brute_force(points, q, radius);
        if (got == want) continue;
        if (++wrong <= 3) {
            for (std::size_t i = 0; i < points.size(); ++i)
                if (got[i] != want[i])
                    ADD_FAILURE() << what << ": query (" << q.x << ", " << q.y << ", " << q.z << "), r = " << radius
                                  << ": point " << i << " (" << points[i].x << ", " << points[i].y << ", "
                                  << points[i].z << ") visited " << got[i] << " times, expected " << want[i];
        }
    }
    return wrong;
}

Vec3 uniform_in_box(std::mt19937& rng, float lo, float hi) {
    std::uniform_real_distribution<float> u(lo, hi);
    const float x = u(rng), y = u(rng), z = u(rng);
    return {x, y, z};
}

TEST(PhotonGrid, EmptyGridVisitsNothing) {
    PhotonGrid grid;
    grid.build({}, 0.5f);
    EXPECT_EQ(grid.size(), 0u);
    int n = 0;
    grid.query({0, 0, 0}, [&](std::uint32_t, float) { ++n; });
    EXPECT_EQ(n, 0);
}

/// One point: the table has a single bucket, so all eight cells of a query share it; the
/// point must still be visited once (at most), exactly when it is within the radius.
TEST(PhotonGrid, SinglePointVisitedOnce) {
    const std::vector<Vec3> points = {{0.3f, -0.7f, 1.1f}};
    std::vector<Vec3> queries;
    for (float dx : {-0.6f, -0.49f, -0.1f, 0.f, 0.2f, 0.5f, 0.51f, 2.f})
        for (float dy : {-0.3f, 0.f, 0.25f}) queries.push_back(points[0] + Vec3(dx, dy, 0.f));
    EXPECT_EQ(check_queries(points, 0.5f, queries, "single point"), 0);
}

/// Random points in boxes straddling the origin (negative cells), at several radii and
/// counts (table sizes 1 to 4096, so every number of shared buckets occurs).
TEST(PhotonGrid, MatchesBruteForceOnRandomPoints) {
    std::mt19937 rng(12345);
    int total_wrong = 0;
    for (int n : {2, 3, 5, 17, 100, 1000, 4000})
        for (float radius : {0.013f, 0.1f, 0.37f, 2.5f}) {
            std::vector<Vec3> points(static_cast<std::size_t>(n)), queries(200);
            for (Vec3& p : points) p = uniform_in_box(rng, -3.f, 2.f);
            // Queries near points (many hits) and anywhere in the box (few).
            for (std::size_t k = 0; k < queries.size(); ++k)
                queries[k] = k % 2 ? uniform_in_box(rng, -3.5f, 2.5f)
                                   : points[k % points.size()] + uniform_in_box(rng, -radius, radius);
            total_wrong += check_queries(points, radius, queries, "n = " + std::to_string(n));
        }
    EXPECT_EQ(total_wrong, 0);
}

/// Clusters: many points at one position or within a tiny ball (one cell, one long bucket
/// run), and points far away (large cell coordinates, hashing with wrap-around).
TEST(PhotonGrid, MatchesBruteForceOnClustersAndFarPoints) {
    std::mt19937 rng(777);
    std::vector<Vec3> points;
    for (int i = 0; i < 50; ++i) points.push_back({-1.25f, 0.5f, -0.75f});  // duplicates
    for (int i = 0; i < 200; ++i) points.push_back(Vec3(0.4f, -0.2f, 0.1f) + uniform_in_box(rng, -1e-3f, 1e-3f));
    for (int i = 0; i < 50; ++i) points.push_back(uniform_in_box(rng, -1e4f, 1e4f));
    std::vector<Vec3> queries = {{-1.25f, 0.5f, -0.75f}, {-1.2f, 0.5f, -0.75f}, {0.4f, -0.2f, 0.1f}};
    for (int i = 0; i < 100; ++i) queries.push_back(Vec3(0.4f, -0.2f, 0.1f) + uniform_in_box(rng, -0.02f, 0.02f));
    for (int i = 0; i < 50; ++i) queries.push_back(points[250 + i] + uniform_in_box(rng, -0.01f, 0.01f));
    for (float radius : {1e-3f, 0.01f, 0.06f}) EXPECT_EQ(check_queries(points, radius, queries, "clusters"), 0);
}

/// Points at exactly the radius (d·d == r·r in float: offsets that are exact binary fractions,
/// along the axes and on 3-4-5 diagonals) are inside; the next float outwards is not.
TEST(PhotonGrid, PointsAtExactlyTheRadiusAreInside) {
    const float r = 0.625f;  // 5/8
    const Vec3 q(0.5f, -0.25f, 1.f);
    std::vector<Vec3> at_r = {
        q + Vec3(r, 0, 0),  q - Vec3(r, 0, 0),  q + Vec3(0, r, 0),  q - Vec3(0, r, 0),  q + Vec3(0, 0, r),
        q - Vec3(0, 0, r),  q + Vec3(0.375f, 0.5f, 0), q + Vec3(-0.375f, 0, -0.5f), q + Vec3(0, -0.5f, 0.375f),
    };
    std::vector<Vec3> points = at_r;
    // Just outside: the next float beyond q.x + r (so the stored point is farther than r).
    points.push_back({std::nextafter(q.x + r, 10.f), q.y, q.z});
    points.push_back({q.x, std::nextafter(q.y - r, -10.f), q.z});
    for (const Vec3& p : at_r) {
        const Vec3 d = p - q;
        ASSERT_EQ(dot(d, d), r * r) << "the offsets must be exact";
    }
    PhotonGrid grid;
    grid.build(points, r);
    const std::vector<int> got = visits(grid, points.size(), q);
    for (std::size_t i = 0; i < at_r.size(); ++i) EXPECT_EQ(got[i], 1) << "point " << i << " at distance r";
    for (std::size_t i = at_r.size(); i < points.size(); ++i) {
        const Vec3 d = points[i] - q;
        ASSERT_GT(dot(d, d), r * r);
        EXPECT_EQ(got[i], 0) << "point " << i << " beyond r";
    }
}

/// Found by this test on the first PhotonGrid (16 misses in 1200 queries; e.g. r = 0.03, query
/// (0.21, −0.99, −0.15), point (0.21, −0.96, −0.15) at d² ≤ r² not visited): the query read
/// cells floor((p − r)/(2r)) and the next one while the point lies in floor(q/(2r)); with
/// rounding the point's cell was a third one. The query now widens its range by the rounding.
///
/// Points at distance r (to float rounding) from queries anywhere, with radii whose cell size
/// 2r is not a binary fraction: the cells a query reads are derived from (p − r)/(2r) and a
/// point's cell from its own coordinate/(2r), both rounded, so a point on the sphere of
/// radius r lying near a cell boundary is where a miss would show.
TEST(PhotonGrid, PointsNearTheRadiusOnCellBoundaries) {
    std::mt19937 rng(4242);
    int wrong = 0;
    for (float radius : {0.1f, 0.03f, 0.7f, 1.3f}) {
        std::vector<Vec3> points, queries;
        std::uniform_real_distribution<float> u(-1.f, 1.f);
        for (int k = 0; k < 300; ++k) {
            // Query on a cell boundary shifted by r (so p ± r falls on a boundary too).
            const float cell = 2.f * radius;
            const Vec3 base(std::round(u(rng) * 20.f) * cell + radius, std::round(u(rng) * 20.f) * cell - radius,
                            std::round(u(rng) * 20.f) * cell + radius);
            const Vec3 q = base + Vec3(u(rng), u(rng), u(rng)) * (1e-6f * radius);
            queries.push_back(q);
            for (int axis = 0; axis < 3; ++axis)
                for (float sign : {-1.f, 1.f}) {
                    Vec3 offset(0, 0, 0);
                    (axis == 0 ? offset.x : axis == 1 ? offset.y : offset.z) = sign * radius;
                    points.push_back(q + offset);
                }
        }
        wrong += check_queries(points, radius, queries, "radius " + std::to_string(radius));
    }
    EXPECT_EQ(wrong, 0);
}

/// Far from the origin relative to the radius (a scene placed at x ≈ 1000 rendered with a
/// merging radius of 0.01): cell coordinates are ~5·10⁴ cells, where a float's rounding is
/// ~0.004 cell, so a point well inside the radius (d ≤ 0.99 r) near a cell boundary may fall
/// in a cell the query does not read.
TEST(PhotonGrid, MatchesBruteForceFarFromTheOrigin) {
    std::mt19937 rng(99);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    int wrong = 0;
    for (float centre : {1000.f, -3000.f}) {
        const float radius = 0.01f;
        std::vector<Vec3> points, queries;
        for (int k = 0; k < 2000; ++k) {
            const Vec3 q = Vec3(centre, centre, centre) + Vec3(u(rng), u(rng), u(rng)) * 5.f;
            queries.push_back(q);
            // Points on the six axis directions at 0.99 r.
            for (int axis = 0; axis < 3; ++axis)
                for (float sign : {-1.f, 1.f}) {
                    Vec3 offset(0, 0, 0);
                    (axis == 0 ? offset.x : axis == 1 ? offset.y : offset.z) = sign * 0.99f * radius;
                    points.push_back(q + offset);
                }
        }
        wrong += check_queries(points, radius, queries, "centre " + std::to_string(centre));
    }
    EXPECT_EQ(wrong, 0);
}

/// Queries far beyond the float resolution of the cells (camera hits near the horizon of an
/// infinite plane: 1e12–1e30 with r = 0.01) read at most 27 cells and never visit a point
/// outside the radius; the first PhotonGrid looped over ~2^39 cells per axis there and
/// overflowed its bucket list (found by the 512² glass-spheres vcm run).
TEST(PhotonGrid, QueriesFarFromTheOriginStayBounded) {
    const float r = 0.01f;
    std::vector<Vec3> points;
    for (float x : {1e12f, 4.6e18f, 1e30f, -3e20f})
        for (int k = 0; k < 4; ++k) points.push_back({x, 0.003f * static_cast<float>(k), -x});
    points.push_back({0, 0, 0});
    PhotonGrid grid;
    grid.build(points, r);
    for (const Vec3& q : points) {
        std::vector<int> got = visits(grid, points.size(), q);
        const std::vector<int> want = brute_force(points, q, r);
        for (std::size_t i = 0; i < points.size(); ++i) EXPECT_LE(got[i], want[i]) << i;
        EXPECT_EQ(got[points.size() - 1], want[points.size() - 1]);
    }
}

// ---- MergePass: photons, subpath bounds, eta ----

BdptVertex surface_vertex(int material, const Vec3& p) {
    BdptVertex v;
    v.type = BdptVertexType::surface;
    v.hit.p = p;
    v.hit.n = {0, 1, 0};
    v.hit.material = material;
    return v;
}

/// Two batches, three subpaths: photons are the surface vertices from the second bounce of
/// light on (light index ≥ 2: not the origin, not the first hit) on materials with a diffuse
/// lobe (not a mirror, not glass), in the grid's order; eta is the one given.
TEST(PhotonGrid, MergePassIndexesDiffuseSurfaceVertices) {
    Scene scene;
    const int diffuse = scene.add_material(test::diffuse_material(0.5));
    const int mirror = scene.add_material(test::mirror_material());
    const int glass = scene.add_material(test::glass_material(1.5));
    scene.finalize();
    BdptVertex origin;
    origin.type = BdptVertexType::light;
    origin.hit.p = {0, 2, 0};

    std::vector<LightSubpathBatch> batches(2);
    // Batch 0: subpath 0 = origin, diffuse, mirror, diffuse; subpath 1 = origin alone.
    batches[0].vertices = {origin, surface_vertex(diffuse, {0, 0, 0}), surface_vertex(mirror, {1, 0, 0}),
                           surface_vertex(diffuse, {2, 0, 0}), origin};
    batches[0].ends = {4, 5};
    // Batch 1: subpath 2 = origin, glass, diffuse, diffuse.
    batches[1].vertices = {origin, surface_vertex(glass, {0, 1, 0}), surface_vertex(diffuse, {0.01f, 0, 0}),
                           surface_vertex(diffuse, {0.02f, 0, 0})};
    batches[1].ends = {4};

    MergePass pass;
    const float r = 0.05f, eta = std::numbers::pi_v<float> * r * r * 3.f;
    pass.build(batches, scene, r, eta);
    // Photons: subpath 0's vertex 3 (s = 4) and subpath 2's vertices 2 and 3 (s = 3, 4); not
    // subpath 0's first hit, the mirror or the glass.
    EXPECT_EQ(pass.photon_count(), 3u);
    const MergeContext mc = pass.context();
    EXPECT_EQ(mc.vertices.size(), 9u);
    EXPECT_EQ(mc.path_begin, (std::vector<std::uint32_t>{0, 4, 5, 9}));
    ASSERT_EQ(mc.photons.size(), 3u);
    EXPECT_FLOAT_EQ(mc.eta, eta);
    EXPECT_EQ(mc.grid.size(), 3u);
    EXPECT_FLOAT_EQ(mc.grid.radius(), r);
    // Grid slot j holds photons[j]: the records follow the grid's order.
    for (std::size_t j = 0; j < mc.photons.size(); ++j) {
        const Vec3 p = mc.photons[j].p;
        int hits = 0;
        mc.grid.query(p, [&](std::uint32_t k, float d2) { hits += k == j && d2 == 0.f; });
        EXPECT_EQ(hits, 1) << j;
    }
    // Around (0.015, 0, 0): the photons at 0.01 and 0.02 (s = 3 and 4), not (2, 0, 0).
    std::vector<int> found;
    mc.grid.query({0.015f, 0, 0}, [&](std::uint32_t j, float) { found.push_back(mc.photons[j].s); });
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, (std::vector<int>{3, 4}));
}

}  // namespace
}  // namespace spt

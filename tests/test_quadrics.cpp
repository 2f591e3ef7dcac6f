// Disks, cylinders and cones (and the surface API shared with spheres and triangles), modelled
// on the sphere tests of test_geometry.cpp: analytic hits (including the far shape of
// ROBUSTNESS.md case 5), reintersection at scales 10^±4 (case 1), unit outward normals, area,
// uniform area sampling (χ² over equal-area cells; samples on the surface within p_err), (u, v)
// in [0, 1]², conservative bounds, and the BVH over all five bounded kinds against brute force.
// References are computed in long double from the same float inputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "chi2.h"
#include "uniform.h"
#include "geometry/bvh.h"

namespace spt {
namespace {

using LD = long double;

/// The geometry tests' random configurations, plus directions in double.
class Uniform : public spt_test::Uniform {
public:
    using spt_test::Uniform::Uniform;
    DVec3 dir() {
        const double z = 1.0 - 2.0 * next(), phi = 2.0 * kPiDouble * next();
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        return {r * std::cos(phi), r * std::sin(phi), z};
    }
    Vec3 unit_float_dir() { return normalize(dir().to_float()); }
};

struct LVec {
    LD x = 0, y = 0, z = 0;
};
LVec lv(const Vec3& v) { return {v.x, v.y, v.z}; }
LVec operator-(const LVec& a, const LVec& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
LVec operator+(const LVec& a, const LVec& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
LVec operator*(LD s, const LVec& a) { return {s * a.x, s * a.y, s * a.z}; }
LD dot(const LVec& a, const LVec& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
LD len(const LVec& a) { return std::sqrt(dot(a, a)); }
LVec unit(const LVec& a) { return (1 / len(a)) * a; }
LVec cross(const LVec& a, const LVec& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/// Some unit vector perpendicular to the unit n.
LVec perpendicular(const LVec& n) {
    return unit(std::fabs(n.x) < 0.5L ? cross(n, LVec{1, 0, 0}) : cross(n, LVec{0, 1, 0}));
}

/// Per-shape helpers of the tests: random configurations, surface points with their outward
/// normals, the analytic area, distance to the surface, and area coordinates (uniform on
/// [0, 1]² for points uniform by area) from the shape's (u, v).
template <typename S>
struct Shape;

template <>
struct Shape<Disk> {
    static Disk random(Uniform& rng, double lo, double hi) {
        return {rng.signed_log_point(lo, hi), rng.unit_float_dir(), float(rng.log_uniform(lo, hi)), 0};
    }
    static LD area(const Disk& d) { return kPiDouble * LD(d.radius) * d.radius; }
    /// Point at (ρ/r)² = s1 (away from the rim) and angle 2π·s2; the normal facing `side`.
    static void point(const Disk& d, double s1, double s2, LVec& p, LVec& n) {
        n = unit(lv(d.normal));
        const LVec e1 = perpendicular(n), e2 = cross(n, e1);
        const LD rho = d.radius * std::sqrt(0.9L * s1), phi = 2 * kPiDouble * s2;
        p = lv(d.center) + (rho * std::cos(phi)) * e1 + (rho * std::sin(phi)) * e2;
    }
    static LD distance(const Disk& d, const Vec3& p) {
        const LVec n = unit(lv(d.normal)), q = lv(p) - lv(d.center);
        const LD h = dot(q, n), rho = len(q - h * n);
        return std::sqrt(h * h + sqr(std::max(LD(0), rho - d.radius)));
    }
    static bool outward(const Disk& d, const Vec3&, const Vec3& n) { return n == d.normal; }
    static void area_coords(float u, float v, double& a, double& b) { a = double(v) * v, b = u; }
    static LD size(const Disk& d) { return d.radius; }
};

template <>
struct Shape<Cylinder> {
    static Cylinder random(Uniform& rng, double lo, double hi) {
        const float r = float(rng.log_uniform(lo, hi));
        return {rng.signed_log_point(lo, hi), rng.unit_float_dir(), r, float(r * rng.log_uniform(-1, 1)), 0};
    }
    static LD area(const Cylinder& c) { return 2 * kPiDouble * LD(c.radius) * c.height; }
    /// Point at height s1 (away from the rims) and angle 2π·s2, with the outward normal.
    static void point(const Cylinder& c, double s1, double s2, LVec& p, LVec& n) {
        const LVec a = unit(lv(c.axis)), e1 = perpendicular(a), e2 = cross(a, e1);
        const LD phi = 2 * kPiDouble * s2;
        n = std::cos(phi) * e1 + std::sin(phi) * e2;
        p = lv(c.base) + (c.height * (0.05L + 0.9L * s1)) * a + LD(c.radius) * n;
    }
    static LD distance(const Cylinder& c, const Vec3& p) {
        const LVec a = unit(lv(c.axis)), q = lv(p) - lv(c.base);
        const LD z = dot(q, a), rho = len(q - z * a);
        const LD dz = z < 0 ? -z : (z > c.height ? z - c.height : 0);
        return std::sqrt(sqr(rho - c.radius) + dz * dz);
    }
    static bool outward(const Cylinder& c, const Vec3& p, const Vec3& n) {
        const LVec a = unit(lv(c.axis)), q = lv(p) - lv(c.base);
        return dot(lv(n), q - dot(q, a) * a) > 0 && std::fabs(dot(lv(n), a)) < 1e-6L;
    }
    /// Strictly outside the infinite solid cylinder: the hit from there is an entry.
    static bool strictly_outside(const Cylinder& c, const Vec3& o) {
        const LVec a = unit(lv(c.axis)), q = lv(o) - lv(c.base);
        return len(q - dot(q, a) * a) > c.radius;
    }
    static void area_coords(float u, float v, double& a, double& b) { a = v, b = u; }
    static LD size(const Cylinder& c) { return LD(c.radius) + c.height; }
};

template <>
struct Shape<Cone> {
    static Cone random(Uniform& rng, double lo, double hi) {
        const float r = float(rng.log_uniform(lo, hi));
        return {rng.signed_log_point(lo, hi), rng.unit_float_dir(), r, float(r * rng.log_uniform(-1, 1)), 0};
    }
    static LD slant(const Cone& c) { return std::sqrt(LD(c.radius) * c.radius + LD(c.height) * c.height); }
    static LD area(const Cone& c) { return kPiDouble * LD(c.radius) * slant(c); }
    /// Point at a fraction w = 0.05 + 0.9·s1 of the slant from the apex, angle 2π·s2.
    static void point(const Cone& c, double s1, double s2, LVec& p, LVec& n) {
        const LVec a = unit(lv(c.axis)), e1 = perpendicular(a), e2 = cross(a, e1);
        const LD phi = 2 * kPiDouble * s2, w = 0.05L + 0.9L * s1;
        const LVec e = std::cos(phi) * e1 + std::sin(phi) * e2;
        p = lv(c.base) + (c.height * (1 - w)) * a + (c.radius * w) * e;
        n = (1 / slant(c)) * (LD(c.height) * e + LD(c.radius) * a);
    }
    /// Distance to the generator segment in the half-plane of p.
    static LD distance(const Cone& c, const Vec3& p) {
        const LVec a = unit(lv(c.axis)), q = lv(p) - lv(c.base);
        const LD z = dot(q, a), rho = len(q - z * a), r = c.radius, h = c.height;
        const LD s = std::clamp(((r - rho) * r + z * h) / (r * r + h * h), LD(0), LD(1));
        return std::sqrt(sqr(rho - r * (1 - s)) + sqr(z - h * s));
    }
    static bool outward(const Cone& c, const Vec3& p, const Vec3& n) {
        const LVec a = unit(lv(c.axis)), q = lv(p) - lv(c.base);
        return dot(lv(n), q - dot(q, a) * a) >= 0 && dot(lv(n), a) > 0;
    }
    /// Strictly outside the infinite solid one-nappe cone below the apex.
    static bool strictly_outside(const Cone& c, const Vec3& o) {
        const LVec a = unit(lv(c.axis)), q = lv(o) - lv(c.base);
        const LD z = dot(q, a), rho = len(q - z * a);
        return z > c.height || rho > LD(c.radius) * (c.height - z) / c.height;
    }
    static void area_coords(float u, float v, double& a, double& b) { a = (1.0 - v) * (1.0 - v), b = u; }
    static LD size(const Cone& c) { return LD(c.radius) + c.height; }
};

template <>
struct Shape<Sphere> {
    static Sphere random(Uniform& rng, double lo, double hi) {
        return {rng.signed_log_point(lo, hi), float(rng.log_uniform(lo, hi)), 0};
    }
    static LD area(const Sphere& s) { return 4 * kPiDouble * LD(s.radius) * s.radius; }
    static LD distance(const Sphere& s, const Vec3& p) { return std::fabs(len(lv(p) - lv(s.center)) - s.radius); }
    static LD size(const Sphere& s) { return s.radius; }
    static bool outward(const Sphere& s, const Vec3& p, const Vec3& n) { return dot(lv(n), lv(p) - lv(s.center)) > 0; }
    /// Archimedes: the height (1 − cos θ)/2 is uniform.
    static void area_coords(float u, float v, double& a, double& b) { a = (1.0 - std::cos(kPiDouble * v)) / 2, b = u; }
};

template <>
struct Shape<Triangle> {
    static Triangle random(Uniform& rng, double lo, double hi) {
        while (true) {  // new position and size until the triangle is resolved by floats
            const Vec3 c = rng.signed_log_point(lo, hi);
            const float s = float(rng.log_uniform(lo, hi));
            const Triangle t{c + rng.unit_float_dir() * s, c + rng.unit_float_dir() * s, c + rng.unit_float_dir() * s, 0};
            if (t.area() > 0.05f * s * s) return t;
        }
    }
    static LD area(const Triangle& t) { return len(cross(lv(t.p1) - lv(t.p0), lv(t.p2) - lv(t.p0))) / 2; }
    static LD distance(const Triangle& t, const Vec3& p) {
        const LVec n = unit(cross(lv(t.p1) - lv(t.p0), lv(t.p2) - lv(t.p0)));
        return std::fabs(dot(lv(p) - lv(t.p0), n));
    }
    static LD size(const Triangle& t) { return std::sqrt(area(t)); }
    static bool outward(const Triangle& t, const Vec3&, const Vec3& n) {
        return dot(lv(n), cross(lv(t.p1) - lv(t.p0), lv(t.p2) - lv(t.p0))) > 0;
    }
    /// (b1, b2) uniform on b1 + b2 ≤ 1: s = b1 + b2 has density 2s, so s² is uniform, and
    /// b1/s is uniform given s.
    static void area_coords(float u, float v, double& a, double& b) {
        const double sum = double(u) + v;
        a = sum * sum, b = sum > 0.0 ? u / sum : 0.0;
    }
};

bool inside(const Aabb& b, const Vec3& p) {
    return p.x >= b.lo.x && p.x <= b.hi.x && p.y >= b.lo.y && p.y <= b.hi.y && p.z >= b.lo.z && p.z <= b.hi.z;
}
LD max_abs_l(const Vec3& v) { return std::max({std::fabs(LD(v.x)), std::fabs(LD(v.y)), std::fabs(LD(v.z))}); }
/// A shape of this size is resolved by floats near p (rounding below 1e-4 of its size).
bool resolved(LD size, const Vec3& p) { return size > 1e3L * max_abs_l(p) * 0x1p-24L; }

// ---------------------------------------------------------------- analytic hits

void expect_vec(const Vec3& got, const Vec3& want, float tol) {
    EXPECT_NEAR(got.x, want.x, tol);
    EXPECT_NEAR(got.y, want.y, tol);
    EXPECT_NEAR(got.z, want.z, tol);
}

template <typename S>
void expect_hit(const S& s, const Ray& ray, double t, const Vec3& p, const Vec3& n) {
    const double got = s.intersect_t(ray);
    ASSERT_NEAR(got, t, 1e-9 * (1 + t));
    const Hit hit = s.make_hit(ray, got);
    expect_vec(hit.p, p, 1e-6f);
    expect_vec(hit.n, n, 1e-6f);
    EXPECT_EQ(hit.ns, hit.n);
    EXPECT_EQ(hit.material, s.material);
    EXPECT_EQ(hit.light, s.light);
}

TEST(Disk, AnalyticHitsBothSidesAndMisses) {
    Disk d{{1, 2, 3}, {0, 0, 1}, 2.f, 4, 7};
    expect_hit(d, {{1.5f, 2, 10}, {0, 0, -1}}, 7.0, {1.5f, 2, 3}, {0, 0, 1});
    expect_hit(d, {{1.5f, 2, -1}, {0, 0, 1}}, 4.0, {1.5f, 2, 3}, {0, 0, 1});  // back side: same n
    EXPECT_EQ(d.intersect_t({{3.5f, 2, 10}, {0, 0, -1}}), kInfinity);        // ρ = 2.5
    EXPECT_EQ(d.intersect_t({{1, 2, 10}, {0, 0, 1}}), kInfinity);             // pointing away
    EXPECT_EQ(d.intersect_t({{0, 2, 3}, {1, 0, 0}}), kInfinity);              // in the plane
    const Disk tilted{{0, 0, 0}, normalize(Vec3(1, 1, 1)), 1.f};
    const Ray diagonal{{5, 5, 5}, normalize(Vec3(-1, -1, -1))};  // t from the rounded direction
    const LD t_diag = -(LD(5) * 3) / (LD(diagonal.d.x) + diagonal.d.y + diagonal.d.z);
    expect_hit(tilted, diagonal, double(t_diag), {0, 0, 0}, tilted.normal);
    // Far disk: unit disk 1e4 away, hit at 0.5 off centre.
    const Disk far{{0, 0, 1e4f}, {0, 0, -1}, 1.f};
    expect_hit(far, {{0.5f, 0, 0}, {0, 0, 1}}, 1e4, {0.5f, 0, 1e4f}, {0, 0, -1});
}

TEST(Cylinder, AnalyticHitsInsideOutsideAndFar) {
    const Cylinder c{{0, 0, 0}, {0, 1, 0}, 1.f, 2.f, 3, 5};
    expect_hit(c, {{-5, 1, 0}, {1, 0, 0}}, 4.0, {-1, 1, 0}, {-1, 0, 0});
    expect_hit(c, {{0, 1, 0}, {1, 0, 0}}, 1.0, {1, 1, 0}, {1, 0, 0});  // from inside: n still outward
    const Vec3 d = normalize(Vec3(0.5f, -1, 0));                        // in through the open top
    expect_hit(c, {{0, 3, 0}, d}, 1.0 / d.x, {1, 3 + d.y / d.x, 0}, {1, 0, 0});
    EXPECT_EQ(c.intersect_t({{-5, 2.5f, 0}, {1, 0, 0}}), kInfinity);    // above the top
    EXPECT_EQ(c.intersect_t({{0, 5, 0}, {0, -1, 0}}), kInfinity);       // along the axis
    EXPECT_EQ(c.intersect_t({{-5, 1, 1.01f}, {1, 0, 0}}), kInfinity);   // passes beside
    // ROBUSTNESS case 5 for a tube: unit radius 1e4 away, rays 0.5 and 0.99 off the axis.
    const Cylinder far{{0, -1, 1e4f}, {0, 1, 0}, 1.f, 2.f};
    for (float h : {0.5f, 0.99f}) {
        const double t = far.intersect_t({{h, 0, 0}, {0, 0, 1}});
        EXPECT_NEAR(t, 1e4 - std::sqrt(1.0 - double(h) * h), 1e-9) << h;
    }
    EXPECT_EQ(far.intersect_t({{1.01f, 0, 0}, {0, 0, 1}}), kInfinity);
}

TEST(Cone, AnalyticHitsInsideOutsideAndFar) {
    const Cone c{{0, 0, 0}, {0, 1, 0}, 1.f, 1.f, 2, 6};
    const float s = 1.f / std::sqrt(2.f);
    expect_hit(c, {{-5, 0.5f, 0}, {1, 0, 0}}, 4.5, {-0.5f, 0.5f, 0}, {-s, s, 0});
    expect_hit(c, {{0, 0.25f, 0}, {1, 0, 0}}, 0.75, {0.75f, 0.25f, 0}, {s, s, 0});  // from inside
    EXPECT_EQ(c.intersect_t({{-5, 1.5f, 0}, {1, 0, 0}}), kInfinity);   // the other nappe: not part of it
    EXPECT_EQ(c.intersect_t({{-5, -0.5f, 0}, {1, 0, 0}}), kInfinity);  // below the base
    // Through the open base from below, meeting the inside at height 0.5.
    expect_hit(c, {{0.5f, -3, 0}, {0, 1, 0}}, 3.5, {0.5f, 0.5f, 0}, {s, s, 0});
    // A cone 1e4 away: slope 1, ray parallel to the base plane at height 0.5 (radius 0.5 there).
    const Cone far{{0, -0.5f, 1e4f}, {0, 1, 0}, 1.f, 1.f};
    for (float h : {0.25f, 0.49f}) {
        const double t = far.intersect_t({{h, 0, 0}, {0, 0, 1}});
        EXPECT_NEAR(t, 1e4 - std::sqrt(0.25 - double(h) * h), 1e-9) << h;
    }
    EXPECT_EQ(far.intersect_t({{0.51f, 0, 0}, {0, 0, 1}}), kInfinity);
}

// ---------------------------------------------------------------- robustness at every scale

template <typename S>
class QuadricShape : public ::testing::Test {};
using QuadricTypes = ::testing::Types<Disk, Cylinder, Cone>;
struct ShapeNames {
    template <typename T>
    static std::string GetName(int) {
        if (std::is_same_v<T, Disk>) return "Disk";
        if (std::is_same_v<T, Cylinder>) return "Cylinder";
        if (std::is_same_v<T, Cone>) return "Cone";
        if (std::is_same_v<T, Sphere>) return "Sphere";
        return "Triangle";
    }
};
TYPED_TEST_SUITE(QuadricShape, QuadricTypes, ShapeNames);

/// A ray from outside at a random surface point (origin up to 100 sizes away in the outward
/// half-space), or nothing when the float origin is not strictly outside (shapes below float
/// resolution at their position).
template <typename S>
bool outside_ray(Uniform& rng, const S& s, Ray& ray) {
    LVec p, n;
    Shape<S>::point(s, rng.next(), rng.next(), p, n);
    const DVec3 w0 = rng.dir();
    LVec w{w0.x, w0.y, w0.z};
    if constexpr (std::is_same_v<S, Disk>) {
        if (rng.next() < 0.5) n = -1 * n;  // either side of a disk
    }
    if (dot(w, n) < 0) w = -1 * w;
    const LD dist = Shape<S>::size(s) * rng.log_uniform(-1, 2);
    const LVec o = p + dist * w, dir = unit(p - o);
    ray = {Vec3(float(o.x), float(o.y), float(o.z)), normalize(Vec3(float(dir.x), float(dir.y), float(dir.z)))};
    if constexpr (std::is_same_v<S, Disk>) {
        const LD side = dot(lv(ray.o) - lv(s.center), unit(lv(s.normal)));
        return side != 0 && (side > 0) == (dot(n, unit(lv(s.normal))) > 0);
    } else {
        return Shape<S>::strictly_outside(s, ray.o);
    }
}

/// A random shape at scales 10^±4, a ray from outside it (outside_ray) and the hit it finds,
/// or nothing when the configuration gives no such ray or the ray misses.
template <typename S>
struct OutsideHit {
    S shape;
    Ray ray;
    double t;
    Hit hit;
};
template <typename S>
std::optional<OutsideHit<S>> random_outside_hit(Uniform& rng) {
    const S s = Shape<S>::random(rng, -4, 4);
    Ray ray;
    if (!outside_ray(rng, s, ray)) return std::nullopt;
    const double t = s.intersect_t(ray);
    if (t == kInfinity) return std::nullopt;
    return OutsideHit<S>{s, ray, t, s.make_hit(ray, t)};
}

TYPED_TEST(QuadricShape, ReintersectionOutgoingRaysEscape) {
    // ROBUSTNESS case 1 for the new shapes: sizes 10^U(−4,4), positions ±10^U(−4,4). A ray
    // from outside hits the shape; 200 rays spawned into the hemisphere it came from must
    // never hit it again (the convex side of a tube or cone, either side of a disk; disks also
    // on the far side). 0 self-hits.
    using S = TypeParam;
    Uniform rng(2024);
    int configurations = 0, self_hits = 0, rays = 0;
    for (int cfg = 0; cfg < 400; ++cfg) {
        const std::optional<OutsideHit<S>> h = random_outside_hit<S>(rng);
        if (!h) continue;
        const auto& [s, ray, t, hit] = *h;
        // Skipped: shapes below float resolution at their position, where the rounded ray
        // can enter a tube or cone through its open end and hit it from inside.
        if (!std::is_same_v<S, Disk> && !(dot(ray.d, hit.n) < 0.f)) continue;
        ++configurations;
        const Vec3 n_out = dot(ray.d, hit.n) < 0.f ? hit.n : -hit.n;
        const bool both_sides = std::is_same_v<S, Disk>;
        for (int i = 0; i < 200; ++i) {
            const Vec3 n_side = both_sides && i % 2 ? -n_out : n_out;
            Vec3 w = rng.unit_float_dir();
            if (dot(w, n_side) < 0.f) w = -w;
            if (!(dot(w, n_side) > 0.f)) continue;
            ++rays;
            if (s.intersect_t(spawn_ray(hit, w)) < kInfinity) ++self_hits;
        }
    }
    EXPECT_GT(configurations, 250);
    EXPECT_EQ(self_hits, 0) << "of " << rays << " rays in " << configurations << " configurations";
}

TYPED_TEST(QuadricShape, HitsAreOnTheSurfaceWithUnitOutwardNormalsAtEveryScale) {
    // For rays from outside at scales 10^±4: the hit point lies within its p_err of the surface
    // (long double), t agrees with the distance to that point, and the normal is unit to
    // float precision and outward (a ray from outside meets a tube or cone against it).
    using S = TypeParam;
    Uniform rng(77);
    int hits = 0;
    LD worst_len = 0, worst_dist = 0;
    for (int cfg = 0; cfg < 2000; ++cfg) {
        const std::optional<OutsideHit<S>> h = random_outside_hit<S>(rng);
        if (!h) continue;
        const auto& [s, ray, t, hit] = *h;
        // Directions only where the shape is resolved by floats at its position: elsewhere the
        // rounded ray can enter through an open end, and the float point has no direction.
        if (!resolved(Shape<S>::size(s), hit.p)) continue;
        ++hits;
        worst_len = std::max(worst_len, std::fabs(len(lv(hit.n)) - 1));
        const LD dist = Shape<S>::distance(s, hit.p);
        worst_dist = std::max(worst_dist, dist / len(lv(hit.p_err)));
        EXPECT_LE(dist, len(lv(hit.p_err))) << "cfg " << cfg;
        if constexpr (!std::is_same_v<S, Disk>) {
            EXPECT_LT(dot(hit.n, ray.d), 0.f) << "cfg " << cfg;
        }
        EXPECT_TRUE(Shape<S>::outward(s, hit.p, hit.n)) << "cfg " << cfg;
        // t is the distance to the (unprojected) hit point: within float rounding of |p| + |o|.
        const LD t_ref = len(lv(hit.p) - lv(ray.o));
        EXPECT_NEAR(LD(t), t_ref, 1e-5L * (max_abs_l(ray.o) + max_abs_l(hit.p))) << "cfg " << cfg;
    }
    EXPECT_GT(hits, 1000);
    EXPECT_LT(worst_len, 0x1p-22L) << "largest | |n| - 1 |";
    std::printf("[ stats    ] largest distance to the surface / |p_err|: %.3Lg\n", worst_dist);
}

TYPED_TEST(QuadricShape, FarAxisAlignedRaysHitOnTheSurface) {
    // A small shape (10^U(−4,0)) near the origin, shot from 10^U(4,8) away along ±x, ±y or
    // ±z through a float point of its surface: the ray is exact, o + t·d is not (its double
    // rounding, ~1e-16·t, dwarfs the shape's own p_err), so only the reprojection onto the
    // surface keeps the hit point within p_err (long double distance).
    using S = TypeParam;
    Uniform rng(404);
    int hits = 0, off_surface = 0;
    for (int cfg = 0; cfg < 1000; ++cfg) {
        const S s = Shape<S>::random(rng, -4, 0);
        LVec p, n;
        Shape<S>::point(s, rng.next(), rng.next(), p, n);
        const int axis = cfg % 3;
        const float sign = rng.sign() > 0 ? 1.f : -1.f;
        Vec3 o(float(p.x), float(p.y), float(p.z)), d(0, 0, 0);
        o[axis] += sign * float(rng.log_uniform(4, 8));
        d[axis] = -sign;
        const double t = s.intersect_t({o, d});
        if (t == kInfinity) continue;
        ++hits;
        const Hit hit = s.make_hit({o, d}, t);
        if (Shape<S>::distance(s, hit.p) > len(lv(hit.p_err))) ++off_surface;
    }
    EXPECT_GT(hits, 500);
    EXPECT_EQ(off_surface, 0) << "of " << hits;
}

// ---------------------------------------------------------------- area, sampling, (u, v), bounds

template <typename S>
class QuadricSurface : public ::testing::Test {};
using SurfaceTypes = ::testing::Types<Disk, Cylinder, Cone, Sphere, Triangle>;
TYPED_TEST_SUITE(QuadricSurface, SurfaceTypes, ShapeNames);

TYPED_TEST(QuadricSurface, AreaMatchesTheAnalyticFormula) {
    using S = TypeParam;
    Uniform rng(5);
    for (int i = 0; i < 200; ++i) {
        const S s = Shape<S>::random(rng, -4, 4);
        const LD want = Shape<S>::area(s);
        EXPECT_NEAR(s.area() / want, 1.0L, 1e-6L) << i;
    }
}

TYPED_TEST(QuadricSurface, SampleAreaIsUniformOnTheSurfaceAndInsideTheBounds) {
    // 200,000 samples of one shape binned in 16×16 cells of equal area (the shape's (u, v)
    // mapped to area coordinates): χ² at α = 0.002 (0.01 Šidák-corrected over the five kinds).
    // Every sample lies on the surface within |p_err|, has a unit outward normal, (u, v) in
    // [0, 1]² and lies inside bounds(shape); also at 10^±4 scales and at u = 0 and u → 1.
    using S = TypeParam;
    Uniform rng(31);
    const S s = Shape<S>::random(rng, 0, 0);
    constexpr int kCells = 16, kSamples = 200000;
    std::vector<double> counts(kCells * kCells, 0.0);
    const Aabb box = bounds(s);
    int off_surface = 0, outside_box = 0, bad_uv = 0, bad_normal = 0;
    auto check = [&](const S& shape, const Aabb& b, const SurfaceSample& x, bool direction = true) {
        if (Shape<S>::distance(shape, x.p) > len(lv(x.p_err))) ++off_surface;
        if (!inside(b, x.p)) ++outside_box;
        if (std::fabs(length(x.n) - 1.f) > 1e-6f) ++bad_normal;
        if (direction && resolved(Shape<S>::size(shape), x.p) && !Shape<S>::outward(shape, x.p, x.n)) ++bad_normal;
        float u = -1, v = -1;
        shape.uv(x.p, u, v);
        if (!(u >= 0.f && u <= 1.f && v >= 0.f && v <= 1.f)) ++bad_uv;
        return std::pair{u, v};
    };
    for (int i = 0; i < kSamples; ++i) {
        const SurfaceSample x = s.sample_area(float(rng.next()), float(rng.next()));
        const auto [u, v] = check(s, box, x);
        double a, b;
        Shape<S>::area_coords(u, v, a, b);
        const int ia = std::clamp(int(a * kCells), 0, kCells - 1), ib = std::clamp(int(b * kCells), 0, kCells - 1);
        counts[ia * kCells + ib] += 1;
    }
    const std::vector<double> expected(kCells * kCells, double(kSamples) / (kCells * kCells));
    const spt_test::Chi2Result r = spt_test::chi2_test(counts, expected);
    EXPECT_GE(r.p_value, 0.002) << "X2=" << r.statistic << " dof=" << r.dof;
    // Every scale, and the ends of the unit square.
    for (int cfg = 0; cfg < 500; ++cfg) {
        const S shape = Shape<S>::random(rng, -4, 4);
        const Aabb b = bounds(shape);
        for (float u1 : {0.f, float(rng.next()), 0x1.fffffep-1f})
            for (float u2 : {0.f, float(rng.next()), 0x1.fffffep-1f})  // (the cone's apex: no direction)
                check(shape, b, shape.sample_area(u1, u2), !(std::is_same_v<S, Cone> && u1 == 0.f));
    }
    EXPECT_EQ(off_surface, 0);
    EXPECT_EQ(outside_box, 0);
    EXPECT_EQ(bad_normal, 0);
    EXPECT_EQ(bad_uv, 0);
}

// ---------------------------------------------------------------- BVH over every bounded kind

struct Mix {
    std::vector<Sphere> spheres;
    std::vector<Triangle> triangles;
    std::vector<Disk> disks;
    std::vector<Cylinder> cylinders;
    std::vector<Cone> cones;
    BvhShapes view() const { return BvhShapes::of_arrays(spheres, triangles, disks, cylinders, cones); }
};

Mix random_mix(Uniform& rng, int n) {
    auto point = [&] { return Vec3(float(rng.next()), float(rng.next()), float(rng.next())) * 10.f - Vec3(5, 5, 5); };
    auto size = [&] { return float(0.02 + rng.next() * rng.next()); };
    Mix m;
    for (int i = 0; i < n; ++i) {
        m.spheres.push_back({point(), size(), 0});
        const Vec3 a = point();
        m.triangles.push_back({a, a + rng.unit_float_dir() * size(), a + rng.unit_float_dir() * size(), 0});
        m.disks.push_back({point(), rng.unit_float_dir(), size(), 0});
        m.cylinders.push_back({point(), rng.unit_float_dir(), size(), 4 * size(), 0});
        m.cones.push_back({point(), rng.unit_float_dir(), size(), 4 * size(), 0});
    }
    return m;
}

bool brute_force(const Mix& m, const Ray& ray, BvhHit& hit) {
    double t_best = ray.t_max;
    bool found = false;
    auto take = [&](double t, ShapeKind kind, std::size_t i) {
        if (t < t_best) t_best = t, hit.prim = PrimId(kind, static_cast<std::uint32_t>(i)), found = true;
    };
    for (std::size_t i = 0; i < m.spheres.size(); ++i) take(m.spheres[i].intersect_t(ray), ShapeKind::sphere, i);
    for (std::size_t i = 0; i < m.triangles.size(); ++i)
        take(m.triangles[i].intersect_t(ray, t_best), ShapeKind::triangle, i);
    for (std::size_t i = 0; i < m.disks.size(); ++i) take(m.disks[i].intersect_t(ray), ShapeKind::disk, i);
    for (std::size_t i = 0; i < m.cylinders.size(); ++i) take(m.cylinders[i].intersect_t(ray), ShapeKind::cylinder, i);
    for (std::size_t i = 0; i < m.cones.size(); ++i) take(m.cones[i].intersect_t(ray), ShapeKind::cone, i);
    hit.t = t_best;
    return found;
}

TEST(QuadricBvh, NearestHitOverAllFiveKindsEqualsBruteForce) {
    Uniform rng(13);
    for (int n : {1, 5, 200}) {
        const Mix m = random_mix(rng, n);
        Bvh bvh;
        bvh.build(m.view());
        int hits[6] = {};
        for (int k = 0; k < 4000; ++k) {
            const Vec3 o = Vec3(float(rng.next()), float(rng.next()), float(rng.next())) * 14.f - Vec3(7, 7, 7);
            Ray ray{o, rng.unit_float_dir(), k % 3 == 0 ? float(2 + 10 * rng.next()) : kInfinity};
            if (k % 2) {  // aimed at a random shape's box centre, to hit the small ones often
                const std::size_t i = k / 2 % m.disks.size();
                const Aabb b = k % 4 == 1   ? bounds(m.cylinders[i])
                               : k % 8 == 3 ? bounds(m.cones[i])
                               : k % 16 == 7 ? bounds(m.disks[i])
                                             : bounds(m.triangles[i]);
                ray.d = normalize(b.centroid() - o);
            }
            BvhHit want, got;
            const bool expected = brute_force(m, ray, want);
            double t_best = ray.t_max;
            const bool have = bvh.intersect(ray, m.view(), t_best, got);
            ASSERT_EQ(have, expected) << "ray " << k;
            EXPECT_EQ(bvh.occluded(ray, m.view()), expected) << "ray " << k;
            if (!expected) continue;
            ++hits[int(want.prim.kind())];
            EXPECT_EQ(got.t, want.t) << "ray " << k;
            EXPECT_EQ(got.prim, want.prim) << "ray " << k;
        }
        if (n < 200) continue;
        for (ShapeKind kind :
             {ShapeKind::sphere, ShapeKind::triangle, ShapeKind::disk, ShapeKind::cylinder, ShapeKind::cone}) {
            EXPECT_GT(hits[int(kind)], 20) << "kind " << int(kind);
        }
    }
}

}  // namespace
}  // namespace spt

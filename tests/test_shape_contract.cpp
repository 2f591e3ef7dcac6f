// The contract of geometry/shape.h, checked for every type of the closed set (a row per type;
// a new type without a row fails EveryTypeHasARow): the nearest hit and occlusion agree (the
// shape's own test and a BVH over it, which also checks bounds()); hit points lie on the
// surface within their error bound, normals are unit and agree with sample_area's, dpdu is
// tangent and u grows along it; rays spawned from a hit do not hit the surface there again;
// area() matches a Monte Carlo estimate (Cauchy–Crofton: isotropic lines cross a surface of
// area A on average A / (2πR²) times when drawn through a disk of radius R), and the points
// sample_area draws are distributed as the lines' crossings, which are uniform by area
// (two-sample chi-square over uv cells; a planted non-uniform warp must fail it); bounds
// contain every sampled and every hit point.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include "chi2.h"
#include "core/frame.h"
#include "geometry/bvh.h"
#include "geometry/shape.h"
#include "uniform.h"

namespace {

using namespace spt;

template <typename Tuple>
struct VariantOf;
template <typename... Ts>
struct VariantOf<std::tuple<Ts...>> {
    using type = std::variant<Ts...>;
};
using AnyShape = VariantOf<ShapeTypes>::type;

struct Case {
    std::string name;
    AnyShape shape;
    Vec3 centre;   ///< of a ball that holds the shape's part the test looks at
    double radius;
};

Plane make_plane(const Vec3& n, float offset) {
    Plane p;
    p.normal = normalize(n), p.offset = offset;
    p.set_frame();
    return p;
}

std::vector<Case> cases() {
    Triangle tri;
    tri.p0 = {0.2f, -0.3f, 1.1f}, tri.p1 = {1.4f, 0.1f, 0.7f}, tri.p2 = {0.5f, 1.2f, 1.3f};
    return {
        {"sphere", Sphere{{0.3f, -0.2f, 0.5f}, 0.8f}, {0.3f, -0.2f, 0.5f}, 0.85},
        {"plane", make_plane({0.2f, 1.f, -0.3f}, 0.4f), {0.f, 0.f, 0.f}, 1.5},
        {"triangle", tri, {0.7f, 0.33f, 1.03f}, 1.0},
        {"disk", Disk{{0.1f, 0.2f, -0.3f}, normalize(Vec3{0.3f, 0.8f, 0.5f}), 0.7f}, {0.1f, 0.2f, -0.3f}, 0.75},
        {"cylinder", Cylinder{{0.f, -0.5f, 0.2f}, normalize(Vec3{0.1f, 1.f, 0.2f}), 0.4f, 1.f},
         {0.05f, 0.f, 0.3f}, 0.7},
        {"cone", Cone{{0.2f, -0.4f, 0.f}, normalize(Vec3{-0.2f, 1.f, 0.1f}), 0.6f, 0.9f}, {0.112f, 0.039f, 0.044f}, 0.8},
    };
}

// The contract's variations for triangles (barycentric intersection) in one place.
std::optional<Hit> nearest(const Triangle& t, const Ray& r) {
    const auto ti = t.intersect(r, r.t_max);
    return ti ? std::optional<Hit>(t.make_hit(*ti)) : std::nullopt;
}
template <typename T>
std::optional<Hit> nearest(const T& s, const Ray& r) {
    const double t = s.intersect_t(r);
    return t < r.t_max ? std::optional<Hit>(s.make_hit(r, t)) : std::nullopt;
}
bool occluded(const Triangle& t, const Ray& r) { return t.intersect_t(r, r.t_max) < r.t_max; }
template <typename T>
bool occluded(const T& s, const Ray& r) {
    return s.intersect_t(r) < r.t_max;
}
Vec3 dpdu(const Triangle& t, const Vec3&) { return t.p1 - t.p0; }  // u = b1 (Scene::surface_tangent)
template <typename T>
Vec3 dpdu(const T& s, const Vec3& p) {
    return s.dpdu(p);
}

// Distance of p to each surface, in double (for the on-the-surface check).
double distance(const Sphere& s, const DVec3& p) { return length(p - DVec3(s.center)) - s.radius; }
double distance(const Plane& s, const DVec3& p) { return dot(DVec3(s.normal), p) - s.offset; }
double distance(const Triangle& t, const DVec3& p) {
    const DVec3 n = normalize(cross(DVec3(t.p1) - DVec3(t.p0), DVec3(t.p2) - DVec3(t.p0)));
    return dot(n, p - DVec3(t.p0));
}
double distance(const Disk& d, const DVec3& p) { return dot(d.unit_normal(), p - DVec3(d.center)); }
double distance(const Cylinder& c, const DVec3& p) {
    const DVec3 a = c.unit_axis(), q = p - DVec3(c.base);
    return length(q - dot(q, a) * a) - c.radius;
}
double distance(const Cone& c, const DVec3& p) {
    const DVec3 a = c.unit_axis(), q = p - DVec3(c.base);
    const double z = dot(q, a), r = length(q - z * a);
    return (r - c.radius * (1.0 - z / c.height)) * c.height / c.slant();
}

bool inside(const Aabb& b, const Vec3& p) {
    return p.x >= b.lo.x && p.x <= b.hi.x && p.y >= b.lo.y && p.y <= b.hi.y && p.z >= b.lo.z && p.z <= b.hi.z;
}

Vec3 sphere_dir(spt_test::Uniform& u) {
    const double z = 1.0 - 2.0 * u.next_double(), phi = 2.0 * kPiDouble * u.next_double();
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return normalize(Vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)));
}

/// A line of the isotropic measure through the disk of radius R about the ball's centre,
/// as a ray starting outside the ball.
Ray random_line(const Case& c, spt_test::Uniform& u) {
    const Vec3 d = sphere_dir(u);
    const Frame f(d);
    const Vec3 s = f.s, t = f.t;
    const double rho = c.radius * std::sqrt(u.next_double()), phi = 2.0 * kPiDouble * u.next_double();
    const Vec3 o = c.centre + s * float(rho * std::cos(phi)) + t * float(rho * std::sin(phi)) - d * float(2.0 * c.radius);
    return {o, d, kInfinity};
}

template <typename T>
void check_hits(const Case& c, const T& shape) {
    spt_test::Uniform u(11);
    constexpr bool bounded = BoundedShape<T>;
    Bvh bvh;
    std::vector<T> one{shape};
    if constexpr (bounded) bvh.build(BvhShapes::of_arrays(one));
    int hits = 0;
    for (int i = 0; i < 4000; ++i) {
        // Aimed at a point of the surface from outside the ball.
        Vec3 target;
        if constexpr (std::is_same_v<T, Plane>) {
            target = c.centre + shape.tangent_u * float(2 * u.next_double() - 1) + shape.tangent_v * float(2 * u.next_double() - 1);
            target = target - shape.normal * (dot(shape.normal, target) - shape.offset);
        } else {
            target = shape.sample_area(u.next_float(), u.next_float()).p;
        }
        const Vec3 o = c.centre + sphere_dir(u) * float(3.0 * c.radius);
        const Ray ray{o, normalize(target - o), kInfinity};
        const std::optional<Hit> hit = nearest(shape, ray);
        if (!hit) continue;
        ++hits;
        const std::string at = c.name + " ray " + std::to_string(i);
        // On the surface within its error bound.
        EXPECT_LE(std::fabs(distance(shape, DVec3(hit->p))), 1.01 * length(hit->p_err) + 1e-12) << at;
        EXPECT_NEAR(length(hit->n), 1.f, 1e-5f) << at;
        EXPECT_EQ(hit->ns, hit->n) << at;
        // Nearest hit and occlusion agree just before and just after it, the BVH too.
        for (const double f : {0.999, 1.001}) {
            Ray shadow = ray;
            shadow.t_max = float(hit->t * f);
            EXPECT_EQ(occluded(shape, shadow), f > 1.0) << at << " t_max = t·" << f;
            if constexpr (bounded) {
                EXPECT_EQ(bvh.occluded(shadow, BvhShapes::of_arrays(one)), f > 1.0) << at;
            }
        }
        if constexpr (bounded) {
            double t_best = kInfinity;
            BvhHit h;
            ASSERT_TRUE(bvh.intersect(ray, BvhShapes::of_arrays(one), t_best, h)) << at;
            EXPECT_FLOAT_EQ(float(t_best), hit->t) << at;
            EXPECT_TRUE(inside(bounds(shape), hit->p)) << at;
        }
        // dpdu is tangent, and u grows along it (away from u's seam and from the axis).
        const Vec3 tangent = dpdu(shape, hit->p);
        if (length(tangent) > 1e-4f) {
            const Vec3 tu = normalize(tangent);
            EXPECT_LT(std::fabs(dot(tu, hit->n)), 1e-4f) << at;
            float u0, v0, u1, v1;
            shape.uv(hit->p, u0, v0);
            shape.uv(hit->p + tu * 1e-3f, u1, v1);
            if (u0 > 0.01f && u0 < 0.99f) {
                EXPECT_GT(u1, u0) << at;
            }
        }
        // A ray spawned from the hit onwards does not meet the surface at the hit again.
        const Ray onward = spawn_ray(*hit, ray.d);
        if (const std::optional<Hit> again = nearest(shape, onward)) {
            EXPECT_GT(length(again->p - hit->p), 1e-4f) << at;
        }
    }
    EXPECT_GT(hits, 1000) << c.name;
}

/// Two-sample chi-square p-value that counts a and b come from the same distribution over
/// the cells (cells with fewer than 10 in both together are pooled).
double same_distribution_p(const std::vector<double>& a, const std::vector<double>& b) {
    double na = 0, nb = 0;
    for (std::size_t i = 0; i < a.size(); ++i) na += a[i], nb += b[i];
    double stat = 0, pa = 0, pb = 0;
    int cells = 0;
    auto add = [&](double x, double y) {
        stat += std::pow(std::sqrt(nb / na) * x - std::sqrt(na / nb) * y, 2) / (x + y);
        ++cells;
    };
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (a[i] + b[i] >= 10) add(a[i], b[i]);
        else pa += a[i], pb += b[i];
    }
    if (pa + pb > 0) add(pa, pb);
    return spt_test::chi2_survival(stat, cells - 1);
}

template <typename T>
void check_area(const Case& c, const T& shape) {
    if constexpr (!requires { shape.sample_area(0.f, 0.f); }) {
        return;  // infinite: no area, no sampling
    } else {
        constexpr int kGrid = 8;
        auto cell = [&](const Vec3& p) {
            float u, v;
            shape.uv(p, u, v);
            return std::min(int(u * kGrid), kGrid - 1) * kGrid + std::min(int(v * kGrid), kGrid - 1);
        };
        spt_test::Uniform u(5);
        // Crossings of isotropic lines: the area estimate and points uniform by area.
        constexpr int kLines = 300000;
        std::vector<double> crossed(kGrid * kGrid, 0.0);
        double sum = 0, sum2 = 0;
        for (int i = 0; i < kLines; ++i) {
            Ray ray = random_line(c, u);
            int n = 0;
            for (std::optional<Hit> hit = nearest(shape, ray); hit && n < 8; hit = nearest(shape, ray)) {
                ++n, crossed[std::size_t(cell(hit->p))] += 1;
                EXPECT_TRUE(inside(bounds(shape), hit->p)) << c.name;
                ray = spawn_ray(*hit, ray.d);
            }
            sum += n, sum2 += double(n) * n;
        }
        const double mean = sum / kLines, se = std::sqrt((sum2 / kLines - mean * mean) / kLines);
        const double scale = 2.0 * kPiDouble * c.radius * c.radius;
        EXPECT_NEAR(shape.area(), mean * scale, 5.0 * se * scale) << c.name;
        // sample_area against the crossings, and a planted non-uniform warp against them.
        constexpr int kSamples = 300000;
        std::vector<double> sampled(kGrid * kGrid, 0.0), warped(kGrid * kGrid, 0.0);
        const Aabb box = bounds(shape);
        for (int i = 0; i < kSamples; ++i) {
            const float u1 = u.next_float(), u2 = u.next_float();
            const SurfaceSample s = shape.sample_area(u1, u2);
            sampled[std::size_t(cell(s.p))] += 1;
            warped[std::size_t(cell(shape.sample_area(u1 * u1, u2).p))] += 1;
            EXPECT_TRUE(inside(box, s.p)) << c.name << " sample " << i;
            EXPECT_LE(std::fabs(distance(shape, DVec3(s.p))), 1.01 * length(s.p_err) + 1e-12) << c.name;
            EXPECT_NEAR(length(s.n), 1.f, 1e-5f) << c.name;
            if (i < 2000) {
                // The sample's normal is the one a ray hitting the point there reports.
                const Vec3 o = s.p + s.n * float(0.5 * c.radius) + sphere_dir(u) * float(0.1 * c.radius);
                if (const std::optional<Hit> hit = nearest(shape, {o, normalize(s.p - o), kInfinity});
                    hit && length(hit->p - s.p) < 1e-4f) {
                    EXPECT_GT(dot(hit->n, s.n), 0.9999f) << c.name << " sample " << i;
                }
            }
        }
        EXPECT_GT(same_distribution_p(crossed, sampled), 1e-4) << c.name;
        EXPECT_LT(same_distribution_p(crossed, warped), 1e-6) << c.name << ": the planted warp u1² was not caught";
    }
}

TEST(ShapeContract, EveryTypeHasARow) {
    std::set<std::size_t> types;
    for (const Case& c : cases()) types.insert(c.shape.index());
    EXPECT_EQ(types.size(), kShapeTypeCount);
}

TEST(ShapeContract, HitsOcclusionNormalsAndTangents) {
    for (const Case& c : cases()) std::visit([&](const auto& shape) { check_hits(c, shape); }, c.shape);
}

TEST(ShapeContract, AreaAndAreaSampling) {
    for (const Case& c : cases()) std::visit([&](const auto& shape) { check_area(c, shape); }, c.shape);
}

}  // namespace

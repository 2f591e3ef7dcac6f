// Direction ↔ unit-square maps (geometry/sphere_mappings.h): the equal-area octahedral square
// against values worked out by hand from its definition (pbrt-v4's layout), round trips over
// random and awkward directions (poles, seams, octant boundaries, signed zeros), the equal
// solid angle of equal square cells (with a non-equal-area octahedral map as negative
// control), the edge mirrors; the lat-long map against Mitsuba 3's formulas at the axes and at
// random directions, its seam and its Jacobian.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "core/math.h"
#include "core/vec3.h"
#include "geometry/sphere_mappings.h"
#include "uniform.h"

namespace {

using spt::Vec3;
using spt_test::Uniform;

constexpr double kPiD = 3.14159265358979323846;

double distance(const Vec3& a, const Vec3& b) {
    const double dx = double(a.x) - b.x, dy = double(a.y) - b.y, dz = double(a.z) - b.z;
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

Vec3 random_direction(Uniform& rng) {
    const double z = 1.0 - 2.0 * rng.next_double(), phi = 2.0 * kPiD * rng.next_double();
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return {float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)};
}

Vec3 normalized(double x, double y, double z) {
    const double l = std::sqrt(x * x + y * y + z * z);
    return {float(x / l), float(y / l), float(z / l)};
}

/// Directions where the maps switch cases: the axes (both zero signs), the coordinate planes,
/// the planes |x| = |y|, next to both poles, and random ones.
std::vector<Vec3> test_directions() {
    std::vector<Vec3> d;
    for (float s : {1.f, -1.f})
        for (float zero : {0.f, -0.f}) {
            d.push_back({s, zero, zero});
            d.push_back({zero, s, zero});
            d.push_back({zero, zero, s});
        }
    for (int k = 0; k < 64; ++k) {
        const double a = 2 * kPiD * k / 64 + 0.01, c = std::cos(a), s = std::sin(a);
        d.push_back(normalized(c, s, 0));          // equator (the square's diamond)
        d.push_back(normalized(c, 0, s));          // y = 0 plane
        d.push_back(normalized(0, c, s));          // x = 0 plane
        d.push_back(normalized(c, c, s));          // |x| = |y|
        d.push_back(normalized(c, -c, s));
    }
    for (double eps : {1e-3, 1e-5, 1e-7, 1e-12, 1e-20})
        for (double z : {1.0, -1.0}) {
            d.push_back(normalized(eps, 0.3 * eps, z));
            d.push_back(normalized(-eps, -2 * eps, z));
        }
    Uniform rng(17);
    for (int k = 0; k < 100000; ++k) d.push_back(random_direction(rng));
    return d;
}

// ---------------------------------------------------------------- equal-area square

TEST(EqualAreaSquare, MatchesValuesWorkedOutFromTheDefinition) {
    // (a, b) = (2u − 1, 2v − 1); s = |a| + |b|; r = s (s ≤ 1) or 2 − s; z = ±(1 − r²);
    // φ = (π/4)(1 + (|b| − |a|)/r); (x, y) = r√(2 − r²)·(±cos φ, ±sin φ) with the signs of a, b.
    struct Case {
        float u, v;
        double x, y, z;
    };
    const double h = std::sqrt(0.5), s7 = std::sqrt(7.0) / 4;
    const std::vector<Case> cases = {
        {0.5f, 0.5f, 0, 0, 1},        // centre: +z
        {1.f, 0.5f, 1, 0, 0},         // a = 1, b = 0: on the equator, φ = 0
        {0.5f, 1.f, 0, 1, 0},         // φ = π/2
        {0.f, 0.5f, -1, 0, 0},
        {0.5f, 0.f, 0, -1, 0},
        {0.f, 0.f, 0, 0, -1},         // every corner: s = 2, r = 0
        {1.f, 1.f, 0, 0, -1},
        {0.f, 1.f, 0, 0, -1},
        {1.f, 0.f, 0, 0, -1},
        {0.75f, 0.75f, h, h, 0},      // a = b = ½: s = 1, φ = π/4
        {0.75f, 0.5f, s7, 0, 0.75},   // a = ½, b = 0: r = ½, z = ¾, r√(2 − r²) = √7/4
        {1.f, 0.75f, s7, 0, -0.75},   // a = 1, b = ½: s = 3/2, r = ½, z = −¾, φ = 0
        {0.625f, 0.875f, std::cos(3 * kPiD / 8), std::sin(3 * kPiD / 8), 0},  // a = ¼, b = ¾: φ = 3π/8
        // a = −¾, b = −7/8: s = 13/8, r = 3/8, z = −55/64, φ = π/3, r√(2 − r²) = 3√119/64
        {0.125f, 0.0625f, -3 * std::sqrt(119.0) / 128, -3 * std::sqrt(357.0) / 128, -55.0 / 64},
    };
    for (const Case& c : cases) {
        const Vec3 d = spt::equal_area_square_to_sphere(c.u, c.v);
        EXPECT_NEAR(d.x, c.x, 1e-6) << c.u << ", " << c.v;
        EXPECT_NEAR(d.y, c.y, 1e-6) << c.u << ", " << c.v;
        EXPECT_NEAR(d.z, c.z, 1e-6) << c.u << ", " << c.v;
        // The inverse gives the point back wherever it is unique (not on the square's edge).
        if (c.u > 0.f && c.u < 1.f && c.v > 0.f && c.v < 1.f) {
            const auto [u, v] = spt::equal_area_sphere_to_square(normalized(c.x, c.y, c.z));
            EXPECT_NEAR(u, c.u, 1e-6) << c.u << ", " << c.v;
            EXPECT_NEAR(v, c.v, 1e-6) << c.u << ", " << c.v;
        }
    }
    // The inverse of points on the edge: +x → (1, ½), −z → a corner, (√7/4, 0, −¾) → (1, ¾).
    const auto px = spt::equal_area_sphere_to_square({1, 0, 0});
    EXPECT_EQ(px[0], 1.f);
    EXPECT_EQ(px[1], 0.5f);
    const auto mz = spt::equal_area_sphere_to_square({0, 0, -1});
    EXPECT_TRUE((mz[0] == 0.f || mz[0] == 1.f) && (mz[1] == 0.f || mz[1] == 1.f));
    const auto south = spt::equal_area_sphere_to_square(normalized(s7, 0, -0.75));
    EXPECT_NEAR(south[0], 1.f, 1e-6);
    EXPECT_NEAR(south[1], 0.75f, 1e-6);
    EXPECT_FLOAT_EQ(spt::equal_area_solid_angle_pdf(1.f), float(1 / (4 * kPiD)));
}

TEST(EqualAreaSquare, RoundTripsDirections) {
    double worst = 0;
    for (const Vec3& d : test_directions()) {
        const auto [u, v] = spt::equal_area_sphere_to_square(d);
        ASSERT_TRUE(u >= 0.f && u <= 1.f && v >= 0.f && v <= 1.f) << d.x << " " << d.y << " " << d.z;
        const Vec3 back = spt::equal_area_square_to_sphere(u, v);
        EXPECT_NEAR(spt::length(back), 1.0, 1e-6);
        worst = std::max(worst, distance(back, d));
    }
    EXPECT_LT(worst, 1e-6);
}

TEST(EqualAreaSquare, RoundTripsInteriorPoints) {
    std::vector<std::array<float, 2>> points;
    for (int i = 1; i < 64; ++i)
        for (int j = 1; j < 64; ++j) points.push_back({i / 64.f, j / 64.f});  // incl. axes, diagonals
    Uniform rng(19);
    for (int k = 0; k < 100000; ++k) points.push_back({rng.next_float(), rng.next_float()});
    for (float e : {1e-7f, 1e-4f}) {  // next to the centre (the +z pole) and to the corners
        points.push_back({0.5f + e, 0.5f - e});
        points.push_back({e, e});
        points.push_back({1 - e, e});
    }
    double worst = 0;
    for (const auto& p : points) {
        if (p[0] <= 0.f || p[0] >= 1.f || p[1] <= 0.f || p[1] >= 1.f) continue;
        const auto q = spt::equal_area_sphere_to_square(spt::equal_area_square_to_sphere(p[0], p[1]));
        worst = std::max({worst, std::fabs(double(q[0]) - p[0]), std::fabs(double(q[1]) - p[1])});
    }
    EXPECT_LT(worst, 1e-6);
}

/// Solid angle of the image of the square cell [u0,u1]×[v0,v1] under `map`: the cell cut into
/// k × k quads, each two spherical triangles (Van Oosterom & Strackee 1983).
template <typename Map>
double cell_solid_angle(Map map, double u0, double v0, double u1, double v1, int k) {
    auto tri = [](const Vec3& a, const Vec3& b, const Vec3& c) {
        const double ax = a.x, ay = a.y, az = a.z, bx = b.x, by = b.y, bz = b.z, cx = c.x, cy = c.y, cz = c.z;
        const double triple = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
        const double denom = 1 + (ax * bx + ay * by + az * bz) + (bx * cx + by * cy + bz * cz) + (cx * ax + cy * ay + cz * az);
        return 2 * std::atan2(std::fabs(triple), denom);
    };
    double sum = 0;
    for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
            const double a0 = u0 + (u1 - u0) * i / k, a1 = u0 + (u1 - u0) * (i + 1) / k;
            const double b0 = v0 + (v1 - v0) * j / k, b1 = v0 + (v1 - v0) * (j + 1) / k;
            const Vec3 p00 = map(a0, b0), p10 = map(a1, b0), p01 = map(a0, b1), p11 = map(a1, b1);
            sum += tri(p00, p10, p11) + tri(p00, p11, p01);
        }
    return sum;
}

/// The octahedral map without the area correction (Cigolle et al. 2014): the negative control.
Vec3 plain_octahedral(double u, double v) {
    const double a = 2 * u - 1, b = 2 * v - 1, z = 1 - std::fabs(a) - std::fabs(b);
    double x = a, y = b;
    if (z < 0) x = std::copysign(1 - std::fabs(b), a), y = std::copysign(1 - std::fabs(a), b);
    return normalized(x, y, z);
}

TEST(EqualAreaSquare, EqualCellsCoverEqualSolidAngles) {
    constexpr int kCells = 16, kSub = 24;
    const auto equal_area = [](double u, double v) { return spt::equal_area_square_to_sphere(float(u), float(v)); };
    double lo = 1e9, hi = 0, total = 0, plain_lo = 1e9, plain_hi = 0;
    for (int i = 0; i < kCells; ++i)
        for (int j = 0; j < kCells; ++j) {
            const double u0 = double(i) / kCells, v0 = double(j) / kCells, w = 1.0 / kCells;
            const double omega = cell_solid_angle(equal_area, u0, v0, u0 + w, v0 + w, kSub);
            lo = std::min(lo, omega), hi = std::max(hi, omega), total += omega;
            const double plain = cell_solid_angle(plain_octahedral, u0, v0, u0 + w, v0 + w, kSub);
            plain_lo = std::min(plain_lo, plain), plain_hi = std::max(plain_hi, plain);
        }
    const double expected = 4 * kPiD / (kCells * kCells);
    EXPECT_NEAR(total, 4 * kPiD, 1e-6);
    EXPECT_NEAR(lo / expected, 1.0, 1e-3);
    EXPECT_NEAR(hi / expected, 1.0, 1e-3);
    // The measurement can tell: the uncorrected octahedral map's cells differ by a factor > 2.
    EXPECT_GT(plain_hi / plain_lo, 2.0);
}

TEST(EqualAreaSquare, WrapContinuesTheSquareAcrossItsEdges) {
    // The edges u = 0 and u = 1 lie in the plane y = 0 (southern half), v = 0 and v = 1 in
    // x = 0. A point just across an edge, wrapped, must be the mirror image through that plane
    // of the point just inside (so a filter crossing the edge continues onto the neighbouring
    // octant), and near the edge point.
    Uniform rng(23);
    const float delta = 1e-3f;
    int flips_that_matter = 0;
    for (int k = 0; k < 2000; ++k) {
        const float t = rng.next_float();
        struct Edge {
            float ex, ey, ox, oy, ix, iy;  // on the edge, outside, inside
            bool mirror_y;                 // else mirror x
        };
        const Edge edges[] = {{0.f, t, -delta, t, delta, t, true},
                              {1.f, t, 1 + delta, t, 1 - delta, t, true},
                              {t, 0.f, t, -delta, t, delta, false},
                              {t, 1.f, t, 1 + delta, t, 1 - delta, false}};
        for (const Edge& e : edges) {
            const auto w = spt::wrap_equal_area_square(e.ox, e.oy);
            ASSERT_TRUE(w[0] >= 0.f && w[0] <= 1.f && w[1] >= 0.f && w[1] <= 1.f);
            const Vec3 across = spt::equal_area_square_to_sphere(w[0], w[1]);
            Vec3 mirrored = spt::equal_area_square_to_sphere(e.ix, e.iy);
            const Vec3 inside = mirrored;
            if (e.mirror_y) mirrored.y = -mirrored.y;
            else mirrored.x = -mirrored.x;
            EXPECT_LT(distance(across, mirrored), 1e-5) << t;
            EXPECT_LT(distance(across, spt::equal_area_square_to_sphere(e.ex, e.ey)), 10 * delta);
            // Negative control: a wrap that only folds the point back inside, without moving
            // the other coordinate, gives `inside`, which this test tells apart.
            if (distance(inside, mirrored) > 1e-4) ++flips_that_matter;
        }
    }
    EXPECT_GT(flips_that_matter, 7000);
    // Points inside are left alone.
    EXPECT_EQ(spt::wrap_equal_area_square(0.3f, 0.7f), (std::array<float, 2>{0.3f, 0.7f}));
}

TEST(EqualAreaSquare, TexelWrapIsTheContinuousMirrorAtTexelCentres) {
    for (int n : {1, 2, 5, 16}) {
        for (int i = -n; i < 2 * n; ++i)
            for (int j = -n; j < 2 * n; ++j) {
                int wi = i, wj = j;
                spt::wrap_equal_area_texel(wi, wj, n);
                ASSERT_TRUE(wi >= 0 && wi < n && wj >= 0 && wj < n) << n << ": " << i << ", " << j;
                const auto w = spt::wrap_equal_area_square((i + 0.5f) / n, (j + 0.5f) / n);
                EXPECT_NEAR(w[0], (wi + 0.5f) / n, 1e-6) << n << ": " << i << ", " << j;
                EXPECT_NEAR(w[1], (wj + 0.5f) / n, 1e-6) << n << ": " << i << ", " << j;
            }
    }
}

// ---------------------------------------------------------------- equirectangular

/// Mitsuba 3's envmap formulas in double: u = atan2(x, −z)/(2π) wrapped, v = acos(y)/π.
std::array<double, 2> mitsuba_uv(const Vec3& d) {
    double u = std::atan2(double(d.x), -double(d.z)) / (2 * kPiD);
    if (u < 0) u += 1;
    return {u, std::acos(std::clamp(double(d.y), -1.0, 1.0)) / kPiD};
}

TEST(Equirect, MatchesMitsubaAtTheAxes) {
    struct Case {
        Vec3 d;
        float u, v;
    };
    const std::vector<Case> cases = {
        {{0, 0, -1}, 0.f, 0.5f},  {{1, 0, 0}, 0.25f, 0.5f}, {{0, 0, 1}, 0.5f, 0.5f},
        {{-1, 0, 0}, 0.75f, 0.5f}, {{0, 1, 0}, 0.f, 0.f},   {{0, -1, 0}, 0.f, 1.f},
    };
    for (const Case& c : cases) {
        const auto [u, v] = spt::direction_to_equirect(c.d);
        if (c.v > 0.f && c.v < 1.f) {  // at the poles u is arbitrary (atan2(0, −0) = π: ½)
            EXPECT_NEAR(u, c.u, 1e-7) << c.d.x << " " << c.d.y << " " << c.d.z;
        }
        EXPECT_NEAR(v, c.v, 1e-7) << c.d.x << " " << c.d.y << " " << c.d.z;
        if (c.v > 0.f && c.v < 1.f) {
            EXPECT_LT(distance(spt::equirect_to_direction(c.u, c.v), c.d), 1e-6);
        }
    }
    EXPECT_LT(distance(spt::equirect_to_direction(0.37f, 0.f), {0, 1, 0}), 1e-6);  // v = 0: +Y, any u
    EXPECT_LT(distance(spt::equirect_to_direction(0.37f, 1.f), {0, -1, 0}), 1e-6);
}

TEST(Equirect, MatchesMitsubaFormulasAndRoundTrips) {
    double worst_uv = 0, worst_dir = 0;
    for (const Vec3& d : test_directions()) {
        const auto [u, v] = spt::direction_to_equirect(d);
        ASSERT_TRUE(u >= 0.f && u < 1.f && v >= 0.f && v <= 1.f) << d.x << " " << d.y << " " << d.z;
        const auto m = mitsuba_uv(d);
        const double du = std::fabs(u - m[0]);
        // Away from the poles, where u is meaningless and acos has no precision.
        if (std::fabs(d.y) < 0.999f) worst_uv = std::max({worst_uv, std::min(du, 1 - du), std::fabs(v - m[1])});
        worst_dir = std::max(worst_dir, distance(spt::equirect_to_direction(u, v), d));
    }
    EXPECT_LT(worst_uv, 1e-6);
    EXPECT_LT(worst_dir, 1e-6);
    // (u, v) → direction → (u, v) away from the poles, modulo the seam.
    Uniform rng(29);
    double worst = 0;
    for (int k = 0; k < 100000; ++k) {
        const float u = rng.next_float(), v = 0.001f + 0.998f * rng.next_float();
        const auto q = spt::direction_to_equirect(spt::equirect_to_direction(u, v));
        const double du = std::fabs(double(q[0]) - u);
        worst = std::max({worst, std::min(du, 1 - du), std::fabs(double(q[1]) - v)});
    }
    EXPECT_LT(worst, 2e-6);
}

TEST(Equirect, SeamGivesUInZeroToOne) {
    // Just west of −Z, atan2 is −tiny, and −tiny + 1 rounds to 1: that is the seam, u = 0.
    for (double x : {-1e-8, -1e-10, -1e-30, -0.0}) {
        const auto [u, v] = spt::direction_to_equirect(normalized(x, 0.2, -1));
        EXPECT_LT(u, 1.f) << x;
        EXPECT_GE(u, 0.f) << x;
        EXPECT_FALSE(std::signbit(u)) << x;
    }
    const auto [u_east, v_east] = spt::direction_to_equirect(normalized(1e-3, 0.2, -1));
    EXPECT_NEAR(u_east, 1e-3 / (2 * kPiD) / 1.0, 1e-6);
}

TEST(Equirect, JacobianGivesTheSolidAngleOfEachRow) {
    // A unit density over the square becomes equirect_solid_angle_pdf(1, v) per steradian, so
    // ∫ 1/pdf du dv over a band of rows is the band's solid angle 2π(cos θ0 − cos θ1).
    constexpr int kRows = 32, kSimpson = 64;
    for (int row = 0; row < kRows; ++row) {
        const double v0 = double(row) / kRows, v1 = double(row + 1) / kRows, h = (v1 - v0) / kSimpson;
        double integral = 0;
        for (int s = 0; s <= kSimpson; ++s) {
            const double v = v0 + s * h;
            const float pdf = spt::equirect_solid_angle_pdf(1.f, float(v));
            const double inv = pdf > 0.f ? 1.0 / pdf : 0.0;  // the poles: sin θ = 0
            integral += inv * (s == 0 || s == kSimpson ? 1 : (s % 2 ? 4 : 2));
        }
        integral *= h / 3;
        const double exact = 2 * kPiD * (std::cos(kPiD * v0) - std::cos(kPiD * v1));
        EXPECT_NEAR(integral / exact, 1.0, 1e-5) << row;
    }
    EXPECT_EQ(spt::equirect_solid_angle_pdf(1.f, 0.f), 0.f);
    EXPECT_EQ(spt::equirect_solid_angle_pdf(1.f, 1.f), 0.f);
    EXPECT_EQ(spt::equirect_solid_angle_pdf(1.f, -0.1f), 0.f);
    EXPECT_EQ(spt::equirect_solid_angle_pdf(1.f, 1.1f), 0.f);
    EXPECT_EQ(spt::equirect_solid_angle_pdf(1.f, std::numeric_limits<float>::quiet_NaN()), 0.f);
    // Next to the south pole the density keeps its precision (sin(π·v) in float would not:
    // π·v rounds by 1e-7 where sin θ is 3e-6).
    for (float v : {1.f - 0x1p-20f, 0x1p-20f, 1.f - 0x1p-17f}) {
        const double exact = 1.0 / (2 * kPiD * kPiD * std::sin(kPiD * double(v)));
        EXPECT_NEAR(spt::equirect_solid_angle_pdf(1.f, v) / exact, 1.0, 1e-5) << v;
    }
}

}  // namespace

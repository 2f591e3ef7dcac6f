// Portals (model/lights/portal_light.h) and the windowed distribution they sample
// (core/windowed_distribution.h): window integrals against sums over cells, sampled points
// against the density (chi-square over the window's cells, which a window cutting through
// cells must get right), the portal's directions through the portal and only through it,
// the mixture with the whole sphere's density (its share, and samples weighed by the density
// they were drawn with), and malformed portals refused. Renders with portals are in
// test_environment_map_scenes.cpp; the light contract's row in test_light_contract.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "chi2.h"
#include "core/windowed_distribution.h"
#include "model/lights/portal_light.h"

namespace spt {
namespace {

using Window = WindowedPiecewiseConstant2D::Window;

/// A function of strong contrast with zero cells: 12 × 9 cells.
WindowedPiecewiseConstant2D test_distribution(std::vector<float>* values = nullptr) {
    const int nx = 12, ny = 9;
    std::vector<float> f;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) f.push_back((i * 7 + j * 3) % 5 == 0 ? 0.f : float(1 + (i * j) % 7) * (i == 4 ? 20.f : 1.f));
    if (values) *values = f;
    return WindowedPiecewiseConstant2D(f, nx, ny);
}

/// ∫ over w of the piecewise-constant f by the overlap of each cell with w.
double integral_by_cells(const std::vector<float>& f, int nx, int ny, const Window& w) {
    double sum = 0;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const double ox = std::max(0.0, std::min<double>(w.x1, double(i + 1) / nx) - std::max<double>(w.x0, double(i) / nx));
            const double oy = std::max(0.0, std::min<double>(w.y1, double(j + 1) / ny) - std::max<double>(w.y0, double(j) / ny));
            sum += f[std::size_t(j * nx + i)] * ox * oy;
        }
    return sum;
}

const std::vector<Window> kWindows = {{0.f, 0.f, 1.f, 1.f}, {0.13f, 0.21f, 0.71f, 0.64f}, {0.3f, 0.05f, 0.34f, 0.93f},
                                      {0.26f, 0.5f, 0.29f, 0.52f}, {0.5f, 0.0f, 1.0f, 0.11f}};

TEST(WindowedDistribution, WindowIntegralsAreTheCellsOverlap) {
    std::vector<float> f;
    const WindowedPiecewiseConstant2D d = test_distribution(&f);
    for (const Window& w : kWindows) {
        const double ref = integral_by_cells(f, 12, 9, w);
        EXPECT_NEAR(d.integral(w), ref, 1e-9 * std::max(1.0, ref));
    }
    EXPECT_EQ(d.integral({0.5f, 0.5f, 0.5f, 0.7f}), 0.0);  // an empty window
}

TEST(WindowedDistribution, SamplesFollowTheDensityInsideTheWindow) {
    // Bins: the window's pieces of the cells; expected counts from the exact overlaps.
    std::vector<float> f;
    const WindowedPiecewiseConstant2D d = test_distribution(&f);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (const Window& w : kWindows) {
        const int n = 200000;
        std::vector<double> observed(12 * 9, 0.0), expected(12 * 9, 0.0);
        const double total = integral_by_cells(f, 12, 9, w);
        for (int j = 0; j < 9; ++j)
            for (int i = 0; i < 12; ++i) {
                Window cell{float(i) / 12, float(j) / 9, float(i + 1) / 12, float(j + 1) / 9};
                cell = {std::max(cell.x0, w.x0), std::max(cell.y0, w.y0), std::min(cell.x1, w.x1), std::min(cell.y1, w.y1)};
                if (cell.x1 > cell.x0 && cell.y1 > cell.y0) expected[std::size_t(j * 12 + i)] = n * integral_by_cells(f, 12, 9, cell) / total;
            }
        for (int k = 0; k < n; ++k) {
            float x, y, pdf;
            ASSERT_TRUE(d.sample(u(rng), u(rng), w, x, y, pdf));
            ASSERT_TRUE(x >= w.x0 && x <= w.x1 && y >= w.y0 && y <= w.y1) << x << ", " << y;
            const int i = std::min(11, int(double(x) * 12)), j = std::min(8, int(double(y) * 9));
            ASSERT_GT(f[std::size_t(j * 12 + i)], 0.f) << "a point in a cell of f = 0";
            ASSERT_NEAR(pdf, d.pdf(x, y, w), 1e-5f * pdf);
            ASSERT_NEAR(pdf, f[std::size_t(j * 12 + i)] / total, 1e-4 * pdf);
            observed[std::size_t(j * 12 + i)] += 1;
        }
        const spt_test::Chi2Result r = spt_test::chi2_test(observed, expected);
        EXPECT_GT(r.p_value, 1e-5) << "window " << w.x0 << " " << w.y0 << " " << w.x1 << " " << w.y1 << ": X² = " << r.statistic;
        EXPECT_EQ(r.observed_in_empty, 0);
    }
}

TEST(WindowedDistribution, DensityIsZeroOutsideTheWindowAndBadValuesThrow) {
    const WindowedPiecewiseConstant2D d = test_distribution();
    const Window w{0.2f, 0.2f, 0.4f, 0.6f};
    EXPECT_EQ(d.pdf(0.1f, 0.3f, w), 0.f);
    EXPECT_EQ(d.pdf(0.3f, 0.7f, w), 0.f);
    EXPECT_GT(d.pdf(0.3f, 0.3f, w), 0.f);
    float x, y, pdf;
    EXPECT_FALSE(d.sample(0.5f, 0.5f, {0.3f, 0.3f, 0.3f, 0.5f}, x, y, pdf));
    EXPECT_THROW(WindowedPiecewiseConstant2D({1.f, -1.f}, 2, 1), std::invalid_argument);
    EXPECT_THROW(WindowedPiecewiseConstant2D({1.f, NAN}, 2, 1), std::invalid_argument);
    EXPECT_THROW(WindowedPiecewiseConstant2D({1.f, 1.f}, 3, 1), std::invalid_argument);
}

/// A lat-long map with a small bright sun and a dim sky, under a 0.6 × 0.4 window in the
/// plane x = 1 whose front (edge1 × edge2 = +x) faces the map.
PortalLight window_light() {
    const int w = 64, h = 32;
    std::vector<float> rgb;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool sun = std::abs(x - 49) <= 1 && std::abs(y - 11) <= 1;
            rgb.insert(rgb.end(), {sun ? 200.f : 0.3f, sun ? 180.f : 0.4f, sun ? 150.f : 0.7f * float(h - y) / h});
        }
    EnvironmentMapLight env;
    env.map = make_environment_map(w, h, 3, rgb, EnvironmentMapping::equirect);
    return make_portal_light(env, {1.f, -0.1f, -0.3f}, {0, 0.4f, 0}, {0, 0, 0.6f});
}

/// The window of window_light() under a sun of 2 × 2 texels (1.4° across; its centre at
/// (u, v) = (0.25, 0.471)) that shines through it, 10^5 times as bright as the sky, on a map
/// as fine as the benchmarks' (texels about as wide as the cells).
PortalLight sunlit_window_light() {
    const int width = 512, height = 256;
    std::vector<float> rgb;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const bool sun = (x == 127 || x == 128) && (y == 120 || y == 121);
            rgb.insert(rgb.end(), {sun ? 5e4f : 0.3f, sun ? 4.5e4f : 0.4f, sun ? 4e4f : 0.7f});
        }
    EnvironmentMapLight env;
    env.map = make_environment_map(width, height, 3, rgb, EnvironmentMapping::equirect);
    return make_portal_light(env, {1.f, -0.1f, -0.3f}, {0, 0.4f, 0}, {0, 0, 0.6f});
}

/// window_light()'s portal turned to face its sun (front −x), and a point behind it on the
/// line to the sun, 1.4 from the window: the sun is partly seen through the window from
/// there, and both strategies of the mixture draw (P = 0.75, share 0.49).
struct MixedPoint {
    PortalLight light;
    Vec3 p;
};
MixedPoint sun_facing_portal() {
    const EnvironmentMapLight env = window_light().environment;
    MixedPoint m{make_portal_light(env, {1.f, -0.1f, -0.3f}, {0, 0, 0.6f}, {0, 0.4f, 0}), {}};
    const Vec3 sun = normalize(env.to_world(env.map->direction_of(49.5f / 64, 11.5f / 32)));
    const Portal& q = m.light.portal();
    m.p = q.origin + q.edge1 * 0.5f + q.edge2 * 0.5f - sun * 1.4f;
    return m;
}

/// Where the ray from p along d crosses the portal's plane lies inside the portal.
bool passes_through(const Portal& portal, const Vec3& p, const Vec3& d) {
    const float t = dot(portal.origin - p, portal.z) / dot(d, portal.z);
    if (!(t > 0.f)) return false;
    const Vec3 q = p + d * t - portal.origin;
    const float a = dot(q, portal.x), b = dot(q, portal.y);
    return a >= -1e-4f && a <= portal.width + 1e-4f && b >= -1e-4f && b <= portal.height + 1e-4f;
}

TEST(PortalLight, SampledDirectionsPassThroughThePortalAndFollowTheirDensity) {
    // The portal's part of the mixture: u1 below the portal's share (the mixture as a whole:
    // MixedSamplesAreWeighedByTheMixturesDensity).
    const PortalLight light = window_light();
    const SampledWavelengths lambda = SampledWavelengths::sample(0.4f);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (const Vec3 p : {Vec3(0, 0, 0), Vec3(0.9f, 0.5f, 0.8f), Vec3(-0.8f, -0.9f, -0.7f)}) {
        const LightSampleContext ctx{p, {}, {0, 1, 0}, {0, 1, 0}, true};
        // The directions' rectified coordinates, binned 16 × 16 over the window.
        WindowedPiecewiseConstant2D::Window w;
        ASSERT_TRUE(light.window(p, w));
        const float share = light.through_from(p).share;
        ASSERT_GT(share, 0.f);
        const int n = 100000, bins = 16;
        std::vector<double> observed(bins * bins, 0.0), expected(bins * bins, 0.0);
        for (int k = 0; k < n; ++k) {
            LightSample ls;
            ASSERT_TRUE(light.sample_li(ctx, lambda, u(rng) * share, u(rng), ls));
            ASSERT_TRUE(passes_through(light.portal(), p, ls.wi)) << "a direction that misses the portal";
            ASSERT_GT(ls.L[0], 0.f);
            float uu, vv, jacobian;
            ASSERT_TRUE(light.rectified(ls.wi, uu, vv, jacobian));
            const int i = std::clamp(int((uu - w.x0) / (w.x1 - w.x0) * bins), 0, bins - 1);
            const int j = std::clamp(int((vv - w.y0) / (w.y1 - w.y0) * bins), 0, bins - 1);
            observed[std::size_t(j * bins + i)] += 1;
        }
        const double total = light.sampling->distribution.integral(w);
        for (int j = 0; j < bins; ++j)
            for (int i = 0; i < bins; ++i) {
                const float x0 = w.x0 + (w.x1 - w.x0) * float(i) / bins, x1 = w.x0 + (w.x1 - w.x0) * float(i + 1) / bins;
                const float y0 = w.y0 + (w.y1 - w.y0) * float(j) / bins, y1 = w.y0 + (w.y1 - w.y0) * float(j + 1) / bins;
                expected[std::size_t(j * bins + i)] = n * light.sampling->distribution.integral({x0, y0, x1, y1}) / total;
            }
        const spt_test::Chi2Result r = spt_test::chi2_test(observed, expected);
        EXPECT_GT(r.p_value, 1e-5) << "X² = " << r.statistic;
    }
}

TEST(PortalLight, DensityIsTheMixtureOfThePortalAndTheWholeSphere) {
    // Where the portal draws alone (share 1) and where both strategies draw.
    const MixedPoint mixed = sun_facing_portal();
    for (const MixedPoint& m : {MixedPoint{window_light(), {0.2f, 0.1f, -0.2f}}, mixed}) {
        const PortalLight& light = m.light;
        const Vec3 p = m.p;
        std::mt19937_64 rng(9);
        std::uniform_real_distribution<float> u(-1.f, 1.f);
        const LightSampleContext ctx{p, {}, {0, 1, 0}, {0, 1, 0}, true};
        const float share = light.through_from(p).share;
        int through = 0;
        for (int k = 0; k < 20000; ++k) {
            const Vec3 d = normalize(Vec3(u(rng), u(rng), u(rng)));
            const float pdf = light.pdf_li(ctx, d), sphere = light.environment.pdf_li(ctx, d);
            // Directions near an edge may round either way: not checked.
            const Portal& q = light.portal();
            auto grown = [&](float e) {  // the portal with a margin e (shrunk for e < 0)
                return Portal{q.origin - q.x * e - q.y * e, q.edge1 + q.x * 2.f * e, q.edge2 + q.y * 2.f * e,
                              q.x, q.y, q.z, q.width + 2.f * e, q.height + 2.f * e};
            };
            if (passes_through(grown(-0.01f), p, d)) {
                EXPECT_GT(pdf, (1.f - share) * sphere);
                ++through;
            } else if (!passes_through(grown(0.01f), p, d)) {
                EXPECT_FLOAT_EQ(pdf, (1.f - share) * sphere);
            }
        }
        EXPECT_GT(through, 100);
    }
    // In front of the portal (outside), the whole sphere's density alone.
    const PortalLight light = window_light();
    const LightSampleContext outside{{1.5f, 0.f, 0.f}, {}, {0, 1, 0}, {0, 1, 0}, true};
    for (const Vec3 d : {Vec3(1, 0, 0), normalize(Vec3(-0.3f, 0.5f, 0.2f))})
        EXPECT_EQ(light.pdf_li(outside, d), light.environment.pdf_li(outside, d));
}

TEST(PortalLight, ThePortalCedesToTheWholeSphereWhereTheSunIsSeenThroughIt) {
    // From a point that sees the sun through the window, most of the whole-sphere density's
    // samples pass through the portal; from one that sees only sky through it, few.
    const PortalLight light = sunlit_window_light();
    const EnvironmentMap& map = *light.environment.map;
    const Vec3 sun = normalize(light.environment.to_world(map.direction_of(0.25f, 0.471f)));
    const Portal& q = light.portal();
    ASSERT_GT(dot(sun, q.z), 0.f);
    const Vec3 centre = q.origin + q.edge1 * 0.5f + q.edge2 * 0.5f;
    // The sun's direction from `shaded` crosses the portal's plane beside the portal.
    const Vec3 sunlit = centre - sun * 0.8f, shaded = sunlit + q.edge2 * 1.5f;
    ASSERT_TRUE(passes_through(q, sunlit, sun));
    ASSERT_FALSE(passes_through(q, shaded, sun));
    EXPECT_LT(light.through_from(sunlit).share, 0.3f);
    EXPECT_GT(light.through_from(shaded).share, 0.9f);
}

TEST(PortalLight, MixedSamplesAreWeighedByTheMixturesDensity) {
    // Where both strategies draw (0 < share < 1), E[g / pdf] = ∫ g = 1 for g each strategy's
    // own density: both fail if sample_li drew with another share than pdf_li weighs by.
    const auto [light, p] = sun_facing_portal();
    const EnvironmentMapLight& env = light.environment;
    const PortalLight::Through t = light.through_from(p);
    ASSERT_TRUE(t.share > 0.1f && t.share < 0.9f) << t.share;
    const LightSampleContext ctx{p, {}, {0, 1, 0}, {0, 1, 0}, true};
    const SampledWavelengths lambda = SampledWavelengths::sample(0.4f);
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    const int n = 200000;
    double sphere = 0, portal = 0;
    for (int k = 0; k < n; ++k) {
        LightSample ls;
        ASSERT_TRUE(light.sample_li(ctx, lambda, u(rng), u(rng), ls));
        ASSERT_NEAR(ls.pdf, light.pdf_li(ctx, ls.wi), 1e-5f * ls.pdf);
        sphere += env.pdf_li(ctx, ls.wi) / ls.pdf;
        float uu, vv, jacobian;
        if (light.rectified(ls.wi, uu, vv, jacobian))
            portal += light.sampling->distribution.pdf(uu, vv, t.window) / jacobian / ls.pdf;
    }
    EXPECT_NEAR(sphere / n, 1.0, 0.01) << "share " << t.share;
    EXPECT_NEAR(portal / n, 1.0, 0.01) << "share " << t.share;
}

TEST(PortalLight, NoDirectionCarriesFarMoreThanTheWindowsRadiance) {
    // A BSDF sample through the portal is weighed against this density by MIS, so where the
    // density is far below the radiance (a cell whose points miss the sun's edge that it
    // covers) a sample carries up to L / pdf: a firefly. With a density proportional to the
    // radiance, L / pdf would be ∫ L dω over the window everywhere. The sky's colour against
    // its luminance, the cells against the texels and the floor on a cell's weight (a quarter
    // of its brightest neighbour's mean, which may itself cover a quarter of the sun) allow
    // up to about 16 times that, never orders of magnitude (10^5 before that floor).
    const PortalLight light = sunlit_window_light();
    const SampledWavelengths lambda = SampledWavelengths::sample(0.4f);
    for (const Vec3 p : {Vec3(0, 0, 0), Vec3(0.5f, -0.05f, 0.1f), Vec3(-0.8f, -0.3f, -0.1f), Vec3(0.3f, 0.1f, 0.05f)}) {
        const LightSampleContext ctx{p, {}, {0, 1, 0}, {0, 1, 0}, true};
        WindowedPiecewiseConstant2D::Window w;
        ASSERT_TRUE(light.window(p, w));
        const int n = 600;  // points per side of the window: far finer than its cells
        double integral = 0, worst = 0;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const float u = w.x0 + (w.x1 - w.x0) * (float(i) + 0.5f) / n;
                const float v = w.y0 + (w.y1 - w.y0) * (float(j) + 0.5f) / n;
                float jacobian = 0.f;
                const Vec3 d = light.direction(u, v, jacobian);
                const double L = light.arriving(d, lambda).average();
                integral += L * jacobian * (w.x1 - w.x0) * (w.y1 - w.y0) / (double(n) * n);
                const float pdf = light.pdf_li(ctx, d);
                ASSERT_GT(pdf, 0.f);
                worst = std::max(worst, L / pdf);
            }
        EXPECT_LT(worst, 20 * integral) << "from (" << p.x << ", " << p.y << ", " << p.z << ")";
    }
}

TEST(PortalLight, LightSubpathsEnterThroughThePortal) {
    // Their directions, binned 16 × 16 in the rectified (u, v) of the light's arrival, follow
    // the whole square's distribution.
    const PortalLight light = window_light();
    std::mt19937_64 rng(13);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    const int n = 100000, bins = 16;
    std::vector<double> observed(bins * bins, 0.0), expected(bins * bins, 0.0);
    for (int k = 0; k < n; ++k) {
        const auto o = light.sample_le(SampledWavelengths::sample(0.4f), u(rng), u(rng), 0.f, u(rng), u(rng), 0.f);
        ASSERT_TRUE(o.has_value());
        float uu, vv, jacobian;
        ASSERT_TRUE(light.rectified(-o->w, uu, vv, jacobian));
        observed[std::size_t(std::min(bins - 1, int(vv * bins)) * bins + std::min(bins - 1, int(uu * bins)))] += 1;
        if (k >= 2000) continue;
        ASSERT_LT(dot(o->w, light.portal().z), 0.f) << "a subpath leaving the room";
        // A point one unit into the room along the ray finds the same origin density.
        const Vec3 inside = o->p + o->w;
        ASSERT_NEAR(light.pdf_le_pos(inside, o->w), o->pdf_pos, 1e-4f * o->pdf_pos);
        ASSERT_NEAR(light.pdf_le_dir({}, o->w), o->pdf_dir, 1e-4f * o->pdf_dir);
    }
    const double total = light.sampling->distribution.integral({});
    for (int j = 0; j < bins; ++j)
        for (int i = 0; i < bins; ++i)
            expected[std::size_t(j * bins + i)] =
                n * light.sampling->distribution.integral({float(i) / bins, float(j) / bins, float(i + 1) / bins, float(j + 1) / bins}) / total;
    const spt_test::Chi2Result r = spt_test::chi2_test(observed, expected);
    EXPECT_GT(r.p_value, 1e-5) << "X² = " << r.statistic;
    // A ray that reaches its point from outside the portal's rectangle has density 0.
    EXPECT_EQ(light.pdf_le_pos({0, 0, 3}, {-1, 0, 0}), 0.f);
}

TEST(PortalLight, MalformedPortalsAreRefused) {
    const PortalLight ok = window_light();
    EXPECT_THROW(make_portal_light(ok.environment, {0, 0, 0}, {1, 0, 0}, {0.1f, 1, 0}), std::invalid_argument);
    EXPECT_THROW(make_portal_light(ok.environment, {0, 0, 0}, {0, 0, 0}, {0, 1, 0}), std::invalid_argument);
    EXPECT_THROW(make_portal_light(ok.environment, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}), std::invalid_argument);
}

}  // namespace
}  // namespace spt

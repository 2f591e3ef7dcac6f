// The environment map (model/lights/environment_map_light.h) beyond the generic contract
// rows: sampled directions against pdf_li texel by texel (chi-square) for a peaked and a
// smooth map in both mappings, with and without the MIS compensation; the irradiance of a
// constant map (π·L) and of a one-texel sun (L·Ω·cos) estimated from sample_li; a white texel
// arrives as D65 of luminance 1; the mappings' conventions (lat-long: +y at the top row,
// u = ¼ towards +x) and the rotation move the bright texel where expected.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "chi2.h"
#include "model/lights/light.h"
#include "spectral/rgb_texels.h"

namespace {

using namespace spt;
constexpr double kPiD = std::numbers::pi;
constexpr double kAlpha = 1e-5;

using TexelFn = std::function<std::array<float, 3>(int x, int y)>;

EnvironmentMapLight map_light(int w, int h, EnvironmentMapping mapping, const TexelFn& f) {
    std::vector<float> rgb;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const auto c = f(x, y);
            rgb.insert(rgb.end(), c.begin(), c.end());
        }
    EnvironmentMapLight l;
    l.map = make_environment_map(w, h, 3, rgb, mapping, true);
    return l;
}

/// A smooth map (a broad bright region and a gradient) and a peaked one (a sun of a few
/// texels 10⁴ times the dim sky), in colour.
std::array<float, 3> smooth(int x, int y, int w, int h) {
    const float a = 0.2f + float(std::pow(std::sin(kPiD * (x + 0.5) / w), 2)) * float(y + 1) / float(h);
    return {a, 0.8f * a, 0.5f + 0.1f * a};
}
std::array<float, 3> peaked(int x, int y, int w, int h) {
    if (std::abs(x - w / 3) <= 1 && std::abs(y - h / 3) <= 1) return {3e3f, 2.5e3f, 2e3f};
    return {0.1f, 0.2f, 0.3f + 0.01f * float(x % 3)};
}

LightSampleContext origin_context() { return {{0, 0, 0}, {0, 0, 0}, {0, 1, 0}, {0, 1, 0}, false}; }

/// Index of the texel a world direction looks up.
std::size_t texel_of(const EnvironmentMapLight& l, const Vec3& d) {
    const auto [u, v] = l.map->square_of(l.to_map(d));
    const int x = std::clamp(int(u * float(l.map->width)), 0, l.map->width - 1);
    const int y = std::clamp(int(v * float(l.map->height)), 0, l.map->height - 1);
    return std::size_t(y) * std::size_t(l.map->width) + std::size_t(x);
}

/// Probability that sample_li lands in each texel according to pdf_li: the density at the
/// texel's centre times the texel's measure (equal-area: 4π/N; lat-long: the square density
/// is pdf·2π²·sin θ, constant over the texel).
std::vector<double> texel_probabilities(const EnvironmentMapLight& l, const std::function<float(const Vec3&)>& pdf) {
    const EnvironmentMap& m = *l.map;
    const double n = double(m.width) * m.height;
    std::vector<double> p;
    for (int y = 0; y < m.height; ++y)
        for (int x = 0; x < m.width; ++x) {
            const float u = (x + 0.5f) / float(m.width), v = (y + 0.5f) / float(m.height);
            const double density = pdf(l.to_world(m.direction_of(u, v)));
            p.push_back(m.mapping == EnvironmentMapping::equal_area ? density * 4 * kPiD / n
                                                                    : density * 2 * kPiD * kPiD * std::sin(kPiD * v) / n);
        }
    return p;
}

spt_test::Chi2Result texel_chi2(const EnvironmentMapLight& l, const std::function<float(const Vec3&)>& pdf, int n,
                                std::uint64_t seed) {
    std::vector<double> observed(std::size_t(l.map->width) * std::size_t(l.map->height), 0.0);
    std::vector<double> expected = texel_probabilities(l, pdf);
    for (double& e : expected) e *= n;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    const SampledWavelengths lambda = SampledWavelengths::sample(0.4f);
    for (int i = 0; i < n; ++i) {
        LightSample ls;
        if (!l.sample_li(origin_context(), lambda, u(rng), u(rng), ls)) continue;
        observed[texel_of(l, ls.wi)] += 1;
    }
    return spt_test::chi2_test(observed, expected);
}

struct MapCase {
    std::string name;
    EnvironmentMapLight light;
};

std::vector<MapCase> cases() {
    std::vector<MapCase> c;
    for (EnvironmentMapping m : {EnvironmentMapping::equirect, EnvironmentMapping::equal_area}) {
        const int w = 24, h = m == EnvironmentMapping::equirect ? 12 : 24;
        const std::string mapping = m == EnvironmentMapping::equirect ? "equirect" : "equal-area";
        c.push_back({mapping + " smooth", map_light(w, h, m, [=](int x, int y) { return smooth(x, y, w, h); })});
        c.push_back({mapping + " peaked", map_light(w, h, m, [=](int x, int y) { return peaked(x, y, w, h); })});
    }
    return c;
}

TEST(EnvironmentMap, SampledDirectionsFollowPdfLiTexelByTexel) {
    for (bool compensated : {false, true})
        for (MapCase& c : cases()) {
            c.light.mis_compensation = compensated;
            const std::string name = c.name + (compensated ? " compensated" : "");
            const spt_test::Chi2Result r =
                texel_chi2(c.light, [&](const Vec3& d) { return c.light.pdf_li(origin_context(), d); }, 200000, 5);
            EXPECT_GT(r.p_value, kAlpha) << name << ": X² = " << r.statistic;
            EXPECT_EQ(r.observed_in_empty, 0) << name;
            // Each sample carries pdf_li's density of its direction, and the radiance a ray
            // along it sees.
            std::mt19937_64 rng(3);
            std::uniform_real_distribution<float> u(0.f, 1.f);
            const SampledWavelengths lambda = SampledWavelengths::sample(0.7f);
            for (int i = 0; i < 2000; ++i) {
                LightSample ls;
                ASSERT_TRUE(c.light.sample_li(origin_context(), lambda, u(rng), u(rng), ls)) << name;
                ASSERT_TRUE(ls.infinite);
                ASSERT_EQ(ls.pdf, c.light.pdf_li(origin_context(), ls.wi)) << name;
                ASSERT_EQ(ls.L[1], c.light.arriving(ls.wi, lambda)[1]) << name;
            }
        }
}

TEST(EnvironmentMap, CompensationLeavesDimDirectionsToBsdfSampling) {
    // Karlík et al.: texels no brighter than the mean weight get density 0, the others more.
    MapCase c = cases()[1];  // equirect peaked
    const Vec3 dim = c.light.to_world(c.light.map->direction_of(0.9f, 0.8f));
    const Vec3 sun = c.light.to_world(c.light.map->direction_of((24 / 3 + 0.5f) / 24.f, (12 / 3 + 0.5f) / 12.f));
    const float full_dim = c.light.pdf_li(origin_context(), dim), full_sun = c.light.pdf_li(origin_context(), sun);
    c.light.mis_compensation = true;
    EXPECT_GT(full_dim, 0.f);
    EXPECT_EQ(c.light.pdf_li(origin_context(), dim), 0.f);
    EXPECT_GT(c.light.pdf_li(origin_context(), sun), full_sun);
    // Light subpaths keep the full density (nothing else samples their first direction).
    EXPECT_EQ(c.light.pdf_le_dir(Vec3(), -dim), full_dim);
}

TEST(EnvironmentMapNegativeControl, TexelChiSquareRejectsTheWrongDensity) {
    // The planted bug: the compensated map's samples against the full density.
    MapCase c = cases()[0];
    EnvironmentMapLight full = c.light;
    c.light.mis_compensation = true;
    const spt_test::Chi2Result r =
        texel_chi2(c.light, [&](const Vec3& d) { return full.pdf_li(origin_context(), d); }, 200000, 5);
    EXPECT_LT(r.p_value, kAlpha);
}

/// E(λ) = ∫ L(ω) max(0, n·ω) dω from sample_li, per wavelength of `lambda`.
std::array<double, 4> irradiance(const EnvironmentMapLight& l, const Vec3& n, const SampledWavelengths& lambda,
                                 int samples, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    std::array<double, 4> e{};
    for (int i = 0; i < samples; ++i) {
        LightSample ls;
        if (!l.sample_li(origin_context(), lambda, u(rng), u(rng), ls)) continue;
        const double c = std::max(0.f, dot(n, ls.wi));
        for (int k = 0; k < 4; ++k) e[std::size_t(k)] += ls.L[k] * c / ls.pdf;
    }
    for (double& x : e) x /= samples;
    return e;
}

TEST(EnvironmentMap, ConstantMapGivesPiLOnAPlane) {
    const SampledWavelengths lambda = SampledWavelengths::sample(0.25f);
    for (EnvironmentMapping m : {EnvironmentMapping::equirect, EnvironmentMapping::equal_area})
        for (EnvironmentSampling s : {EnvironmentSampling::importance, EnvironmentSampling::uniform}) {
            EnvironmentMapLight l = map_light(16, 16, m, [](int, int) { return std::array<float, 3>{0.7f, 0.7f, 0.7f}; });
            l.sampling = s;
            l.scale = 2.f;
            for (const Vec3& n : {Vec3{0, 1, 0}, normalize(Vec3{0.3f, -0.5f, 0.8f})}) {
                const auto e = irradiance(l, n, lambda, 400000, 9);
                for (int k = 0; k < 4; ++k) {
                    const double L = 2 * 0.7 * d65_unit_luminance(lambda.lambda[std::size_t(k)]);
                    EXPECT_NEAR(e[std::size_t(k)], kPiD * L, 0.01 * kPiD * L)
                        << (m == EnvironmentMapping::equirect ? "equirect" : "equal-area")
                        << (s == EnvironmentSampling::uniform ? " uniform" : " importance") << " λ " << lambda.lambda[std::size_t(k)];
                }
            }
        }
}

TEST(EnvironmentMap, OneTexelSunGivesItsAnalyticIrradiance) {
    // Only one texel emits (radiance S): E = S·∫_texel cos dω ≈ S·Ω·cos θ at its centre, Ω its
    // solid angle (4π/N equal-area; (2π/w)(cos θ0 − cos θ1) lat-long). Importance sampling
    // puts every sample in the texel.
    const SampledWavelengths lambda = SampledWavelengths::sample(0.6f);
    for (EnvironmentMapping m : {EnvironmentMapping::equirect, EnvironmentMapping::equal_area}) {
        const int w = 64, h = m == EnvironmentMapping::equal_area ? 64 : 32, sx = 20, sy = 11;
        const float S = 5000.f;
        const EnvironmentMapLight l = map_light(w, h, m, [&](int x, int y) {
            return x == sx && y == sy ? std::array<float, 3>{S, S, S} : std::array<float, 3>{0.f, 0.f, 0.f};
        });
        const double omega = m == EnvironmentMapping::equal_area
                                 ? 4 * kPiD / (w * h)
                                 : 2 * kPiD / w * (std::cos(kPiD * sy / h) - std::cos(kPiD * (sy + 1) / h));
        const Vec3 centre = l.map->direction_of((sx + 0.5f) / w, (sy + 0.5f) / h);
        // A surface turned 30° away from the sun.
        const Vec3 n = normalize(centre * std::cos(0.5236f) + Frame(centre).s * std::sin(0.5236f));
        const auto e = irradiance(l, n, lambda, 20000, 4);
        for (int k = 0; k < 4; ++k) {
            const double expected = S * d65_unit_luminance(lambda.lambda[std::size_t(k)]) * omega * std::cos(0.5236);
            EXPECT_NEAR(e[std::size_t(k)], expected, 2e-3 * expected) << (m == EnvironmentMapping::equirect ? "equirect" : "equal-area");
        }
    }
}

TEST(EnvironmentMap, WhiteTexelArrivesAsD65OfUnitLuminance) {
    const EnvironmentMapLight l =
        map_light(8, 4, EnvironmentMapping::equirect, [](int, int) { return std::array<float, 3>{1.f, 1.f, 1.f}; });
    for (float u : {0.05f, 0.3f, 0.55f, 0.9f}) {
        const SampledWavelengths lambda = SampledWavelengths::sample(u);
        const SampledSpectrum L = l.arriving(normalize(Vec3{0.2f, 0.5f, -0.7f}), lambda);
        for (int k = 0; k < 4; ++k) {
            const double d65 = d65_unit_luminance(lambda.lambda[std::size_t(k)]);
            EXPECT_NEAR(L[k], d65, 2e-3 * d65) << lambda.lambda[std::size_t(k)];
        }
    }
}

TEST(EnvironmentMap, LatLongConventionAndRotation) {
    // One bright texel at column w/4 (u just past ¼), in the middle rows: seen along +x; the
    // top row along +y (Mitsuba 3's layout).
    const int w = 32, h = 16;
    const EnvironmentMapLight l = map_light(w, h, EnvironmentMapping::equirect, [&](int x, int y) {
        if (x == w / 4 && y == h / 2) return std::array<float, 3>{1000.f, 1000.f, 1000.f};
        if (y == 0) return std::array<float, 3>{0.f, 0.f, 7.f};
        return std::array<float, 3>{0.01f, 0.01f, 0.01f};
    });
    const SampledWavelengths lambda = SampledWavelengths::sample(0.5f);
    const Vec3 bright = normalize(Vec3{1.f, -0.05f, 0.05f});
    EXPECT_GT(l.arriving(bright, lambda)[0], 10.f);
    EXPECT_LT(l.arriving({-1, 0, 0}, lambda)[0], 1.f);
    EXPECT_LT(l.arriving({0, 0, 1}, lambda)[0], 1.f);
    // The top row is blue (its spectrum peaks short).
    const SampledSpectrum top = l.arriving({0, 1, 0}, SampledWavelengths::sample(0.f));
    EXPECT_GT(top.max_value(), 1.f);
    // Turned 90° about z (x → y): the bright texel is now overhead, found there by sampling.
    EnvironmentMapLight turned = l;
    turned.world_from_map[0] = {0, -1, 0};
    turned.world_from_map[1] = {1, 0, 0};
    turned.world_from_map[2] = {0, 0, 1};
    const Vec3 up = normalize(Vec3{0.05f, 1.f, 0.05f});
    EXPECT_GT(turned.arriving(up, lambda)[0], 10.f);
    EXPECT_LT(turned.arriving(bright, lambda)[0], 1.f);
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    int near_up = 0;
    for (int i = 0; i < 1000; ++i) {
        LightSample ls;
        if (turned.sample_li(origin_context(), lambda, u(rng), u(rng), ls) && ls.wi.y > 0.95f) ++near_up;
    }
    EXPECT_GT(near_up, 950);  // the bright texel holds 99% of the weight
}

TEST(EnvironmentMap, EqualAreaMapsPbrtV4sSquare) {
    // pbrt-v4's octahedral square: its centre is +z, its corners −z, the middle of its right
    // edge +x, of its bottom edge (v = 1) +y.
    const int n = 16;
    const EnvironmentMapLight l = map_light(n, n, EnvironmentMapping::equal_area, [&](int x, int y) {
        if (x == n / 2 && y == n / 2) return std::array<float, 3>{50.f, 50.f, 50.f};
        if (x == n - 1 && y == n / 2) return std::array<float, 3>{0.f, 20.f, 0.f};
        return std::array<float, 3>{0.01f, 0.01f, 0.01f};
    });
    const SampledWavelengths lambda = SampledWavelengths::sample(0.5f);
    EXPECT_GT(l.arriving(normalize(Vec3{0.02f, 0.02f, 1.f}), lambda)[0], 10.f);
    EXPECT_LT(l.arriving({0, 0, -1}, lambda)[0], 1.f);
    EXPECT_GT(l.arriving(normalize(Vec3{1.f, 0.02f, -0.05f}), SampledWavelengths::sample(0.45f)).max_value(), 1.f);
}

TEST(EnvironmentMap, BadTexelsAndShapesAreRefused) {
    const auto message = [](int w, int h, EnvironmentMapping m, float bad) -> std::string {
        std::vector<float> v(std::size_t(w) * std::size_t(h) * 3, 1.f);
        v[4] = bad;
        try {
            make_environment_map(w, h, 3, v, m);
        } catch (const std::invalid_argument& e) {
            return e.what();
        }
        return "(no error)";
    };
    EXPECT_EQ(message(4, 2, EnvironmentMapping::equirect, std::nanf("")), "texel (1, 0) is NaN; expected finite radiance");
    EXPECT_EQ(message(4, 2, EnvironmentMapping::equirect, INFINITY), "texel (1, 0) is infinite; expected finite radiance");
    EXPECT_NE(message(4, 2, EnvironmentMapping::equirect, -1.f).find("texel (1, 0) is negative"), std::string::npos);
    EXPECT_NE(message(4, 2, EnvironmentMapping::equal_area, 1.f).find("expected a square image"), std::string::npos);
    EXPECT_EQ(message(4, 2, EnvironmentMapping::equirect, 1.f), "(no error)");
    std::vector<float> black(8 * 3, 0.f);
    EXPECT_THROW(make_environment_map(4, 2, 3, black, EnvironmentMapping::equirect), std::invalid_argument);
}

/// Texels of every kind the build treats differently: distinct colours, runs of equal ones,
/// greys, black, a sun; `bad` rows (if any) get a NaN at column 3.
std::vector<float> varied_texels(int w, int h, const std::vector<int>& bad_rows = {}) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> uni(0.f, 2.f);
    std::vector<float> v;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            std::array<float, 3> c{uni(rng), uni(rng), uni(rng)};
            if (x % 7 < 3) c = {0.3f, 0.5f, 0.9f};            // a run of equal texels
            if (x % 11 == 0) c = {c[0], c[0], c[0]};          // grey
            if (x % 13 == 0) c = {0.f, 0.f, 0.f};             // black
            if (x == w / 2 && y == h / 3) c = {4e4f, 3e4f, 2e4f};  // a sun
            v.insert(v.end(), c.begin(), c.end());
        }
    for (int y : bad_rows) v[(std::size_t(y) * std::size_t(w) + 3) * 3 + 1] = std::nanf("");
    return v;
}

TEST(EnvironmentMap, TheMapIsTheSameForEveryThreadCount) {
    // Rows are built in parallel and their sums added in row order: a sum or a table that
    // depended on which thread did which row would differ between these counts.
    for (const EnvironmentMapping mapping : {EnvironmentMapping::equirect, EnvironmentMapping::equal_area}) {
        const int w = 96, h = mapping == EnvironmentMapping::equirect ? 53 : 96;
        const std::vector<float> texels = varied_texels(w, h);
        const auto one = make_environment_map(w, h, 3, texels, mapping, true, 1);
        for (const int threads : {2, 3, 8}) {
            SCOPED_TRACE(threads);
            const auto many = make_environment_map(w, h, 3, texels, mapping, true, threads);
            EXPECT_EQ(many->radiant_mean, one->radiant_mean);
            EXPECT_EQ(many->up_illuminance, one->up_illuminance);
            ASSERT_EQ(many->texels.size(), one->texels.size());
            EXPECT_EQ(0, std::memcmp(many->texels.data(), one->texels.data(), one->texels.size() * sizeof(RgbIlluminant)));
            for (const auto& [a, b] : {std::pair{&one->distribution, &many->distribution},
                                       std::pair{&one->compensated, &many->compensated}}) {
                for (int y = 0; y < h; ++y)
                    for (int x = 0; x < w; ++x) {
                        const float u = (float(x) + 0.5f) / float(w), v = (float(y) + 0.5f) / float(h);
                        ASSERT_EQ(a->pdf(u, v), b->pdf(u, v)) << x << ", " << y;
                    }
                for (int k = 0; k < 200; ++k) {
                    float pa = 0, pb = 0;
                    const float u0 = float(k) / 200.f, u1 = float((k * 37) % 200) / 200.f;
                    ASSERT_EQ(a->sample(u0, u1, &pa), b->sample(u0, u1, &pb));
                    ASSERT_EQ(pa, pb);
                }
            }
        }
    }
}

TEST(EnvironmentMap, TheFirstBadTexelInRowOrderIsReportedWithAnyThreadCount) {
    const std::vector<float> texels = varied_texels(40, 64, {41, 9, 50});
    for (const int threads : {1, 2, 5}) {
        try {
            make_environment_map(40, 64, 3, texels, EnvironmentMapping::equirect, false, threads);
            ADD_FAILURE() << "no error with " << threads << " threads";
        } catch (const std::invalid_argument& e) {
            EXPECT_STREQ(e.what(), "texel (3, 9) is NaN; expected finite radiance") << threads << " threads";
        }
    }
}

TEST(EnvironmentMap, RadiantMeanAndUpIlluminanceAreTheTexelSums) {
    // power() and "illuminance" rest on these two sums: each texel's radiance averaged over
    // 380, 390, …, 780 nm (by eval, one wavelength at a time) times its solid angle, and each
    // upper texel's luminance times its centre's cosine to the map's up times its solid angle.
    for (const EnvironmentMapping mapping : {EnvironmentMapping::equirect, EnvironmentMapping::equal_area}) {
        const int w = 48, h = mapping == EnvironmentMapping::equirect ? 24 : 48;
        const std::vector<float> texels = varied_texels(w, h);
        const auto m = make_environment_map(w, h, 3, texels, mapping, false, 2);
        double radiant = 0, up = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
                const double omega =
                    mapping == EnvironmentMapping::equal_area
                        ? 4 * kPiD / (double(w) * h)
                        : 2 * kPiD / w * (std::cos(kPiD * y / h) - std::cos(kPiD * (y + 1) / h));
                double mean = 0;
                for (int k = 0; k <= 40; ++k) {
                    SampledWavelengths at;
                    at.lambda.fill(380.f + 10.f * float(k));
                    mean += m->eval(m->texels[i], at)[0];
                }
                radiant += mean / 41 * omega;
                const Vec3 d = m->direction_of((float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h));
                const double cos_up = mapping == EnvironmentMapping::equal_area ? d.z : d.y;
                const double lum = 0.2126729 * texels[3 * i] + 0.7151522 * texels[3 * i + 1] + 0.0721750 * texels[3 * i + 2];
                if (cos_up > 0) up += lum * cos_up * omega;
            }
        EXPECT_NEAR(m->radiant_mean, radiant, 1e-12 * radiant);
        EXPECT_NEAR(m->up_illuminance, up, 1e-12 * up);
    }
}

}  // namespace

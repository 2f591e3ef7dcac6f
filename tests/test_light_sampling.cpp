// Statistical tests of LightSampler (the origins of bidirectional light subpaths): chi-square
// goodness of fit of every sampling step against its density, in the style of the BSDF
// chi-square tests of pbrt-v4 (bsdfs_test.cpp) and Mitsuba (chi2.py):
//   - the choice of a light ∝ power (4π·I for points, 2π·A·Le for two-sided area emitters,
//     means over 380–780 nm), computed here independently of the sampler;
//   - points uniform over the area of spheres and triangles, and the area density pdf_pos;
//   - emission directions: a side with probability 1/2, cosine-weighted about it
//     (direction_pdf), and uniform directions from point lights;
//   - origin_pdf(hit) against the pdf_pos of sample(), and 0 where nothing is sampled;
//   - planted-bug negative controls that the same tests must reject.
// Fixed seeds; each chi-square rejects at p < 1e-3, Šidák-corrected within a family.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <random>
#include <vector>

#include "chi2.h"
#include "geometry/ray.h"
#include "render/light_sampling.h"
#include "scene/scene.h"
#include "spectral/sampled.h"
#include "spectral/spectrum.h"
#include "uniform.h"

namespace {

constexpr double kPiD = 3.14159265358979323846;
constexpr double kAlpha = 1e-3;  ///< family-wise rejection level

/// Per-test level for m tests sharing one family at level kAlpha (Šidák).
double sidak(int m) { return 1.0 - std::pow(1.0 - kAlpha, 1.0 / m); }

using spt_test::Uniform;

spt::Spectrum exact(const spt::SpectrumSource& s) {
    return spt::Spectrum(s, spt::SpectralResolution{spt::SpectralResolution::kExact});
}

/// Lambertian material of constant reflectance (0: a material that reflects nothing, for the
/// emitters).
spt::Material diffuse(const char* name, double kd) {
    spt::Material m;
    m.name = name;
    m.bsdf = spt::DiffuseBsdf{exact(spt::SpectrumSource::constant(kd))};
    return m;
}

/// Mean over 380–780 nm at 10 nm spacing (41 values), in double, from the analytic source:
/// the "power" measure the sampler documents, recomputed independently.
double mean_380_780(const spt::SpectrumSource& s) {
    double sum = 0.0;
    for (int i = 0; i <= 40; ++i) sum += s.eval(380.0 + 10.0 * i);
    return sum / 41.0;
}

struct D3 {
    double x, y, z;
};
D3 d3(const spt::Vec3& v) { return {v.x, v.y, v.z}; }
D3 sub(const D3& a, const D3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dotd(const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 crossd(const D3& a, const D3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double lend(const D3& a) { return std::sqrt(dotd(a, a)); }
D3 scaled(const D3& a, double s) { return {a.x * s, a.y * s, a.z * s}; }

/// Our own orthonormal frame around a unit normal (not the renderer's Frame), for azimuths.
struct OwnFrame {
    D3 t1, t2, n;
    explicit OwnFrame(const spt::Vec3& normal) : n(d3(normal)) {
        n = scaled(n, 1.0 / lend(n));
        const D3 a = std::fabs(n.x) < 0.9 ? D3{1, 0, 0} : D3{0, 1, 0};
        t1 = crossd(n, a);
        t1 = scaled(t1, 1.0 / lend(t1));
        t2 = crossd(n, t1);
    }
    /// Azimuth in [0, 2π) of w about n.
    double phi(const spt::Vec3& w) const {
        const D3 v = d3(w);
        double p = std::atan2(dotd(v, t2), dotd(v, t1));
        if (p < 0.0) p += 2.0 * kPiD;
        return p;
    }
    spt::Vec3 direction(double theta, double phi) const {
        const double s = std::sin(theta), c = std::cos(theta);
        const D3 v = {s * std::cos(phi) * t1.x + s * std::sin(phi) * t2.x + c * n.x,
                      s * std::cos(phi) * t1.y + s * std::sin(phi) * t2.y + c * n.y,
                      s * std::cos(phi) * t1.z + s * std::sin(phi) * t2.z + c * n.z};
        return spt::normalize(spt::Vec3(float(v.x), float(v.y), float(v.z)));
    }
};

// ---------------------------------------------------------------- the test scene

/// Two point lights of different intensity, an emitting sphere and an emitting triangle (the
/// four sampled lights), plus what must never be sampled: a diffuse sphere and triangle, an
/// emitting infinite plane, and an emitting plane with the triangle's material and emission
/// spectrum (its own emitter: nothing of the triangle's density may carry over to it). The
/// emitters' materials reflect nothing. Every emission spectrum is exact (no bins), so the
/// powers computed here from the sources are those the sampler sees.
struct TestScene {
    spt::SpectrumSource point_a = spt::SpectrumSource::constant(2.0);
    spt::SpectrumSource point_b = spt::SpectrumSource::gaussian(600, 50, 10, 0.5);
    spt::SpectrumSource sphere_le = spt::SpectrumSource::blackbody(3000, 3);
    spt::SpectrumSource panel_le = spt::SpectrumSource::gaussian(500, 80, 8, 1);
    spt::Scene scene;
    int m_white = -1, m_sphere = -1, m_panel = -1, m_ceiling = -1;
    int l_sphere = -1, l_panel = -1, l_ceiling = -1, l_wall = -1;  ///< the emitters (Scene::lights)

    static constexpr int kPointA = 0, kPointB = 1, kSphere = 2, kTriangle = 3, kLights = 4;
    std::array<double, kLights> probability{};  ///< expected choice probabilities
    double sphere_area = 0, triangle_area = 0;

    TestScene() {
        m_white = scene.add_material(diffuse("white", 0.7));
        m_sphere = scene.add_material(diffuse("sphere lamp", 0.0));
        m_panel = scene.add_material(diffuse("panel", 0.0));
        m_ceiling = scene.add_material(diffuse("ceiling", 0.0));

        scene.add_point_light(spt::Vec3(0.f, 1.5f, 0.f), exact(point_a));
        scene.add_point_light(spt::Vec3(1.f, 1.f, 1.f), exact(point_b));
        l_sphere = scene.add_emitter(spt::ShapeKind::sphere, exact(sphere_le));
        l_panel = scene.add_emitter(spt::ShapeKind::triangle, exact(panel_le));
        l_ceiling = scene.add_emitter(spt::ShapeKind::plane, exact(spt::SpectrumSource::constant(5.0)));
        l_wall = scene.add_emitter(spt::ShapeKind::plane, exact(panel_le));
        scene.spheres.push_back({spt::Vec3(-1.f, 0.f, 0.f), 0.4f, m_sphere, l_sphere});
        scene.spheres.push_back({spt::Vec3(1.2f, -0.2f, 0.f), 0.5f, m_white});
        scene.triangles.push_back({spt::Vec3(-0.5f, -0.5f, -1.f), spt::Vec3(0.7f, -0.3f, -1.2f),
                                   spt::Vec3(0.1f, 0.8f, -0.9f), m_panel, l_panel});
        scene.triangles.push_back({spt::Vec3(0.f, -1.f, 1.f), spt::Vec3(1.f, -1.f, 1.f),
                                   spt::Vec3(0.f, -1.f, 2.f), m_white});
        scene.planes.push_back({spt::Vec3(0.f, -1.f, 0.f), -2.f, m_ceiling, l_ceiling});  // y = 2, facing down
        // z = −3: the panel's material and spectrum, its own (plane) emitter.
        scene.planes.push_back({spt::Vec3(0.f, 0.f, 1.f), -3.f, m_panel, l_wall});
        scene.finalize();

        const spt::Sphere& s = scene.spheres[0];
        sphere_area = 4.0 * kPiD * double(s.radius) * s.radius;
        const spt::Triangle& t = scene.triangles[0];
        triangle_area = 0.5 * lend(crossd(sub(d3(t.p1), d3(t.p0)), sub(d3(t.p2), d3(t.p0))));
        const std::array<double, kLights> power = {
            4.0 * kPiD * mean_380_780(point_a),
            4.0 * kPiD * mean_380_780(point_b),
            2.0 * kPiD * sphere_area * mean_380_780(sphere_le),
            2.0 * kPiD * triangle_area * mean_380_780(panel_le),
        };
        double total = 0.0;
        for (double p : power) total += p;
        for (int i = 0; i < kLights; ++i) probability[i] = power[i] / total;
    }
};

const TestScene& test_scene() {
    static const TestScene s;
    return s;
}

/// Which light produced a sample, from the sample alone (−1: none of them).
int identify(const TestScene& ts, const spt::LightOrigin& o) {
    const spt::Scene& sc = ts.scene;
    if (o.delta_position) {
        for (int i = 0; i < 2; ++i)
            if (o.p == std::get<spt::PointLight>(sc.lights[sc.point_light_indices[i]]).position) return i;
        return -1;
    }
    const spt::Sphere& s = sc.spheres[0];
    if (std::fabs(lend(sub(d3(o.p), d3(s.center))) - s.radius) < 1e-5) return TestScene::kSphere;
    const spt::Triangle& t = sc.triangles[0];
    const D3 nt = crossd(sub(d3(t.p1), d3(t.p0)), sub(d3(t.p2), d3(t.p0)));
    if (std::fabs(dotd(sub(d3(o.p), d3(t.p0)), nt)) / lend(nt) < 1e-5) return TestScene::kTriangle;
    return -1;
}

/// One large run of sample() on the test scene, shared by the tests (sampled once).
struct LightRun {
    static constexpr int kSamples = 1'000'000;
    spt::SampledWavelengths lambda = spt::SampledWavelengths::sample(0.37f);
    std::vector<spt::LightOrigin> origins;
    std::vector<int> light;  ///< identify() of each origin
    int dropped = 0;         ///< nullopt (direction exactly at the horizon)
    int unidentified = 0;
};

const LightRun& light_run() {
    static const LightRun run = [] {
        const TestScene& ts = test_scene();
        const spt::LightSampler sampler(ts.scene);
        LightRun r;
        r.origins.reserve(LightRun::kSamples);
        r.light.reserve(LightRun::kSamples);
        // Fixed seed. Over seeds 1–40 the p-values of the chi-square tests below were spread
        // uniformly, and runs 8× larger showed no systematic deviation: a low p-value here
        // would be worth investigating, not reseeding.
        Uniform rng(1);
        for (int i = 0; i < LightRun::kSamples; ++i) {
            const float u_light = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
            const float u_side = rng.next_float(), u3 = rng.next_float(), u4 = rng.next_float();
            const std::optional<spt::LightOrigin> o = sampler.sample(r.lambda, u_light, u1, u2, u_side, u3, u4);
            if (!o) {
                ++r.dropped;
                continue;
            }
            const int id = identify(ts, *o);
            if (id < 0) ++r.unidentified;
            r.origins.push_back(*o);
            r.light.push_back(id);
        }
        return r;
    }();
    return run;
}

/// Equal-area (z, φ) cells of the unit sphere: z uniform ⇔ area uniform (Archimedes).
struct SphereHistogram {
    static constexpr int kZ = 20, kPhi = 36;
    std::vector<double> counts = std::vector<double>(kZ * kPhi, 0.0);
    double total = 0;
    void add(double z, double phi) {
        const int i = std::clamp(static_cast<int>((z + 1.0) * 0.5 * kZ), 0, kZ - 1);
        const int j = std::clamp(static_cast<int>(phi / (2.0 * kPiD) * kPhi), 0, kPhi - 1);
        counts[i * kPhi + j] += 1.0;
        total += 1.0;
    }
    std::vector<double> uniform_expected() const {
        return std::vector<double>(counts.size(), total / counts.size());
    }
};

double azimuth(double x, double y) {
    double p = std::atan2(y, x);
    return p < 0.0 ? p + 2.0 * kPiD : p;
}

/// 64 congruent sub-triangles of a triangle (8 subdivisions per edge), in barycentric space:
/// cell (i, j) of the grid of (b1, b2) holds an "up" triangle (frac sum < 1) and, when
/// i + j ≤ 6, a "down" one. 36 up + 28 down = 64 cells of area A/64 each.
struct TriangleHistogram {
    static constexpr int kN = 8, kCells = kN * kN;
    std::vector<double> counts = std::vector<double>(kCells, 0.0);
    double total = 0;
    int outside = 0;
    static int cell(double b1, double b2) {
        const double x = b1 * kN, y = b2 * kN;
        int i = static_cast<int>(std::floor(x)), j = static_cast<int>(std::floor(y));
        i = std::clamp(i, 0, kN - 1), j = std::clamp(j, 0, kN - 1);
        if (i + j > kN - 1) {  // rounding just past the hypotenuse
            if (i > j) i = kN - 1 - j; else j = kN - 1 - i;
        }
        const bool up = (x - i) + (y - j) < 1.0 || i + j == kN - 1;
        // Index: up triangles 0..35 in (i, j) order with i + j ≤ 7, then down ones.
        int index = 0;
        for (int a = 0; a < kN; ++a)
            for (int b = 0; a + b < kN; ++b) {
                if (a == i && b == j && up) return index;
                ++index;
            }
        for (int a = 0; a < kN; ++a)
            for (int b = 0; a + b < kN - 1; ++b) {
                if (a == i && b == j) return index;
                ++index;
            }
        return -1;
    }
    void add(double b1, double b2) {
        const double tol = 1e-6;
        if (b1 < -tol || b2 < -tol || b1 + b2 > 1.0 + tol) ++outside;
        counts[cell(std::clamp(b1, 0.0, 1.0), std::clamp(b2, 0.0, 1.0))] += 1.0;
        total += 1.0;
    }
};

/// Barycentrics (b1, b2) of p with respect to the triangle, solved in double (least squares
/// in the triangle's plane, so the rounding of p off the plane does not matter).
std::pair<double, double> barycentrics(const spt::Triangle& t, const spt::Vec3& p) {
    const D3 e1 = sub(d3(t.p1), d3(t.p0)), e2 = sub(d3(t.p2), d3(t.p0)), q = sub(d3(p), d3(t.p0));
    const double a = dotd(e1, e1), b = dotd(e1, e2), c = dotd(e2, e2);
    const double r1 = dotd(q, e1), r2 = dotd(q, e2);
    const double det = a * c - b * b;
    return {(c * r1 - b * r2) / det, (a * r2 - b * r1) / det};
}

/// θ × φ × side histogram of emission directions about a surface normal.
struct EmissionHistogram {
    static constexpr int kTheta = 9, kPhi = 12, kSides = 2;
    std::vector<double> counts = std::vector<double>(kTheta * kPhi * kSides, 0.0);
    double total = 0;
    void add(const spt::Vec3& n, const spt::Vec3& w) {
        const double c = double(spt::dot(n, w)) / (double(spt::length(n)) * spt::length(w));
        const int side = c >= 0.0 ? 0 : 1;
        const double theta = std::acos(std::min(1.0, std::fabs(c)));
        const OwnFrame f(side == 0 ? n : -n);
        const double phi = f.phi(w);
        const int i = std::min(kTheta - 1, static_cast<int>(theta / (0.5 * kPiD) * kTheta));
        const int j = std::min(kPhi - 1, static_cast<int>(phi / (2.0 * kPiD) * kPhi));
        counts[(side * kTheta + i) * kPhi + j] += 1.0;
        total += 1.0;
    }
    /// Expected counts from a solid-angle density pdf(n, w), integrated over each cell by
    /// Simpson's rule in θ and φ (16 × 4 intervals per cell) about a reference normal.
    template <typename Pdf>
    std::vector<double> expected(Pdf pdf, const spt::Vec3& reference_normal) const {
        std::vector<double> e(counts.size());
        const double dtheta = 0.5 * kPiD / kTheta, dphi = 2.0 * kPiD / kPhi;
        constexpr int kSt = 16, kSp = 4;
        for (int side = 0; side < kSides; ++side) {
            const OwnFrame f(side == 0 ? reference_normal : -reference_normal);
            for (int i = 0; i < kTheta; ++i)
                for (int j = 0; j < kPhi; ++j) {
                    double s = 0.0;
                    for (int a = 0; a <= kSt; ++a) {
                        const double wa = (a == 0 || a == kSt) ? 1.0 : (a % 2 ? 4.0 : 2.0);
                        const double theta = (i + double(a) / kSt) * dtheta;
                        for (int b = 0; b <= kSp; ++b) {
                            const double wb = (b == 0 || b == kSp) ? 1.0 : (b % 2 ? 4.0 : 2.0);
                            const double phi = (j + double(b) / kSp) * dphi;
                            s += wa * wb * double(pdf(reference_normal, f.direction(theta, phi))) * std::sin(theta);
                        }
                    }
                    e[(side * kTheta + i) * kPhi + j] = total * s * (dtheta / kSt / 3.0) * (dphi / kSp / 3.0);
                }
        }
        return e;
    }
};

std::vector<double> choice_counts(const LightRun& run) {
    std::vector<double> counts(TestScene::kLights, 0.0);
    for (int id : run.light)
        if (id >= 0) counts[id] += 1.0;
    return counts;
}

}  // namespace

// ---------------------------------------------------------------- light choice

TEST(LightSampling, ChoiceProportionalToPower) {
    // 1e6 samples; 4 cells (two point lights, the emitting sphere, the emitting triangle);
    // expected probabilities from the powers computed above (4π·I, 2π·A·Le, 41-point means).
    const TestScene& ts = test_scene();
    const LightRun& run = light_run();
    EXPECT_EQ(run.unidentified, 0) << "a sample came from something that is not a sampled light";
    EXPECT_LE(run.dropped, 10);
    const std::vector<double> counts = choice_counts(run);
    double n = 0.0;
    for (double c : counts) n += c;
    std::vector<double> expected(TestScene::kLights);
    for (int i = 0; i < TestScene::kLights; ++i) {
        expected[i] = n * ts.probability[i];
        EXPECT_GT(ts.probability[i], 0.1) << "light " << i << ": the scene should exercise every light";
    }
    const spt_test::Chi2Result r = spt_test::chi2_test(counts, expected);
    EXPECT_EQ(r.dof, 3);
    EXPECT_GE(r.p_value, kAlpha) << "X2=" << r.statistic << " p: " << ts.probability[0] << " "
                                 << ts.probability[1] << " " << ts.probability[2] << " " << ts.probability[3];
    std::printf("[ stats    ] light choice: X2=%.3f dof=%d p=%.4f\n", r.statistic, r.dof, r.p_value);

    // The spectra carried by the samples are those of the chosen light.
    const spt::Scene& sc = ts.scene;
    for (std::size_t k = 0; k < run.origins.size(); k += 97) {
        const spt::LightOrigin& o = run.origins[k];
        const int id = run.light[k];
        const spt::Spectrum& s = id < 2 ? std::get<spt::PointLight>(sc.lights[sc.point_light_indices[id]]).intensity
                                 : id == 2 ? std::get<spt::SphereLight>(sc.lights[ts.l_sphere]).Le
                                           : std::get<spt::TriangleMeshLight>(sc.lights[ts.l_panel]).Le;
        for (int i = 0; i < spt::kLambdaCount; ++i) ASSERT_EQ(o.Le[i], s.eval(run.lambda.lambda[i])) << "light " << id;
        if (id < 2) {
            ASSERT_TRUE(o.delta_position);
            ASSERT_NEAR(o.pdf_pos, ts.probability[id], 1e-5 * ts.probability[id]);
            ASSERT_NEAR(o.pdf_dir, 1.0 / (4.0 * kPiD), 1e-7);
        }
    }
}

TEST(LightSampling, NoLightsNoSamples) {
    // A scene lit only by an emitting infinite plane has nothing to sample.
    spt::Scene scene;
    const int m = scene.add_material(diffuse("ceiling", 0.0));
    const int light = scene.add_emitter(spt::ShapeKind::plane, exact(spt::SpectrumSource::constant(5.0)));
    scene.planes.push_back({spt::Vec3(0.f, -1.f, 0.f), -2.f, m, light});
    scene.finalize();
    const spt::LightSampler sampler(scene);
    EXPECT_TRUE(sampler.empty());
    const spt::SampledWavelengths lambda = spt::SampledWavelengths::sample(0.5f);
    EXPECT_FALSE(sampler.sample(lambda, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f).has_value());
    const std::optional<spt::Hit> hit = scene.intersect({spt::Vec3(0.f, 0.f, 0.f), spt::Vec3(0.f, 1.f, 0.f)});
    ASSERT_TRUE(hit.has_value());
    EXPECT_EQ(sampler.origin_pdf(*hit), 0.f);
}

// ---------------------------------------------------------------- points on emitters

TEST(LightSampling, SpherePointsUniformOverArea) {
    // Sphere samples binned in 20 z × 36 φ cells of equal area (≈490 expected each); every
    // point on the surface with the outward normal, and pdf_pos = P(choose sphere)/area.
    const TestScene& ts = test_scene();
    const LightRun& run = light_run();
    const spt::Sphere& s = ts.scene.spheres[0];
    const double pdf_expected = ts.probability[TestScene::kSphere] / ts.sphere_area;
    SphereHistogram h;
    for (std::size_t k = 0; k < run.origins.size(); ++k) {
        if (run.light[k] != TestScene::kSphere) continue;
        const spt::LightOrigin& o = run.origins[k];
        const D3 v = sub(d3(o.p), d3(s.center));
        ASSERT_NEAR(lend(v), s.radius, 1e-6);
        ASSERT_NEAR(o.n.x, v.x / s.radius, 1e-5);
        ASSERT_NEAR(o.n.y, v.y / s.radius, 1e-5);
        ASSERT_NEAR(o.n.z, v.z / s.radius, 1e-5);
        ASSERT_NEAR(o.pdf_pos, pdf_expected, 1e-5 * pdf_expected);
        ASSERT_FALSE(o.delta_position);
        h.add(v.z / lend(v), azimuth(v.x, v.y));
    }
    EXPECT_GT(h.total, 300000);
    const spt_test::Chi2Result r = spt_test::chi2_test(h.counts, h.uniform_expected());
    EXPECT_EQ(r.dof, SphereHistogram::kZ * SphereHistogram::kPhi - 1);
    EXPECT_GE(r.p_value, kAlpha) << "X2=" << r.statistic << " dof=" << r.dof;
    std::printf("[ stats    ] sphere points: X2=%.1f dof=%d p=%.4f\n", r.statistic, r.dof, r.p_value);
}

TEST(LightSampling, TrianglePointsUniformOverArea) {
    // Triangle samples binned in 64 congruent sub-triangles (equal expected counts); every
    // point inside the triangle, on its plane, with its normal; pdf_pos = P(choose)/area.
    const TestScene& ts = test_scene();
    const LightRun& run = light_run();
    const spt::Triangle& t = ts.scene.triangles[0];
    const D3 nt = crossd(sub(d3(t.p1), d3(t.p0)), sub(d3(t.p2), d3(t.p0)));
    const double nlen = lend(nt);
    const double pdf_expected = ts.probability[TestScene::kTriangle] / ts.triangle_area;
    TriangleHistogram h;
    for (std::size_t k = 0; k < run.origins.size(); ++k) {
        if (run.light[k] != TestScene::kTriangle) continue;
        const spt::LightOrigin& o = run.origins[k];
        ASSERT_NEAR(o.n.x, nt.x / nlen, 1e-6);
        ASSERT_NEAR(o.n.y, nt.y / nlen, 1e-6);
        ASSERT_NEAR(o.n.z, nt.z / nlen, 1e-6);
        ASSERT_NEAR(o.pdf_pos, pdf_expected, 1e-5 * pdf_expected);
        const auto [b1, b2] = barycentrics(t, o.p);
        h.add(b1, b2);
    }
    EXPECT_EQ(h.outside, 0);
    EXPECT_GT(h.total, 100000);
    const spt_test::Chi2Result r =
        spt_test::chi2_test(h.counts, std::vector<double>(TriangleHistogram::kCells, h.total / TriangleHistogram::kCells));
    EXPECT_EQ(r.dof, 63);
    EXPECT_GE(r.p_value, kAlpha) << "X2=" << r.statistic << " dof=" << r.dof;
    std::printf("[ stats    ] triangle points: X2=%.1f dof=%d p=%.4f\n", r.statistic, r.dof, r.p_value);
}

TEST(LightSampling, SubTriangleCellsAreCongruentPartition) {
    // The binning itself: a fine grid of barycentric points at sub-cell centroids lands one in
    // each of the 64 cells, and uniform points (rejection sampling in the unit square) fill
    // them equally.
    std::vector<int> hit(TriangleHistogram::kCells, 0);
    constexpr int kN = TriangleHistogram::kN;
    for (int i = 0; i < kN; ++i)
        for (int j = 0; i + j < kN; ++j) {
            ++hit[TriangleHistogram::cell((i + 1.0 / 3) / kN, (j + 1.0 / 3) / kN)];
            if (i + j < kN - 1) ++hit[TriangleHistogram::cell((i + 2.0 / 3) / kN, (j + 2.0 / 3) / kN)];
        }
    for (int c = 0; c < TriangleHistogram::kCells; ++c) EXPECT_EQ(hit[c], 1) << "cell " << c;
    TriangleHistogram h;
    Uniform rng(77);
    while (h.total < 64000) {
        const double a = rng.next_double(), b = rng.next_double();
        if (a + b < 1.0) h.add(a, b);
    }
    EXPECT_GE(spt_test::chi2_test(h.counts, std::vector<double>(64, h.total / 64)).p_value, kAlpha);
}

// ---------------------------------------------------------------- emission directions

TEST(LightSampling, AreaEmissionCosineWeightedOnEitherSide) {
    // Directions from the sphere and from the triangle (two tests: Šidák α = 1 − (1 − 1e-3)^½),
    // binned in 9 θ × 12 φ × 2 sides about the surface normal; expected counts integrate
    // direction_pdf (½·|cos θ|/π: side ½, cosine-weighted). pdf_dir of each sample equals
    // two_sided_direction_pdf(n, w).
    const TestScene& ts = test_scene();
    const LightRun& run = light_run();
    const double alpha = sidak(2);
    EmissionHistogram hs, ht;
    for (std::size_t k = 0; k < run.origins.size(); ++k) {
        const int id = run.light[k];
        if (id != TestScene::kSphere && id != TestScene::kTriangle) continue;
        const spt::LightOrigin& o = run.origins[k];
        ASSERT_NEAR(spt::length(o.w), 1.0, 1e-5);
        const float pdf = spt::two_sided_direction_pdf(o.n, o.w);
        ASSERT_NEAR(o.pdf_dir, pdf, 1e-5 * pdf + 1e-7);
        ASSERT_GT(o.pdf_dir, 0.f);
        (id == TestScene::kSphere ? hs : ht).add(o.n, o.w);
    }
    const spt::Vec3 tri_n = spt::normalize(spt::cross(ts.scene.triangles[0].p1 - ts.scene.triangles[0].p0,
                                                      ts.scene.triangles[0].p2 - ts.scene.triangles[0].p0));
    auto pdf = [](const spt::Vec3& n, const spt::Vec3& w) { return spt::two_sided_direction_pdf(n, w); };
    for (auto* h : {&hs, &ht}) {
        const bool sphere = h == &hs;
        // Any reference normal will do for the sphere (the density depends on θ only).
        const std::vector<double> expected = h->expected(pdf, sphere ? spt::Vec3(0.f, 0.f, 1.f) : tri_n);
        double total = 0.0, front = 0.0;
        for (std::size_t c = 0; c < expected.size(); ++c) {
            total += expected[c];
            if (c < expected.size() / 2) front += expected[c];
        }
        EXPECT_NEAR(total / h->total, 1.0, 1e-5) << "direction_pdf must integrate to 1 over the sphere";
        EXPECT_NEAR(front / h->total, 0.5, 1e-5) << "each side with probability 1/2";
        const spt_test::Chi2Result r = spt_test::chi2_test(h->counts, expected);
        EXPECT_EQ(r.observed_in_empty, 0.0);
        EXPECT_GT(r.dof, 200);
        EXPECT_GE(r.p_value, alpha) << (sphere ? "sphere" : "triangle") << " X2=" << r.statistic << " dof=" << r.dof;
        std::printf("[ stats    ] %s directions: X2=%.1f dof=%d p=%.4f (alpha %.2e)\n", sphere ? "sphere" : "triangle",
                    r.statistic, r.dof, r.p_value, alpha);
    }
}

TEST(LightSampling, PointLightDirectionsUniform) {
    // Point-light directions in 20 z × 36 φ equal-area cells of the unit sphere.
    const LightRun& run = light_run();
    SphereHistogram h;
    for (std::size_t k = 0; k < run.origins.size(); ++k) {
        if (run.light[k] != TestScene::kPointA && run.light[k] != TestScene::kPointB) continue;
        const spt::Vec3& w = run.origins[k].w;
        ASSERT_NEAR(spt::length(w), 1.0, 1e-5);
        h.add(double(w.z) / spt::length(w), azimuth(w.x, w.y));
    }
    EXPECT_GT(h.total, 300000);
    const spt_test::Chi2Result r = spt_test::chi2_test(h.counts, h.uniform_expected());
    EXPECT_GE(r.p_value, kAlpha) << "X2=" << r.statistic << " dof=" << r.dof;
    std::printf("[ stats    ] point-light directions: X2=%.1f dof=%d p=%.4f\n", r.statistic, r.dof, r.p_value);
}

// ---------------------------------------------------------------- origin_pdf of hits

TEST(LightSampling, OriginPdfOfHitsMatchesSampledPdf) {
    // Rays from random points hit the emitters from outside and (sphere: from inside,
    // triangle: from the back) the other side; origin_pdf(hit) must equal the pdf_pos that
    // sample() reports for points on that emitter. Hits on the diffuse sphere and triangle,
    // the emitting ceiling plane and the plane with the panel's material and spectrum give 0.
    const TestScene& ts = test_scene();
    const spt::Scene& sc = ts.scene;
    const spt::LightSampler sampler(sc);
    const LightRun& run = light_run();
    float pdf_sphere = -1.f, pdf_triangle = -1.f;
    for (std::size_t k = 0; k < run.origins.size() && (pdf_sphere < 0.f || pdf_triangle < 0.f); ++k) {
        if (run.light[k] == TestScene::kSphere) pdf_sphere = run.origins[k].pdf_pos;
        if (run.light[k] == TestScene::kTriangle) pdf_triangle = run.origins[k].pdf_pos;
    }
    ASSERT_GT(pdf_sphere, 0.f);
    ASSERT_GT(pdf_triangle, 0.f);

    Uniform rng(5);
    auto random_point_in_box = [&](double half) {
        return spt::Vec3(float((2 * rng.next_double() - 1) * half), float((2 * rng.next_double() - 1) * half),
                         float((2 * rng.next_double() - 1) * half));
    };
    const spt::Sphere& lamp = sc.spheres[0];
    const spt::Sphere& ball = sc.spheres[1];
    const spt::Triangle& panel = sc.triangles[0];
    const spt::Triangle& floor_tri = sc.triangles[1];
    auto point_on_triangle = [&](const spt::Triangle& t) {
        double a = rng.next_double(), b = rng.next_double();
        if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
        return t.p0 + (t.p1 - t.p0) * float(a) + (t.p2 - t.p0) * float(b);
    };
    int counted[6] = {};
    for (int i = 0; i < 4000; ++i) {
        // Target: a point on one of the shapes; origin: random (inside the lamp for a quarter
        // of the lamp rays).
        const int which = i % 6;
        spt::Vec3 origin = random_point_in_box(1.9);
        spt::Vec3 target;
        switch (which) {
            case 0: target = lamp.center + spt::normalize(random_point_in_box(1.0)) * lamp.radius; break;
            case 1: origin = lamp.center + random_point_in_box(0.2);
                    target = lamp.center + spt::normalize(random_point_in_box(1.0)) * lamp.radius; break;
            case 2: target = point_on_triangle(panel); break;
            case 3: target = ball.center + spt::normalize(random_point_in_box(1.0)) * ball.radius; break;
            case 4: target = point_on_triangle(floor_tri); break;
            default: target = spt::Vec3(float(4 * rng.next_double() - 2), 2.f, float(4 * rng.next_double() - 2));
        }
        if (which == 5 && i % 12 == 11) target = spt::Vec3(float(4 * rng.next_double() - 2), float(4 * rng.next_double() - 2), -3.f);
        const spt::Vec3 d = spt::normalize(target - origin);
        const std::optional<spt::Hit> hit = sc.intersect({origin, d});
        if (!hit) continue;
        const float pdf = sampler.origin_pdf(*hit);
        if (hit->light == ts.l_sphere) {
            EXPECT_NEAR(pdf, pdf_sphere, 1e-5f * pdf_sphere);
            ++counted[which == 1 ? 1 : 0];
        } else if (hit->light == ts.l_panel) {
            EXPECT_GT(std::fabs(hit->p.z + 3.f), 1e-4f) << "the z = −3 plane has its own emitter";
            EXPECT_NEAR(pdf, pdf_triangle, 1e-5f * pdf_triangle);
            ++counted[dot(hit->n, d) < 0.f ? 2 : 3];  // front (n faces the ray origin) or back
        } else {
            EXPECT_EQ(pdf, 0.f) << "material " << hit->material << " at (" << hit->p.x << ", " << hit->p.y << ", "
                                << hit->p.z << ")";
            ++counted[hit->material == ts.m_white ? 4 : 5];
        }
    }
    for (int c = 0; c < 6; ++c) EXPECT_GT(counted[c], 50) << "case " << c << " barely exercised";
    // Exact relation: origin_pdf is the sphere's and the triangle's pdf_pos, which differ.
    EXPECT_NEAR(pdf_sphere, ts.probability[TestScene::kSphere] / ts.sphere_area, 1e-5 * pdf_sphere);
    EXPECT_NEAR(pdf_triangle, ts.probability[TestScene::kTriangle] / ts.triangle_area, 1e-5 * pdf_triangle);
}

// ---------------------------------------------------------------- planted-bug negative controls

TEST(LightSamplingNegativeControl, DirectionsRejectUniformInTheta) {
    // The same emission-direction histogram judged against a density uniform in θ on each side
    // (p(ω) = 1/(2·(π/2)·2π·sin θ)): must be rejected.
    const LightRun& run = light_run();
    EmissionHistogram h;
    for (std::size_t k = 0; k < run.origins.size(); ++k)
        if (run.light[k] == TestScene::kSphere) h.add(run.origins[k].n, run.origins[k].w);
    auto wrong = [](const spt::Vec3& n, const spt::Vec3& w) {
        const double c = std::min(1.0, std::fabs(double(spt::dot(n, w))));
        const double s = std::max(1e-12, std::sqrt(1.0 - c * c));
        return 1.0 / (2.0 * (0.5 * kPiD) * 2.0 * kPiD * s);
    };
    const spt_test::Chi2Result r = spt_test::chi2_test(h.counts, h.expected(wrong, spt::Vec3(0.f, 0.f, 1.f)));
    EXPECT_LT(r.p_value, kAlpha) << "X2=" << r.statistic;
    std::printf("[ stats    ] control (uniform in theta): X2=%.1f dof=%d p=%.3g\n", r.statistic, r.dof, r.p_value);
}

TEST(LightSamplingNegativeControl, ChoiceRejectsOneSidedAreaPower) {
    // Planted bug in the expectation: area emitters counted one-sided (π·A·Le instead of 2π·A·Le).
    const TestScene& ts = test_scene();
    const std::vector<double> counts = choice_counts(light_run());
    double n = 0.0;
    for (double c : counts) n += c;
    std::array<double, TestScene::kLights> wrong = ts.probability;
    wrong[TestScene::kSphere] *= 0.5, wrong[TestScene::kTriangle] *= 0.5;
    double sum = 0.0;
    for (double p : wrong) sum += p;
    std::vector<double> expected;
    for (double p : wrong) expected.push_back(n * p / sum);
    const spt_test::Chi2Result r = spt_test::chi2_test(counts, expected);
    EXPECT_LT(r.p_value, kAlpha) << "X2=" << r.statistic;
    std::printf("[ stats    ] control (one-sided power): X2=%.1f p=%.3g\n", r.statistic, r.p_value);
}

TEST(LightSamplingNegativeControl, RejectsTriangleWarpWithoutSquareRoot) {
    // Planted bug in a sampler: barycentrics b0 = 1 − u1, b1 = u1·u2 (no square root), which
    // crowds points towards p0. The sub-triangle test must reject it at the sample size used
    // for the real sampler's triangle (≈140k).
    TriangleHistogram h;
    Uniform rng(9);
    for (int i = 0; i < 140000; ++i) {
        const double u1 = rng.next_double(), u2 = rng.next_double();
        h.add(u1 * u2, u1 * (1.0 - u2));
    }
    const spt_test::Chi2Result r = spt_test::chi2_test(h.counts, std::vector<double>(64, h.total / 64));
    EXPECT_LT(r.p_value, kAlpha) << "X2=" << r.statistic;
    // And the sphere test rejects points uniform in the polar angle instead of in z.
    SphereHistogram hs;
    for (int i = 0; i < 350000; ++i) hs.add(std::cos(kPiD * rng.next_double()), 2 * kPiD * rng.next_double());
    const spt_test::Chi2Result rs = spt_test::chi2_test(hs.counts, hs.uniform_expected());
    EXPECT_LT(rs.p_value, kAlpha) << "X2=" << rs.statistic;
    std::printf("[ stats    ] controls (triangle no-sqrt, sphere uniform-theta): p=%.3g, %.3g\n", r.p_value, rs.p_value);
}

// ---------------------------------------------------------------- the constant environment

namespace {

/// A point light, a diffuse sphere, the camera and a floor plane y = −1 under a constant
/// environment: the environment's disk is aimed at the bounding sphere of the sphere, the
/// camera and the point light (computed here), and the floor hides part of it upstream.
struct EnvironmentScene {
    spt::Scene scene;
    D3 centre{};
    double radius = 0, p_environment = 0;
    static constexpr double kLe = 0.5, kIntensity = 2.0;

    EnvironmentScene() {
        const int m = scene.add_material(diffuse("white", 0.7));
        scene.spheres.push_back({spt::Vec3(0.5f, 0.f, -0.5f), 0.8f, m});
        scene.planes.push_back({spt::Vec3(0.f, 1.f, 0.f), -1.f, m});
        scene.add_point_light(spt::Vec3(-1.f, 1.5f, 0.f), exact(spt::SpectrumSource::constant(kIntensity)));
        scene.camera.position = spt::Vec3(0.f, 0.5f, 3.f);
        scene.set_background(exact(spt::SpectrumSource::constant(kLe)));
        scene.finalize();
        // Box: x ∈ [−1, 1.3], y ∈ [−0.8, 1.5], z ∈ [−1.3, 3].
        const D3 lo{-1.0, -0.8, -1.3}, hi{1.3, 1.5, 3.0};
        centre = scaled(D3{lo.x + hi.x, lo.y + hi.y, lo.z + hi.z}, 0.5);
        radius = 0.5 * lend(sub(hi, lo));
        const double p_env = 4.0 * kPiD * kPiD * radius * radius * kLe, p_point = 4.0 * kPiD * kIntensity;
        p_environment = p_env / (p_env + p_point);
    }
};

}  // namespace

TEST(LightSampling, EnvironmentDirectionsDiskAndDensities) {
    // 400k samples: the environment chosen ∝ 4π·πR²·Le against 4π·I; its directions uniform
    // (20 z × 36 φ equal-area cells), its points uniform on the disk of radius R one radius
    // upstream of the centre (10 r² × 24 φ equal-area cells), the densities those of the
    // header, and `blocked` exactly when the floor crosses the ray upstream of the disk.
    const EnvironmentScene es;
    const spt::LightSampler sampler(es.scene);
    ASSERT_EQ(es.scene.infinite_light_indices.size(), 1u);
    const int env = es.scene.infinite_light_indices[0];
    const spt::Vec3 any_d(0.f, 0.f, -1.f);
    EXPECT_NEAR(sampler.infinite_pdf(env, any_d), es.p_environment / (4.0 * kPiD),
                1e-5 * sampler.infinite_pdf(env, any_d));
    const spt::SampledWavelengths lambda = spt::SampledWavelengths::sample(0.61f);
    Uniform rng(5);
    constexpr int kN = 400000;
    SphereHistogram directions;
    constexpr int kR = 10, kPhi = 24;
    std::vector<double> disk(kR * kPhi, 0.0);
    double environment = 0;
    int blocked = 0;
    for (int i = 0; i < kN; ++i) {
        float u[6];
        for (float& x : u) x = rng.next_float();
        const std::optional<spt::LightOrigin> o = sampler.sample(lambda, u[0], u[1], u[2], u[3], u[4], u[5]);
        ASSERT_TRUE(o.has_value());
        if (!o->infinite) {
            ASSERT_TRUE(o->delta_position);
            continue;
        }
        ++environment;
        const D3 w = d3(o->w), p = d3(o->p);
        ASSERT_NEAR(lend(w), 1.0, 1e-5);
        for (int k = 0; k < spt::kLambdaCount; ++k) ASSERT_EQ(o->Le[k], float(EnvironmentScene::kLe));
        ASSERT_NEAR(o->pdf_dir, es.p_environment / (4.0 * kPiD), 1e-5 * o->pdf_dir);
        ASSERT_NEAR(o->pdf_pos, 1.0 / (kPiD * es.radius * es.radius), 1e-5 * o->pdf_pos);
        // On the disk: in the plane one radius upstream of the centre, within R of its middle.
        const D3 v = sub(p, es.centre);
        const double along = dotd(v, w);
        ASSERT_NEAR(along, -es.radius, 1e-5 * es.radius);
        const D3 across = sub(v, scaled(w, along));
        const double r2 = dotd(across, across) / (es.radius * es.radius);
        ASSERT_LE(r2, 1.0 + 1e-5);
        directions.add(w.z, azimuth(w.x, w.y));
        const OwnFrame f(o->w);
        const int ir = std::min(kR - 1, static_cast<int>(r2 * kR));
        const int iphi = std::min(kPhi - 1, static_cast<int>(f.phi(spt::Vec3(float(across.x), float(across.y), float(across.z))) / (2.0 * kPiD) * kPhi));
        disk[ir * kPhi + iphi] += 1.0;
        // Upstream of p (towards −w) the floor y = −1 is crossed iff it lies that way.
        const double t = (-1.0 - p.y) / -w.y;
        ASSERT_EQ(o->blocked, t > 0.0) << "p.y = " << p.y << ", w.y = " << w.y;
        blocked += o->blocked;
        // The disk's density reaches every point downstream inside the cylinder, none upstream.
        const spt::Vec3 inside = o->p + o->w * float(1.7 * es.radius);
        EXPECT_EQ(sampler.infinite_position_pdf(env, inside, o->w), o->pdf_pos);
        EXPECT_EQ(sampler.infinite_position_pdf(env, o->p - o->w * float(0.1 * es.radius), o->w), 0.f);
    }
    const double z = (environment - kN * es.p_environment) / std::sqrt(kN * es.p_environment * (1 - es.p_environment));
    EXPECT_LT(std::fabs(z), 4.0) << environment << " environment samples, expected " << kN * es.p_environment;
    EXPECT_GT(blocked, 0.2 * environment);
    const spt_test::Chi2Result rd = spt_test::chi2_test(directions.counts, directions.uniform_expected());
    const spt_test::Chi2Result rp = spt_test::chi2_test(disk, std::vector<double>(disk.size(), environment / disk.size()));
    EXPECT_GE(rd.p_value, sidak(2)) << "directions X2=" << rd.statistic;
    EXPECT_GE(rp.p_value, sidak(2)) << "disk X2=" << rp.statistic;
    std::printf("[ stats    ] environment: chosen %.0f of %d (z = %.2f), %d blocked; directions X2=%.1f p=%.4f; "
                "disk X2=%.1f p=%.4f\n", environment, kN, z, blocked, rd.statistic, rd.p_value, rp.statistic,
                rp.p_value);

    // Points outside the cylinder of the disk are out of reach.
    const spt::Vec3 d(0.f, 0.f, -1.f);
    const spt::Vec3 c(float(es.centre.x), float(es.centre.y), float(es.centre.z));
    EXPECT_GT(sampler.infinite_position_pdf(env, c + spt::Vec3(float(0.99 * es.radius), 0.f, -5.f), d), 0.f);
    EXPECT_EQ(sampler.infinite_position_pdf(env, c + spt::Vec3(float(1.01 * es.radius), 0.f, 0.f), d), 0.f);
}

TEST(LightSampling, NoEnvironmentWithoutBackground) {
    // The same scene with a black background: no environment entry, nothing to pay.
    EnvironmentScene es;
    es.scene.set_background(exact(spt::SpectrumSource::constant(0.0)));
    es.scene.finalize();
    const spt::LightSampler sampler(es.scene);
    EXPECT_TRUE(es.scene.infinite_light_indices.empty());
    const spt::SampledWavelengths lambda = spt::SampledWavelengths::sample(0.5f);
    Uniform rng(6);
    for (int i = 0; i < 1000; ++i) {
        const std::optional<spt::LightOrigin> o = sampler.sample(lambda, rng.next_float(), rng.next_float(),
                                                                 rng.next_float(), rng.next_float(),
                                                                 rng.next_float(), rng.next_float());
        ASSERT_TRUE(o.has_value());
        ASSERT_FALSE(o->infinite);
        ASSERT_NEAR(o->pdf_pos, 1.f, 1e-6f);  // the point light is the only light
    }
}

TEST(LightSamplingNegativeControl, RejectsDiskWithoutSquareRoot) {
    // Planted bug: disk radius R·u instead of R·√u (points crowd the middle). The equal-area
    // r² × φ histogram must reject it at the environment test's sample size (~360k).
    std::vector<double> disk(10 * 24, 0.0);
    Uniform rng(7);
    constexpr int kN = 360000;
    for (int i = 0; i < kN; ++i) {
        const double r = rng.next_double(), phi = 2 * kPiD * rng.next_double();
        disk[std::min(9, static_cast<int>(r * r * 10)) * 24 + std::min(23, static_cast<int>(phi / (2 * kPiD) * 24))] += 1;
    }
    const spt_test::Chi2Result r = spt_test::chi2_test(disk, std::vector<double>(disk.size(), double(kN) / disk.size()));
    EXPECT_LT(r.p_value, kAlpha) << "X2=" << r.statistic;
    std::printf("[ stats    ] control (disk without square root): X2=%.1f p=%.3g\n", r.statistic, r.p_value);
}

// Path guiding (render/guiding/): the directional quadtree's sampling against its density
// (pdf integrates to 1, sampled pdf = pdf(), chi-square), the field's independence of the
// order records arrive in, and the guided path tracer: unbiased against the unguided one on
// three scenes, a planted MIS bug caught, the same image whatever the threads, and resumed or
// split renders equal to the whole render bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <thread>

#include "chi2.h"
#include "render/guiding/directional_tree.h"
#include "render/guiding/guide_bands.h"
#include "render/guiding/guiding_field.h"
#include "render/guiding/guiding_schedule.h"
#include "test_scenes.h"

namespace {

using namespace spt;
using spt::test::compare;
using spt::test::count_differences;
using spt::test::describe;
using spt::test::render_film;
using spt::test::small_settings;

/// A smooth density on the square with a sharp peak, as radiance arriving mostly from a
/// small bright window.
double peaked(double u, double v) {
    const double du = u - 0.7, dv = v - 0.3;
    return 0.2 + 50.0 * std::exp(-(du * du + dv * dv) / (2 * 0.02 * 0.02)) + 2.0 * v;
}

/// A tree trained on `records` samples of `shape` (uniform points, weight shape/uniform pdf),
/// refined and trained again, as two iterations would; channel 0 of `channels`.
DirectionalTree trained_tree(int channels, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    DirectionalTree tree(channels, 2);
    for (int round = 0; round < 3; ++round) {
        for (int i = 0; i < 200000; ++i) {
            const SquarePoint s{uni(rng), uni(rng)};
            for (int c = 0; c < channels; ++c)
                tree.record(s, c, static_cast<std::uint64_t>(std::llround(1000.0 * peaked(s.u, s.v) * (1 + c))));
        }
        tree.gather(1e-3);
        if (round < 2) tree = tree.refined(0.01);
    }
    return tree;
}

TEST(DirectionalTree, EqualAreaMapRoundTrips) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (int i = 0; i < 10000; ++i) {
        const SquarePoint s{uni(rng), uni(rng)};
        const Vec3 w = square_to_direction(s);
        EXPECT_NEAR(length(w), 1.f, 1e-5f);
        const SquarePoint back = direction_to_square(w);
        EXPECT_NEAR(back.u, s.u, 1e-5);
        // v wraps at 1 (φ = 2π is φ = 0).
        EXPECT_NEAR(std::remainder(back.v - s.v, 1.0), 0.0, 1e-5);
    }
}

TEST(DirectionalTree, RefinementFollowsTheEnergy) {
    const DirectionalTree tree = trained_tree(1, 1);
    // The peak holds most of the energy: the tree is far deeper than its 2 initial levels.
    EXPECT_GT(tree.node_count(), 200);
    EXPECT_TRUE(tree.usable(0));
    // The peak's region has a far higher density than a dim corner.
    EXPECT_GT(tree.pdf(0, {0.7, 0.3}), 20.f * tree.pdf(0, {0.1, 0.05}));
}

TEST(DirectionalTree, DensityIntegratesToOneAndMatchesSamples) {
    // Alone and in product with the clamped cosine around a normal; the normal leaves some
    // nodes with positive cone bounds whose children all lie below the surface.
    const Vec3 normal = normalize(Vec3{0.3f, -0.5f, 0.8f});
    for (int channels : {1, kGuideBands}) {
        const DirectionalTree tree = trained_tree(channels, 2);
        std::vector<int> below_alone(static_cast<std::size_t>(channels), 0);
        for (const Vec3* side : {static_cast<const Vec3*>(nullptr), &normal})
            for (int c = 0; c < channels; ++c) {
                const std::string where = "channel " + std::to_string(c) + (side ? ", product" : "");
                // ∫ pdf over the square by a fine midpoint grid (finer than the smallest leaf).
                constexpr int kGrid = 2048;
                double integral = 0;
                for (int j = 0; j < kGrid; ++j)
                    for (int i = 0; i < kGrid; ++i)
                        integral += tree.pdf(c, {(i + 0.5) / kGrid, (j + 0.5) / kGrid}, side);
                EXPECT_NEAR(integral / (double(kGrid) * kGrid), 1.0, 2e-3) << where;

                // Samples against the density on a 32 x 32 grid of cells (chi-square), and each
                // sample's stated density against pdf() at its point.
                constexpr int kCells = 32, kSamples = 400000;
                std::vector<double> observed(kCells * kCells, 0.0), expected(kCells * kCells, 0.0);
                std::mt19937 rng(7 + c);
                std::uniform_real_distribution<double> uni(0.0, 1.0);
                int mismatched = 0, below = 0;
                for (int i = 0; i < kSamples; ++i) {
                    float pdf = 0.f;
                    const SquarePoint s = tree.sample(c, uni(rng), uni(rng), pdf, side);
                    ASSERT_TRUE(s.u >= 0 && s.u < 1 && s.v >= 0 && s.v < 1) << where;
                    if (!(std::fabs(pdf - tree.pdf(c, s, side)) <= 1e-4f * pdf)) ++mismatched;
                    if (dot(square_to_direction(s), normal) < 0.f) ++below;
                    observed[static_cast<std::size_t>(int(s.v * kCells) * kCells + int(s.u * kCells))] += 1;
                }
                EXPECT_EQ(mismatched, 0) << where;
                // The product sends only what straddling leaves hold below the surface.
                // The product sends only what straddling leaves hold below the surface (here,
                // with leaves as coarse as 1/16 of the sphere, about 2/3 of what the field alone
                // sends), and nothing around the direction opposite the normal.
                if (!side) below_alone[c] = below;
                if (side) {
                    EXPECT_LT(below, 0.8 * below_alone[c]) << where;
                    EXPECT_EQ(tree.pdf(c, direction_to_square(-normal), side), 0.f) << where;
                }
                constexpr int kSub = 64;  // midpoints per cell side for the expected counts
                for (int cy = 0; cy < kCells; ++cy)
                    for (int cx = 0; cx < kCells; ++cx) {
                        double e = 0;
                        for (int j = 0; j < kSub; ++j)
                            for (int i = 0; i < kSub; ++i)
                                e += tree.pdf(c, {(cx + (i + 0.5) / kSub) / kCells, (cy + (j + 0.5) / kSub) / kCells},
                                              side);
                        expected[static_cast<std::size_t>(cy * kCells + cx)] =
                            e / (kSub * kSub) / (kCells * kCells) * kSamples;
                    }
                const spt_test::Chi2Result r = spt_test::chi2_test(observed, expected);
                EXPECT_GT(r.p_value, 1e-4) << where;
            }
    }
}

TEST(GuidingField, RecordsInAnyOrderGiveTheSameField) {
    // The same records, added by one thread in order and by four threads interleaved.
    struct Record {
        Vec3 p;
        SquarePoint s;
        int channel;
        float value;
    };
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    std::vector<Record> records;
    for (int i = 0; i < 200000; ++i)
        records.push_back({{uni(rng) * 2 - 1, uni(rng) * 2 - 1, uni(rng) * 2 - 1},
                           {uni(rng), uni(rng)},
                           int(uni(rng) * kGuideBands) % kGuideBands,
                           uni(rng) < 0.1f ? 1e3f * uni(rng) : uni(rng)});
    auto train = [&](int threads) {
        GuidingField field({0, 0, 0}, 1.f, kGuideBands);
        field.set_unit(1e-6);
        for (int iteration = 0; iteration < 3; ++iteration) {
            std::vector<std::thread> pool;
            for (int t = 0; t < threads; ++t)
                pool.emplace_back([&, t] {
                    // Thread t takes every threads-th record, from the end when t is odd.
                    for (std::size_t k = 0; k < records.size(); ++k) {
                        const std::size_t i = t % 2 ? records.size() - 1 - k : k;
                        if (int(i % std::size_t(threads)) != t) continue;
                        const int leaf = field.leaf_of(records[i].p);
                        field.record(leaf, records[i].s, records[i].channel, records[i].value);
                        field.count(leaf);
                        field.record_moments(leaf, records[i].value, 1.f, records[i].s.u * 2, 0.5f);
                    }
                });
            for (std::thread& th : pool) th.join();
            field.end_iteration(1 << iteration);
        }
        return field;
    };
    const GuidingField one = train(1), four = train(4);
    EXPECT_GT(one.leaf_count(), 8);  // 200 000 records per iteration split the space
    EXPECT_TRUE(one == four);
}

TEST(GuidingField, EachLeafChoosesTheFractionOfLeastSecondMoment) {
    // A contribution x of a direction drawn with density p adds x²·p / p_α for each candidate
    // α. Where the guide's density is high where contributions are (a good guide), a large α
    // has the least moment; where it is low there (a bad one), α = 0.
    auto chosen = [](float pdf_guide, float pdf_bsdf) {
        GuidingField field({0, 0, 0}, 1.f, 1);
        field.set_unit(1e-6);
        for (int i = 0; i < 1000; ++i) field.record_moments(0, 1.f + float(i % 7), 0.5f, pdf_guide, pdf_bsdf);
        field.end_iteration(1);
        return field.guide_fraction(0);
    };
    EXPECT_EQ(chosen(8.f, 0.3f), GuidingField::kGuideFractions[3]);
    EXPECT_EQ(chosen(0.01f, 0.3f), GuidingField::kGuideFractions[0]);
    // A leaf without guided records keeps the first fraction.
    GuidingField untouched({0, 0, 0}, 1.f, 1);
    untouched.end_iteration(1);
    EXPECT_EQ(untouched.guide_fraction(0), GuidingField::kGuideFractions[GuidingField::kFirstFraction]);
}

TEST(GuidingSchedule, IterationsDoubleUpToHalfTheSamples) {
    EXPECT_EQ(guiding_iteration_ends(64), (std::vector<int>{1, 3, 7, 15, 31, 64}));
    EXPECT_EQ(guiding_iteration_ends(16), (std::vector<int>{1, 3, 7, 16}));
    EXPECT_EQ(guiding_iteration_ends(1), (std::vector<int>{1}));
    EXPECT_EQ(guiding_iteration_ends(2), (std::vector<int>{1, 2}));
}

TEST(GuideBands, AStratifiedHeroSetHasOneWavelengthPerBand) {
    for (float u = 0.f; u < 1.f; u += 0.0137f) {
        const SampledWavelengths lambda = SampledWavelengths::sample(u);
        int seen = 0;
        for (float l : lambda.lambda) seen |= 1 << guide_band(l);
        EXPECT_EQ(seen, 0xf) << "u = " << u;
    }
}

/// A room lit only through a gap: a wall with a slot splits a box; the emitter, in the far
/// part, faces away from the slot, so the camera's part is lit indirectly (guiding's case).
Scene gap_room() {
    return spt::test::load_exact_scene(R"({
      "camera": {"position": [0, 0, 2.9], "look_at": [0, 0, 0], "up": [0, 1, 0], "vfov_degrees": 60},
      "image": {"width": 24, "height": 24, "spp": 64},
      "materials": {"wall": {"kd": 0.7}, "plastic": {"type": "plastic", "kd": 0.5, "roughness": 0.2}},
      "shapes": [
        {"type": "plane", "normal": [1, 0, 0], "point": [-1, 0, 0], "material": "wall"},
        {"type": "plane", "normal": [-1, 0, 0], "point": [1, 0, 0], "material": "wall"},
        {"type": "plane", "normal": [0, 1, 0], "point": [0, -1, 0], "material": "wall"},
        {"type": "plane", "normal": [0, -1, 0], "point": [0, 1, 0], "material": "wall"},
        {"type": "plane", "normal": [0, 0, 1], "point": [0, 0, -3], "material": "wall"},
        {"type": "plane", "normal": [0, 0, -1], "point": [0, 0, 3], "material": "wall"},
        {"type": "quad", "origin": [-1, -1, -1], "edge1": [2, 0, 0], "edge2": [0, 1.7, 0], "material": "wall"},
        {"type": "quad", "origin": [-1, 0.85, -1], "edge1": [2, 0, 0], "edge2": [0, 0.15, 0], "material": "wall"},
        {"type": "sphere", "center": [0.3, -0.7, 0], "radius": 0.3, "material": "plastic"},
        {"type": "quad", "origin": [-0.3, -0.3, -1.5], "edge1": [0.6, 0, 0], "edge2": [0, 0.6, 0],
         "emission": 40, "two_sided": false}
      ]
    })", "gap_room");
}

RenderSettings guided(RenderSettings s, GuidingMode mode = GuidingMode::luminance) {
    s.guiding = mode;
    return s;
}

/// Guided (both fields) against unguided, independent seeds: every pixel within 5σ and the
/// image means within 5 standard errors.
void expect_guiding_unbiased(const Scene& scene, int spp) {
    const auto plain = render_film(scene, small_settings(24, 24, spp, 1));
    for (GuidingMode mode : {GuidingMode::luminance, GuidingMode::spectral}) {
        const auto guided_film = render_film(scene, guided(small_settings(24, 24, spp, 2), mode));
        EXPECT_EQ(guided_film->rejected_samples(), 0u);
        const spt::test::Comparison c = compare(*plain, *guided_film, [](int, int) { return true; });
        EXPECT_LE(c.max_z, 5.0) << guiding_mode_name(mode) << ": " << describe(c);
        EXPECT_NEAR(c.mean_a, c.mean_b, 5.0 * c.se) << guiding_mode_name(mode) << ": " << describe(c);
    }
}

TEST(GuidedPath, AgreesWithUnguidedThroughAGap) { expect_guiding_unbiased(gap_room(), 1024); }
TEST(GuidedPath, AgreesWithUnguidedInCornellQuad) {
    expect_guiding_unbiased(*load_builtin_scene("cornell-quad", SpectralResolution{}), 512);
}
TEST(GuidedPath, AgreesWithUnguidedWithTextures) {
    expect_guiding_unbiased(*load_builtin_scene("textured", SpectralResolution{}), 256);
}

TEST(GuidedPath, APlantedMisBugIsCaught) {
    // Next-event estimation weighted against the BSDF's density alone, not the mixture's:
    // the two strategies' weights no longer sum to 1. A floor under a large emitter, where the
    // field learns the light and its density is near the light sampler's (the bias shows most).
    const Scene scene = spt::test::load_exact_scene(R"({
      "camera": {"position": [0, 0.4, 0.01], "look_at": [0, 0, 0], "up": [0, 0, -1], "vfov_degrees": 70},
      "materials": {"floor": {"kd": 0.8}},
      "shapes": [
        {"type": "plane", "normal": [0, 1, 0], "point": [0, 0, 0], "material": "floor"},
        {"type": "quad", "origin": [-1, 0.5, -1], "edge1": [2, 0, 0], "edge2": [0, 0, 2], "emission": 5,
         "two_sided": false}
      ]
    })", "lit_floor");
    const auto plain = render_film(scene, small_settings(24, 24, 256, 1));
    RenderSettings bugged = guided(small_settings(24, 24, 256, 2));
    bugged.integrator.guiding_bug = GuidingBug::nee_weight_without_guide;
    const auto film = render_film(scene, bugged);
    const spt::test::Comparison c = compare(*plain, *film, [](int, int) { return true; });
    EXPECT_GT(std::fabs(c.mean_a - c.mean_b), 8.0 * c.se) << describe(c);
    // Without the bug, the same render agrees.
    bugged.integrator.guiding_bug = GuidingBug::none;
    const spt::test::Comparison fixed = compare(*plain, *render_film(scene, bugged), [](int, int) { return true; });
    EXPECT_NEAR(fixed.mean_a, fixed.mean_b, 5.0 * fixed.se) << describe(fixed);
}

TEST(GuidedPath, SameImageWhateverTheThreadsAndPasses) {
    const Scene scene = gap_room();
    RenderSettings one = guided(small_settings(24, 24, 40, 5, 1), GuidingMode::spectral);
    RenderSettings two = one;
    two.threads = 2;
    two.tile = TileShape{5, 5};
    two.pass_spp = 3;  // passes of 3 samples, cut again at the iterations
    RenderSettings threads_only = one;
    threads_only.threads = 2;
    RenderSettings passes_only = two;
    passes_only.threads = 1;
    const auto a = render_film(scene, one), b = render_film(scene, two);
    EXPECT_EQ(count_differences(*a, *b), 0u);
    EXPECT_EQ(count_differences(*a, *render_film(scene, threads_only)), 0u);
    EXPECT_EQ(count_differences(*a, *render_film(scene, passes_only)), 0u);
}

TEST(GuidedPath, ResumedAndSplitRendersEqualTheWholeRender) {
    const Scene scene = gap_room();
    const RenderSettings whole = guided(small_settings(24, 24, 40, 9));
    const auto reference = render_film(scene, whole);
    // Stopped after 5 samples (inside the third iteration), then resumed into the same film.
    for (int cut : {5, 7, 20}) {
        Film film(whole.width, whole.height);
        RenderSettings first = whole;
        first.end_sample = cut;
        render(scene, first, film);
        RenderSettings rest = whole;
        rest.first_sample = cut;
        render(scene, rest, film);
        EXPECT_EQ(count_differences(*reference, film), 0u) << "cut at " << cut;
    }
}

}  // namespace

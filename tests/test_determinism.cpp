// Reproducibility: a seed fixes the image bit for bit, whatever the thread count, tile size or
// pass size; another seed gives another image with the same expectation (ROBUSTNESS case 24).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "scene/builtin_scenes.h"
#include "test_scenes.h"

namespace spt {
namespace {

constexpr double kZ = 5.0;  // z-score bound for the seed comparison (fixed seeds: deterministic)

const Scene& cornell() {
    static const Scene scene = *make_builtin_scene("cornell", SpectralResolution{});
    return scene;
}
const Scene& cornell_point() {
    static const Scene scene = *make_builtin_scene("cornell-point", SpectralResolution{});
    return scene;
}

RenderSettings base_settings() {
    RenderSettings rs;
    rs.width = 32;
    rs.height = 32;
    rs.spp = 8;
    rs.seed = 7;
    rs.threads = 1;
    return rs;
}

using test::count_differences;

TEST(Determinism, ThreadCountDoesNotChangeTheFilm) {
    for (const Scene* scene : {&cornell(), &cornell_point()})
        for (const SamplerKind sampler : kSamplerKinds) {
            RenderSettings rs = base_settings();
            rs.sampler = sampler;
            const auto one = test::render_film(*scene, rs);
            ASSERT_GT(test::image_mean_y(*one).mean, 0.0);
            for (const int threads : {2, 7}) {
                rs.threads = threads;
                const auto many = test::render_film(*scene, rs);
                EXPECT_EQ(count_differences(*one, *many), 0u)
                    << scene->name << ", " << threads << " threads, " << sampler_name(sampler);
            }
        }
}

TEST(Determinism, RepeatedRenderIsIdentical) {
    RenderSettings rs = base_settings();
    rs.threads = 2;
    const auto a = test::render_film(cornell(), rs);
    const auto b = test::render_film(cornell(), rs);
    EXPECT_EQ(count_differences(*a, *b), 0u);
}

TEST(Determinism, TileAndPassSizesDoNotChangeTheFilm) {
    for (const SamplerKind sampler : kSamplerKinds) {
        RenderSettings rs = base_settings();
        rs.sampler = sampler;
        rs.threads = 2;
        rs.tile = {32, 32};
        rs.pass_spp = 8;
        const auto reference = test::render_film(cornell(), rs);
        struct Variant {
            int tile_size, pass_spp;
        };
        for (const Variant v : {Variant{8, 8}, Variant{32, 1}, Variant{8, 1}, Variant{5, 3}, Variant{1, 8},
                                Variant{64, 0}}) {
            rs.tile = {v.tile_size, v.tile_size};
            rs.pass_spp = v.pass_spp;
            RenderStats stats;
            const auto film = test::render_film(cornell(), rs, &stats);
            EXPECT_EQ(count_differences(*reference, *film), 0u)
                << "tile " << v.tile_size << ", pass " << v.pass_spp << ", " << sampler_name(sampler);
            EXPECT_EQ(stats.paths, 32u * 32u * 8u);
            if (v.pass_spp > 0) {
                EXPECT_EQ(stats.passes_total, (8 + v.pass_spp - 1) / v.pass_spp);
            }
        }
    }
}

/// Timed passes (RenderSettings::pass_seconds, for live previews) start with one sample, are
/// sized from the measured pace within [1, effective_pass_spp], and leave the film unchanged.
TEST(Determinism, TimedPassesDoNotChangeTheFilm) {
    RenderSettings rs = base_settings();
    rs.threads = 2;
    rs.spp = 40;
    const auto reference = test::render_film(cornell(), rs);
    rs.pass_seconds = 1e-3;  // about a millisecond: passes of a few samples
    std::vector<int> ends;
    RenderHooks hooks;
    hooks.pass_completed = [&](int samples) { ends.push_back(samples); };
    Film film(rs.width, rs.height);
    const RenderStats stats = render(cornell(), rs, film, hooks);
    EXPECT_EQ(count_differences(*reference, film), 0u);
    ASSERT_GE(ends.size(), 2u);
    EXPECT_EQ(ends.front(), 1) << "the first timed pass has one sample";
    EXPECT_EQ(ends.back(), rs.spp);
    for (std::size_t i = 1; i < ends.size(); ++i) {
        EXPECT_GE(ends[i] - ends[i - 1], 1);
        EXPECT_LE(ends[i] - ends[i - 1], effective_pass_spp(rs));
    }
    EXPECT_EQ(stats.passes_completed, static_cast<int>(ends.size()));
    EXPECT_EQ(stats.passes_total, stats.passes_completed);
}

/// render() and render_pixel() driven by hand agree: the pixel is the unit of determinism.
TEST(Determinism, RenderPixelMatchesRender) {
    const RenderSettings rs = base_settings();
    const auto whole = test::render_film(cornell(), rs);
    Film film(rs.width, rs.height);
    const Camera camera(cornell().camera, rs.width, rs.height);
    PathStats stats;
    // Pixels in reverse order, samples split in two calls: the order between pixels is free.
    for (int y = rs.height - 1; y >= 0; --y)
        for (int x = rs.width - 1; x >= 0; --x) {
            render_pixel(cornell(), rs, camera, x, y, 0, 3, film, stats);
            render_pixel(cornell(), rs, camera, x, y, 3, rs.spp, film, stats);
        }
    EXPECT_EQ(count_differences(*whole, film), 0u);
}

/// Another seed: a different film whose mean agrees within kZ·σ (the two renders are
/// independent, so σ² = σ₁² + σ₂²). Checked on the image mean and on every pixel.
TEST(Determinism, DifferentSeedDiffersButAgreesStatistically) {
    RenderSettings rs = base_settings();
    rs.threads = 2;
    rs.spp = 32;
    const auto a = test::render_film(cornell(), rs);
    rs.seed = 8;
    const auto b = test::render_film(cornell(), rs);
    const std::size_t diff = count_differences(*a, *b);
    EXPECT_GT(diff, a->xyz_sums().size() / 2) << "a new seed must change most pixels";

    const auto ma = test::image_mean_y(*a), mb = test::image_mean_y(*b);
    const double sigma = std::hypot(ma.standard_error, mb.standard_error);
    EXPECT_NEAR(ma.mean, mb.mean, kZ * sigma) << "σ = " << sigma;
    EXPECT_LT(sigma, 0.02 * ma.mean) << "too noisy to mean anything";
    double max_z = 0;
    for (int y = 0; y < rs.height; ++y)
        for (int x = 0; x < rs.width; ++x) {
            const double s = std::hypot(a->pixel_y_standard_error(x, y), b->pixel_y_standard_error(x, y));
            if (s == 0) {
                EXPECT_EQ(a->pixel_xyz(x, y).y, b->pixel_xyz(x, y).y) << x << ", " << y;
                continue;
            }
            max_z = std::max(max_z, std::fabs(a->pixel_xyz(x, y).y - b->pixel_xyz(x, y).y) / s);
        }
    // 1024 pixels at 32 spp: the per-pixel σ comes from few samples, so allow the 5σ bound
    // plus the t-distribution's heavier tail (t with 31 dof: P(|t| > 6) ≈ 1e-6 per pixel).
    EXPECT_LE(max_z, 6.0);
}

/// Seeds are used in full: seeds differing only in high bits give different images.
TEST(Determinism, HighSeedBitsMatter) {
    RenderSettings rs = base_settings();
    rs.width = rs.height = 8;
    rs.spp = 2;
    rs.seed = 7;
    const auto a = test::render_film(cornell(), rs);
    rs.seed = 7 + (std::uint64_t(1) << 40);
    const auto b = test::render_film(cornell(), rs);
    EXPECT_GT(count_differences(*a, *b), a->xyz_sums().size() / 2);
}

}  // namespace
}  // namespace spt

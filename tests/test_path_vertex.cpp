// The path kernel's shared per-vertex steps (render/path_vertex.h): Russian roulette keeps
// the estimate unbiased and spares the first bounces; the MIS state after a bounce.
#include <gtest/gtest.h>

#include <cmath>

#include "core/rng.h"
#include "render/path_vertex.h"

namespace spt {
namespace {

IntegratorSettings roulette_from(int depth) {
    IntegratorSettings s;
    s.roulette_depth = depth;
    return s;
}

TEST(PathVertex, RouletteSparesTheFirstBouncesAndDrawsNothingThere) {
    const IntegratorSettings settings = roulette_from(3);
    Rng rng(7, 1, 2), untouched = rng;
    SampledSpectrum beta(1e-6f);
    for (int depth = 0; depth + 1 < settings.roulette_depth; ++depth)
        EXPECT_TRUE(survives_roulette(settings, depth, [&] { return beta.max_value(); }, beta, rng));
    EXPECT_EQ(beta[0], 1e-6f);
    EXPECT_EQ(rng.uniform(), untouched.uniform());  // no number drawn
    IntegratorSettings off = roulette_from(0);
    off.roulette = false;
    EXPECT_TRUE(survives_roulette(off, 50, [&] { return beta.max_value(); }, beta, rng));
}

// E[beta after roulette] = beta: survival with probability q and beta/q. Planted bug: a
// survivor not divided by q would give a mean q·beta, far outside the bound.
TEST(PathVertex, RouletteIsUnbiased) {
    const IntegratorSettings settings = roulette_from(0);
    for (const float throughput : {0.05f, 0.3f, 0.9f, 3.f}) {
        Rng rng(11, 0, 0);
        const int n = 200000;
        double sum = 0, sum2 = 0;
        int survived = 0;
        for (int i = 0; i < n; ++i) {
            SampledSpectrum beta(0.5f);
            const bool ok = survives_roulette(settings, 0, [&] { return throughput; }, beta, rng);
            const double v = ok ? beta[0] : 0.0;
            survived += ok;
            sum += v, sum2 += v * v;
        }
        const double mean = sum / n, sd = std::sqrt((sum2 / n - mean * mean) / n);
        EXPECT_NEAR(mean, 0.5, 5 * sd + 1e-9) << throughput;
        // Survival probability min(0.95, throughput): lossless paths still end.
        const double q = std::min(0.95, double(throughput));
        EXPECT_NEAR(double(survived) / n, q, 5 * std::sqrt(q * (1 - q) / n)) << throughput;
    }
}

TEST(PathVertex, EmissionMisAfterABounce) {
    BsdfSample diffuse{{0, 0, 1}, SampledSpectrum(1.f), 0.4f, BsdfFlags{static_cast<std::uint8_t>(BsdfFlags::reflection | BsdfFlags::non_delta)}, 1.f};
    BsdfSample mirror = diffuse;
    mirror.flags = BsdfFlags{static_cast<std::uint8_t>(BsdfFlags::reflection | BsdfFlags::delta)};
    mirror.pdf = 0.f;
    LightSampleContext ctx;
    ctx.p = {1, 2, 3};
    EmissionMis mis;
    mis.leave(diffuse, LightSampling::mis, ctx);
    EXPECT_TRUE(mis.on);
    EXPECT_EQ(mis.prev_pdf, 0.4f);
    EXPECT_EQ(mis.prev_ctx.p.y, 2.f);
    // After a delta bounce no light sample could have found the emission: weight 1.
    mis.leave(mirror, LightSampling::mis, ctx);
    EXPECT_FALSE(mis.on);
    // Light sampling alone: emission found after a non-delta bounce gets weight 0 (density
    // 0 for the BSDF side) except from lights never sampled.
    mis.leave(diffuse, LightSampling::light, ctx);
    EXPECT_TRUE(mis.on);
    EXPECT_EQ(mis.prev_pdf, 0.f);
    mis.leave(mirror, LightSampling::light, ctx);
    EXPECT_FALSE(mis.on);
}

}  // namespace
}  // namespace spt

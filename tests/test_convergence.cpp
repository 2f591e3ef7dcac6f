// Convergence: with an unbiased estimator the relative MSE against a reference falls as 1/N
// with the samples per pixel N; a flatter slope means bias (clamping, truncation, NaN-zeroing).
// Both Cornell boxes, log-log slope within 10% of -1 (issue 6; ROBUSTNESS.md case 23).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "render/renderer.h"
#include "scene/builtin_scenes.h"

namespace {

using namespace spt;

std::vector<double> render_y(const Scene& scene, int size, int spp, std::uint64_t seed) {
    RenderSettings rs;
    rs.width = rs.height = size;
    rs.spp = spp;
    rs.seed = seed;
    rs.threads = 2;
    // Independent samples: their relMSE falls as exactly 1/N (a scrambled net's may fall faster).
    rs.sampler = SamplerKind::independent;
    Film film(size, size);
    render(scene, rs, film);
    EXPECT_EQ(film.rejected_samples(), 0u);
    std::vector<double> y;
    for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) y.push_back(film.pixel_xyz(i, j).y);
    return y;
}

/// Least-squares slope of log(relMSE) against log(spp).
double convergence_slope(const std::string& name) {
    const Scene scene = *make_builtin_scene(name, SpectralResolution{});
    constexpr int kSize = 12, kReferenceSpp = 16384;
    const std::vector<double> ref = render_y(scene, kSize, kReferenceSpp, 1000);
    const std::vector<int> spps = {4, 16, 64, 256};
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (int spp : spps) {
        // Average over independent seeds so the estimate of the MSE is itself precise.
        double rel_mse = 0;
        constexpr int kSeeds = 4;
        for (int s = 0; s < kSeeds; ++s) {
            const std::vector<double> y = render_y(scene, kSize, spp, 1 + s);
            for (std::size_t i = 0; i < y.size(); ++i)
                rel_mse += (y[i] - ref[i]) * (y[i] - ref[i]) / (ref[i] * ref[i] + 1e-2);
        }
        rel_mse /= kSeeds * double(ref.size());
        // Remove the reference's own noise, which is spp/reference_spp of the render's.
        rel_mse /= 1.0 + double(spp) / kReferenceSpp;
        const double x = std::log(double(spp)), l = std::log(rel_mse);
        sx += x, sy += l, sxx += x * x, sxy += x * l;
    }
    const double n = double(spps.size());
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

TEST(Convergence, CornellRelativeMseFallsAsOneOverN) {
    const double slope = convergence_slope("cornell");
    RecordProperty("slope", std::to_string(slope));
    std::printf("cornell relMSE slope %.3f\n", slope);
    EXPECT_NEAR(slope, -1.0, 0.1);
}

TEST(Convergence, CornellPointRelativeMseFallsAsOneOverN) {
    const double slope = convergence_slope("cornell-point");
    RecordProperty("slope", std::to_string(slope));
    std::printf("cornell-point relMSE slope %.3f\n", slope);
    EXPECT_NEAR(slope, -1.0, 0.1);
}

}  // namespace

// A vcm render kept pass by pass, for tests whose error bars must respect vcm's
// correlations: every pixel of a pass shares the pass's wavelengths and photons, so a mean
// over pixels takes its standard error from the spread of the per-pass means.
#pragma once
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "render/film.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "test_scenes.h"

namespace spt::test {

/// A vcm render kept pass by pass: every pixel's Y of each pass (its camera sample plus the
/// splats of that pass's light subpaths), from the film after each pass. All pixels of a pass
/// share the wavelengths and the photons, so errors of means over pixels are taken from the
/// spread of the per-pass means, not from the pixels' errors as if independent.
struct PassImages {
    int width = 0, height = 0, passes = 0;
    std::vector<double> y;  ///< y[pass·pixels + pixel]
    std::unique_ptr<Film> film;

    double at(int pass, int x, int yy) const { return y[std::size_t(pass) * width * height + std::size_t(yy) * width + x]; }
    /// Mean over passes and its standard error, of the mean over the pixels where mask holds.
    template <typename Mask>
    ImageMean region(Mask mask) const {
        double sum = 0, sum2 = 0;
        for (int k = 0; k < passes; ++k) {
            double m = 0;
            int n = 0;
            for (int j = 0; j < height; ++j)
                for (int i = 0; i < width; ++i)
                    if (mask(i, j)) m += at(k, i, j), ++n;
            m /= n;
            sum += m, sum2 += m * m;
        }
        const double mean = sum / passes;
        return {mean, std::sqrt(std::max(0.0, sum2 / passes - mean * mean) / (passes - 1))};
    }
    ImageMean pixel(int x, int yy) const {
        return region([&](int i, int j) { return i == x && j == yy; });
    }
};

inline PassImages render_passes(const Scene& scene, const RenderSettings& rs) {
    PassImages p;
    p.width = rs.width, p.height = rs.height;
    p.film = std::make_unique<Film>(rs.width, rs.height);
    const std::size_t n = std::size_t(rs.width) * rs.height;
    std::vector<double> prev(n, 0.0);
    RenderHooks hooks;
    hooks.pass_completed = [&](int end) {
        for (int j = 0; j < rs.height; ++j)
            for (int i = 0; i < rs.width; ++i) {
                const std::size_t k = std::size_t(j) * rs.width + i;
                const double s = p.film->pixel_xyz(i, j).y * end;  // Σ camera + Σ splats
                p.y.push_back(s - prev[k]);
                prev[k] = s;
            }
        ++p.passes;
    };
    render(scene, rs, *p.film, hooks);
    return p;
}


}  // namespace spt::test

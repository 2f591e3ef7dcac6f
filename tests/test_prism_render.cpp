// The prism scene disperses: in a small render of its screen (tests/scenes/prism_small.json:
// the prism scene with a wider slit and lamp, the camera cropped on the band) the hue
// centroids along the band are ordered violet/blue, green/yellow, red in the direction of
// decreasing deviation, and the band spans red to blue. The same scene with a constant index
// (prism_small_constant.json) gives a white band, and the check must fail on it.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "scene/scene_loader.h"
#include "spectral/color_space.h"
#include "test_scenes.h"

namespace spt {
namespace {

struct BandOrder {
    double centroid[3] = {0, 0, 0};  ///< energy-weighted mean column of blue, green, red columns
    double share[3] = {0, 0, 0};     ///< their fractions of the band's energy
    bool ordered() const {
        for (double s : share)
            if (s < 0.05) return false;  // the band must span red to blue
        return centroid[0] < centroid[1] && centroid[1] < centroid[2];
    }
};

/// HSV hue in degrees of a linear RGB triple (negative components clamped).
double hue_degrees(double r, double g, double b, double& saturation) {
    r = std::max(r, 0.0), g = std::max(g, 0.0), b = std::max(b, 0.0);
    const double mx = std::max({r, g, b}), mn = std::min({r, g, b}), c = mx - mn;
    saturation = mx > 0 ? c / mx : 0;
    if (c <= 0) return 0;
    double h = mx == r ? std::fmod((g - b) / c + 6.0, 6.0) : mx == g ? (b - r) / c + 2.0 : (r - g) / c + 4.0;
    return 60.0 * h;
}

/// Columns (the camera's x runs along the dispersion: left = more deviated) summed over rows,
/// classified by hue; only saturated columns of the band count.
BandOrder analyse_band(const std::string& scene_file) {
    const Scene scene = load_scene_file(std::string(SPT_TEST_DIR) + "/scenes/" + scene_file, SpectralResolution{});
    const auto film = test::render_film(scene, test::small_settings(64, 16, 768, 5));
    const Image image = film->develop(srgb_color_space());
    std::vector<std::array<double, 3>> columns(image.width, {0, 0, 0});
    double max_energy = 0;
    for (int x = 0; x < image.width; ++x) {
        for (int y = 0; y < image.height; ++y)
            for (int k = 0; k < 3; ++k) columns[x][k] += image.pixel(x, y)[k];
        max_energy = std::max(max_energy, columns[x][0] + columns[x][1] + columns[x][2]);
    }
    BandOrder order;
    double weight[3] = {0, 0, 0}, total = 0;
    for (int x = 0; x < image.width; ++x) {
        const auto& c = columns[x];
        const double energy = c[0] + c[1] + c[2];
        if (energy < 0.1 * max_energy) continue;  // outside the band
        total += energy;
        double saturation = 0;
        const double h = hue_degrees(c[0], c[1], c[2], saturation);
        if (saturation < 0.5) continue;  // white light is no colour
        const int cls = (h < 45 || h >= 330) ? 2 : h < 165 ? 1 : 0;  // red, green-yellow, blue-violet
        order.centroid[cls] += energy * x;
        weight[cls] += energy;
    }
    for (int k = 0; k < 3; ++k) {
        if (weight[k] > 0) order.centroid[k] /= weight[k];
        order.share[k] = total > 0 ? weight[k] / total : 0;
    }
    return order;
}

TEST(PrismRender, SpectrumOnTheScreenIsOrderedRedLeastDeviated) {
    const BandOrder o = analyse_band("prism_small.json");
    EXPECT_TRUE(o.ordered()) << "centroids (blue, green, red) " << o.centroid[0] << ", " << o.centroid[1] << ", "
                             << o.centroid[2] << "; shares " << o.share[0] << ", " << o.share[1] << ", " << o.share[2];
}

TEST(PrismRender, ConstantIndexGivesNoSpectrum) {
    const BandOrder o = analyse_band("prism_small_constant.json");
    EXPECT_FALSE(o.ordered()) << "shares " << o.share[0] << ", " << o.share[1] << ", " << o.share[2];
    EXPECT_LT(o.share[0] + o.share[1] + o.share[2], 0.3) << "a non-dispersive prism's band is white";
}

}  // namespace
}  // namespace spt

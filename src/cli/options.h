// Command-line options of the pathtracer program and their parser.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/tev_client.h"
#include "render/integrator.h"
#include "spectral/spectrum.h"

namespace spt {

/// A bad flag or value: the message is one line naming the flag and the accepted values.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct Options {
    std::string scene = "cornell";
    std::optional<int> spp, width, height;  ///< unset: the scene's defaults
    std::vector<std::string> outputs;       ///< unset: "<scene>.png"
    std::uint64_t color_resolution = 1ull << 25;
    SpectralResolution spectral;
    std::string color_space = "srgb";
    int threads = 0;
    std::uint64_t seed = 0;
    int max_depth = -1;
    IntegratorKind integrator = IntegratorKind::path;
    LightSampling light_sampling = LightSampling::mis;  ///< path: how emitters are found
    double merge_radius = 0;          ///< vcm's first radius; 0: automatic
    int wavelengths_per_path = 4;  ///< 1 or 4
    bool dispersion = true;        ///< false: dispersive glass gets its mean index
    int pass_spp = 0;  ///< samples per pass (0: automatic); does not change the image
    double exposure = 0.0;
    std::string checkpoint;            ///< save the film state here (empty: never)
    double time_limit = 0;  ///< seconds (0: none): no pass is started that would end later
    double checkpoint_interval = 300;  ///< seconds between checkpoints (after a whole pass)
    std::string resume;                ///< continue the render saved in this checkpoint
    /// Seconds between preview files (the outputs' partial names, rewritten during the
    /// render); unset: none. 0: after every pass.
    std::optional<double> preview_interval;
    std::optional<DisplayServerAddress> display_server;  ///< a tev viewer to show the render in
    bool quiet = false;
    bool show_help = false;
    bool show_version = false;
    bool list_scenes = false;
    /// --rgb-to-spectrum R,G,B: print the fitted spectrum of an RGB reflectance and exit
    /// (a diagnostic hook for validation/test_rgb_fit.py).
    std::optional<std::array<double, 3>> rgb_to_spectrum;
};

/// Parses argv (without the program name). Throws UsageError.
Options parse_options(const std::vector<std::string>& args);

/// The --help text.
std::string usage_text();

}  // namespace spt

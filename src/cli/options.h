// Command-line options of the pathtracer program and their parser.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "io/tone_map.h"
#include "io/tev_client.h"
#include "render/integrator.h"
#include "render/sampler_kind.h"
#include "render/renderer.h"
#include "scene/scene_loader.h"
#include "spectral/chromatic_adaptation.h"
#include "spectral/spectral_bands.h"
#include "spectral/spectrum.h"

namespace spt {

/// A bad flag or value: the message is one line naming the flag and the accepted values.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct Options {
    std::string scene = kDefaultScene;
    std::optional<int> spp, width, height;  ///< unset: the scene's defaults
    std::optional<double> scale;            ///< the scene's size times this (not with width/height)
    std::vector<std::string> outputs;       ///< unset: "<scene>.png"
    std::uint64_t color_resolution = 1ull << 25;
    SpectralResolution spectral{SpectralResolution::kDefaultBins, true};
    std::string color_space = "srgb";
    SpectralBands spectral_bands;  ///< count 0: no spectral channels in the .exr outputs
    std::string sensor;            ///< camera sensitivities (CSV) instead of CIE 1931; empty: none
    int threads = 0;
    TileShape tile;                       ///< --tile (default 32x32)
    QueueKind queue = QueueKind::mutex;   ///< --queue
    Schedule schedule = Schedule::tiles;  ///< --schedule
    std::uint64_t seed = 0;
    // Integrator settings: unset, the scene file's choice applies, else the default.
    std::optional<int> max_depth;                   ///< default: unbounded
    std::optional<IntegratorKind> integrator;       ///< default: path
    std::optional<LightSampling> light_sampling;    ///< path: how emitters are found (default mis)
    std::optional<double> merge_radius;             ///< vcm's first radius (default: automatic)
    int wavelengths_per_path = 4;  ///< 1 or 4
    bool caustic_nee = true;       ///< --caustic-nee (path, light sampling mis)
    bool plane_nee = true;         ///< --plane-nee (path: sample emitting infinite planes)
    LightSelection light_selection = LightSelection::power;  ///< --light-selection (path)
    /// --guiding: on, off, or unset for the automatic choice (cli/guiding_choice.h).
    std::optional<bool> guiding;
    GuidingMode guiding_field = GuidingMode::luminance;  ///< --guiding-field
    std::optional<SamplerKind> sampler;  ///< --sampler (default: default_sampler)
    bool dispersion = true;        ///< false: dispersive glass gets its mean index
    bool strict = false;           ///< every warning about the scene is an error (--strict)
    bool bvh = true;               ///< false: spheres and triangles tested in a loop (--no-bvh)
    int pass_spp = 0;  ///< samples per pass (0: automatic); does not change the image
    double exposure = 0.0;
    bool auto_exposure = false;  ///< PNG: add the stops that take the median luminance to 0.18
    ToneMap tone_map = kDefaultToneMap;  ///< PNG: the curve after exposure
    std::optional<Chromaticity> white_balance;  ///< adapt this white to the output space's white
    std::string checkpoint;            ///< save the film state here (empty: never)
    double time_limit = 0;  ///< seconds (0: none): no pass is started that would end later
    double checkpoint_interval = 300;  ///< seconds between checkpoints (after a whole pass)
    std::string resume;                ///< continue the render saved in this checkpoint
    /// Seconds between preview files (the outputs' partial names, rewritten during the
    /// render); unset: none. 0: after every pass.
    std::optional<double> preview_interval;
    std::optional<DisplayServerAddress> display_server;  ///< a tev viewer to show the render in
    /// --passes A:B: render only passes [A, B) of the render's automatic passes (a partial
    /// film, see partial_films.h); unset: all of them.
    std::optional<std::pair<int, int>> passes;
    bool print_passes = false;  ///< print the render's pass count and size, and exit
    bool quiet = false;
    /// Every flag given, by its long name ("--spp"), for warnings about flags without effect.
    std::set<std::string> given;
    bool show_help = false;
    bool show_version = false;
    bool list_scenes = false;
    /// --export-pbrt FILE: write the scene as a pbrt-v4 file (and the meshes and images it
    /// needs beside it) and exit without rendering; empty: render.
    std::string export_pbrt;
    /// --rgb-to-spectrum R,G,B: print the fitted spectrum of an RGB reflectance and exit
    /// (a diagnostic hook for validation/test_rgb_fit.py).
    std::optional<std::array<double, 3>> rgb_to_spectrum;
    /// --print-adaptation WHITE: print the white-balance matrix from WHITE to the white of
    /// --color-space and exit (a diagnostic hook for validation/test_white_balance.py).
    std::optional<Chromaticity> print_adaptation;
};

/// Parses argv (without the program name). Throws UsageError.
Options parse_options(const std::vector<std::string>& args);

/// Every long flag the parser knows (for "did you mean"; the --help text names each).
const std::vector<std::string>& known_flags();

/// The --help text.
std::string usage_text();

}  // namespace spt

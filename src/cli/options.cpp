// Flag parsing: every value is checked, and errors name the flag and what it accepts.
#include "cli/options.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include "cli/output_names.h"
#include "io/image_writer.h"
#include "spectral/color_space.h"

namespace spt {

namespace {

template <typename T>
T parse_integer(const std::string& flag, const std::string& text, T lo, T hi, const char* what) {
    T value{};
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() || value < lo || value > hi)
        throw UsageError(flag + ": expected " + what + ", got '" + text + "'");
    return value;
}

double parse_real(const std::string& flag, const std::string& text, double lo, double hi,
                  const char* what) {
    double value = 0;
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() ||
        !std::isfinite(value) || value < lo || value > hi)
        throw UsageError(flag + ": expected " + what + ", got '" + text + "'");
    return value;
}

}  // namespace

std::string usage_text() {
    return R"(Usage: pathtracer [SCENE] [options]

Spectral Monte Carlo path tracer. SCENE is a built-in scene name (default: cornell; see
--list-scenes) or a scene file (.json, format in scenes/README.md). An error in a scene file
is reported as FILE:LINE:COLUMN: message, with exit status 1.

Options:
  --spp N                paths per pixel (1 to 1000000; default: the scene's)
  --width W, --height H  image size in pixels (1 to 65536; default: the scene's)
  -o, --output FILE      output image; repeat to write several files from one render.
                         Format by extension: .png (sRGB 8-bit, tone-mapped), .exr and .pfm
                         (linear float), .ppm (P3 with #MAX=). Default: SCENE.png
  --exposure STOPS       PNG exposure adjustment in stops (-20 to 20; default 0)
  --color-resolution R   PPM integer levels (2 to 2^62; default 2^25)
  --color-space NAME     srgb (default), rec2020, acescg or xyz: linear RGB of the .exr, .pfm
                         and .ppm outputs (a .png is always sRGB)
  --spectral-bins N      bins per spectrum, 1 to 1024, or 'exact' to evaluate the
                         analytic spectra at each wavelength (default 16)
  --threads T            worker threads (1 to 1024; default: all cores)
  --seed S               random seed (0 to 2^64-1; default 0); same seed, same image
                         On SIGINT/SIGTERM the unfinished image is written beside each
                         output X.ext as X.partial.ext (X.ext is left as it was) and the
                         program exits with status 130/143.
  --wavelengths-per-path K   4 (default: hero wavelength set) or 1 (hero alone)
  --no-dispersion        give dispersive glass its mean index over 380-780 nm (to measure
                         what dispersion costs)
  --integrator NAME      path (default: unidirectional path tracing), bdpt
                         (bidirectional: light and camera subpaths combined by MIS) or vcm
                         (bdpt plus vertex merging: photon density estimation as one more
                         MIS strategy, for caustics seen through glass; consistent, the
                         radius shrinks with the passes)
  --light-sampling MODE  path: mis (default: light sampling and BSDF sampling combined by
                         multiple importance sampling), bsdf (emitters found only by paths
                         that hit them) or light (light sampling alone); to measure what MIS
                         buys. Point lights are always sampled
  --merge-radius R       vcm: merging radius of the first pass in scene units (default:
                         five pixel footprints at the median distance the camera sees,
                         less where a pilot finds photons dense; at most 1% of the scene)
  --max-depth D          maximum scattering events per path (0 to 100000; default unbounded)
  --time-limit SECONDS   render whole passes until the next one would end after SECONDS
                         (at least one pass); --spp is then the most it renders. For
                         equal-time comparisons: add --pass-spp 1 for a fine granularity
  --checkpoint FILE      save the render state to FILE (atomically) after a whole pass once
                         --checkpoint-interval seconds have passed, and at exit
  --checkpoint-interval SECONDS   0 to 1e6 (default 300)
  --pass-spp N           samples per pixel per pass (default: about 4 million paths per
                         pass); sets checkpoint and interruption granularity, not the image
  --resume FILE          continue the render saved in FILE (same scene and settings);
                         the result is identical to a render run straight through
  --preview-interval SECONDS   while rendering, write each output X.ext as X.partial.ext
                         (atomically) at most every SECONDS (0 to 1e6; 0: after every
                         pass), in passes of about SECONDS/2 unless --pass-spp; a finished
                         render removes them. Default: no previews
  --display-server HOST[:PORT]   show the render in the tev viewer listening there (default
                         port 14158; IPv6 as [ADDR]:PORT): the image, named after the
                         first output, is sent with the previews of --preview-interval, or
                         else after every pass, in passes of about 1 s unless --pass-spp
  --quiet                no progress bar and no summary
  --list-scenes          list the built-in scenes
  -h, --help             this text
  --version              the program version

Diagnostics:
  --rgb-to-spectrum R,G,B  print the spectrum fitted to a linear sRGB reflectance (each in
                         [0, 1]) as 'rgb_sigmoid c0 c1 c2' or 'constant v', and exit
)";
}

Options parse_options(const std::vector<std::string>& args) {
    Options o;
    bool scene_given = false;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& arg = args[i];
        // --flag=value and --flag value are both accepted.
        std::string flag = arg, value;
        bool inline_value = false;
        if (arg.rfind("--", 0) == 0) {
            if (const auto eq = arg.find('='); eq != std::string::npos) {
                flag = arg.substr(0, eq), value = arg.substr(eq + 1), inline_value = true;
            }
        }
        auto next_value = [&]() -> std::string {
            if (inline_value) return value;
            if (i + 1 >= args.size()) throw UsageError(flag + ": missing value");
            return args[++i];
        };
        if (flag == "-h" || flag == "--help") {
            o.show_help = true;
        } else if (flag == "--version") {
            o.show_version = true;
        } else if (flag == "--list-scenes") {
            o.list_scenes = true;
        } else if (flag == "--rgb-to-spectrum") {
            const std::string v = next_value();
            std::array<double, 3> rgb{};
            std::size_t start = 0;
            for (int k = 0; k < 3; ++k) {
                const std::size_t comma = k < 2 ? v.find(',', start) : v.size();
                if (comma == std::string::npos)
                    throw UsageError(flag + ": expected R,G,B with each in [0, 1], got '" + v + "'");
                rgb[k] = parse_real(flag, v.substr(start, comma - start), 0, 1, "R,G,B with each in [0, 1]");
                start = comma + 1;
            }
            o.rgb_to_spectrum = rgb;
        } else if (flag == "--quiet") {
            o.quiet = true;
        } else if (flag == "--spp") {
            o.spp = parse_integer<int>(flag, next_value(), 1, 1000000, "an integer from 1 to 1000000");
        } else if (flag == "--width" || flag == "--height") {
            const int v = parse_integer<int>(flag, next_value(), 1, 65536, "an integer from 1 to 65536");
            (flag == "--width" ? o.width : o.height) = v;
        } else if (flag == "-o" || flag == "--output") {
            const std::string path = next_value();
            if (!image_format_from_path(path))
                throw UsageError(flag + ": expected a file name ending in .png, .exr, .pfm or .ppm, got '" +
                                 path + "'");
            o.outputs.push_back(path);
        } else if (flag == "--exposure") {
            o.exposure = parse_real(flag, next_value(), -20, 20, "a number of stops from -20 to 20");
        } else if (flag == "--color-resolution") {
            o.color_resolution = parse_integer<std::uint64_t>(flag, next_value(), 2, 1ull << 62,
                                                              "an integer from 2 to 2^62");
        } else if (flag == "--color-space") {
            o.color_space = next_value();
            if (!color_space_by_name(o.color_space))
                throw UsageError(flag + ": expected srgb, rec2020, acescg or xyz, got '" +
                                 o.color_space + "'");
        } else if (flag == "--spectral-bins") {
            const std::string v = next_value();
            o.spectral.bins = v == "exact" ? SpectralResolution::kExact
                                           : parse_integer<int>(flag, v, SpectralResolution::kMinBins,
                                                                SpectralResolution::kMaxBins,
                                                                "an integer from 1 to 1024 or 'exact'");
        } else if (flag == "--threads") {
            o.threads = parse_integer<int>(flag, next_value(), 1, 1024, "an integer from 1 to 1024");
        } else if (flag == "--seed") {
            o.seed = parse_integer<std::uint64_t>(flag, next_value(), 0,
                                                  std::numeric_limits<std::uint64_t>::max(),
                                                  "an integer from 0 to 2^64-1");
        } else if (flag == "--checkpoint" || flag == "--resume") {
            const std::string path = next_value();
            if (path.empty()) throw UsageError(flag + ": expected a file name");
            (flag == "--checkpoint" ? o.checkpoint : o.resume) = path;
        } else if (flag == "--checkpoint-interval") {
            o.checkpoint_interval =
                parse_real(flag, next_value(), 0, 1e6, "a number of seconds from 0 to 1000000");
        } else if (flag == "--preview-interval") {
            o.preview_interval =
                parse_real(flag, next_value(), 0, 1e6, "a number of seconds from 0 to 1000000");
        } else if (flag == "--display-server") {
            const std::string v = next_value();
            o.display_server = parse_display_server(v);
            if (!o.display_server)
                throw UsageError(flag + ": expected HOST or HOST:PORT with PORT from 1 to 65535, got '" +
                                 v + "'");
        } else if (flag == "--time-limit") {
            o.time_limit = parse_real(flag, next_value(), 0.001, 1e7,
                                      "a number of seconds from 0.001 to 10000000");
        } else if (flag == "--wavelengths-per-path") {
            const std::string v = next_value();
            if (v != "1" && v != "4")
                throw UsageError(flag + ": expected 1 (hero only) or 4 (hero set), got '" + v + "'");
            o.wavelengths_per_path = v == "1" ? 1 : 4;
        } else if (flag == "--integrator") {
            const std::string v = next_value();
            const std::optional<IntegratorKind> kind = integrator_from_name(v);
            if (!kind) throw UsageError(flag + ": expected path, bdpt or vcm, got '" + v + "'");
            o.integrator = *kind;
        } else if (flag == "--light-sampling") {
            const std::string v = next_value();
            if (v == "mis") o.light_sampling = LightSampling::mis;
            else if (v == "bsdf") o.light_sampling = LightSampling::bsdf;
            else if (v == "light") o.light_sampling = LightSampling::light;
            else throw UsageError(flag + ": expected mis, bsdf or light, got '" + v + "'");
        } else if (flag == "--merge-radius") {
            o.merge_radius = parse_real(flag, next_value(), 1e-12, 1e12, "a radius from 1e-12 to 1e12");
        } else if (flag == "--no-dispersion") {
            o.dispersion = false;
        } else if (flag == "--pass-spp") {
            o.pass_spp = parse_integer<int>(flag, next_value(), 1, 1000000, "an integer from 1 to 1000000");
        } else if (flag == "--max-depth") {
            o.max_depth = parse_integer<int>(flag, next_value(), 0, 100000, "an integer from 0 to 100000");
        } else if (!arg.empty() && arg[0] == '-') {
            throw UsageError(arg + ": unknown option (see --help)");
        } else {
            if (scene_given)
                throw UsageError("SCENE: expected one scene, got '" + o.scene + "' and '" + arg + "'");
            o.scene = arg;
            scene_given = true;
        }
        if (inline_value && (flag == "-h" || flag == "--help" || flag == "--version" ||
                             flag == "--list-scenes" || flag == "--quiet" || flag == "--no-dispersion"))
            throw UsageError(flag + ": takes no value");
    }
    // X.partial.ext is where the unfinished image of X.ext goes: it cannot be an output too.
    for (const std::string& path : o.outputs)
        if (std::find(o.outputs.begin(), o.outputs.end(), partial_output_name(path)) != o.outputs.end())
            throw UsageError("-o: expected names that are not the unfinished-image names of other "
                             "outputs, got '" + path + "' and '" + partial_output_name(path) + "'");
    return o;
}

}  // namespace spt

// Flag parsing: every value is checked, and errors name the flag and what it accepts.
#include "cli/options.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include "core/text.h"
#include "cli/output_names.h"
#include "cli/partial_films.h"
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

/// Combinations the spectral outputs do not support, refused before any work.
void check_spectral_output(const Options& o, bool spectral_range_given) {
    if (!o.sensor.empty() && o.color_space != "srgb")
        throw UsageError("--color-space: not with --sensor (the outputs hold raw camera RGB)");
    if (!o.sensor.empty() && o.white_balance)
        throw UsageError("--white-balance: not with --sensor (the outputs hold raw camera RGB)");
    if (o.spectral_bands.count == 0) {
        if (spectral_range_given) throw UsageError("--spectral-range: needs --spectral-bands N");
        return;
    }
    bool exr = false;
    for (const std::string& path : o.outputs)
        exr |= image_format_from_path(path) == ImageFormat::Exr;
    if (!exr)
        throw UsageError("--spectral-bands: needs an .exr output (-o FILE.exr) to hold the bands");
    // (A scene file's choice of bdpt or vcm is refused once the scene is loaded.)
    if (o.integrator && *o.integrator != IntegratorKind::path)
        throw UsageError(
            "--spectral-bands: only with --integrator path (bdpt and vcm splats are not binned)");
    if (!o.checkpoint.empty() || !o.resume.empty())
        throw UsageError(std::string(o.checkpoint.empty() ? "--resume" : "--checkpoint") +
                         ": not with --spectral-bands (checkpoints do not hold the bands)");
}

}  // namespace

const std::vector<std::string>& known_flags() {
    static const std::vector<std::string> flags = {
        "--help", "--version", "--list-scenes", "--export-pbrt", "--rgb-to-spectrum", "--quiet", "--spp", "--width",
        "--height", "--scale", "--output", "--exposure", "--auto-exposure", "--tonemap", "--white-balance",
        "--print-adaptation", "--color-resolution", "--color-space", "--spectral-bins", "--spectral-bands",
        "--spectral-range", "--sensor", "--preview-interval", "--display-server", "--threads", "--tile", "--queue",
        "--schedule", "--seed",
        "--checkpoint", "--resume", "--checkpoint-interval", "--time-limit", "--wavelengths-per-path",
        "--integrator", "--light-sampling", "--light-selection", "--guiding", "--guiding-field", "--caustic-nee", "--plane-nee", "--merge-radius", "--no-dispersion", "--no-bvh", "--strict", "--pass-spp", "--max-depth",
        "--passes", "--print-passes", "--sampler"};
    return flags;
}

std::string usage_text() {
    return R"(Usage: pathtracer [SCENE] [options]
       pathtracer merge PART.film... -o FILE [-o FILE...] [output options]

Spectral Monte Carlo path tracer. SCENE is a built-in scene name (default: )" + std::string(kDefaultScene) + R"(; see
--list-scenes) or a scene file: .json (format in scenes/README.md) or a pbrt-v4 file (.pbrt;
docs/PBRT.md says what is read and how). An error in a scene file is reported as
FILE:LINE:COLUMN: message, with exit status 1.

Options:
  --spp N                paths per pixel (1 to 1000000; default: the scene's)
  --width W, --height H  image size in pixels (1 to 65536; default: the scene's); with
                         only one of them the other keeps the scene's aspect ratio
  --scale F              the scene's image size times F (0.001 to 100, each side rounded,
                         at least 1); not with --width or --height
  -o, --output FILE      output image; repeat to write several files from one render.
                         Format by extension: .png (sRGB 8-bit, tone-mapped), .exr and .pfm
                         (linear float), .ppm (P3 with #MAX=), .film (a partial film:
                         the film's sums for 'pathtracer merge'; then every output is a
                         .film). Default: the scene's image file (a pbrt Film's
                         filename), else SCENE.png
  --exposure STOPS       PNG exposure adjustment in stops (-20 to 20; default 0)
  --auto-exposure        PNG: also add the stops that bring the median luminance of the
                         non-black pixels to 0.18 (middle grey); the summary prints them
  --tonemap CURVE        PNG tone curve after exposure: neutral (default: Khronos PBR
                         Neutral with F90 = 0, the identity up to 0.8, then a hue-keeping
                         shoulder; a grey reaches white at 9.57), pbr-neutral (the Khronos
                         curve as specified: 0.04 darker, white at 13.5) or clip (each
                         channel clipped at 1). EXR, PFM and PPM are never tone-mapped
  --white-balance WHITE  adapt colours seen under WHITE to the output's white (Bradford),
                         for every output: A, D50, D55, D65, D75, E, F2, F11 (CIE xy) or a
                         temperature 1000K to 25000K (Planckian below 4000 K, CIE daylight
                         above); default: none
  --color-resolution R   PPM integer levels (2 to 2^62; default 2^25)
  --color-space NAME     srgb (default), rec2020, acescg or xyz: linear RGB of the .exr, .pfm
                         and .ppm outputs (a .png is always sRGB)
  --spectral-bands N     also write N spectral channels into every .exr output (1 to 4096):
                         band-averaged spectral radiance, channels S0.<centre>nm (Fichet et
                         al. 2021 layout) beside R, G, B; path integrator only, no checkpoints
  --spectral-range MIN:MAX   wavelength range of the bands in nm (100 to 3000; default
                         360:830). Beyond 360-830 nm half the wavelengths are drawn uniformly
                         over the range, and binned spectra (380-780 nm) hold their end
                         values there: use --spectral-bins exact for the analytic spectra
  --sensor FILE.csv      integrate against a camera's spectral sensitivities (columns
                         wavelength_nm,r,g,b; 360-830 nm) instead of the CIE 1931 observer:
                         the outputs hold raw camera RGB (no colour space; .png: that RGB
                         through the sRGB curve), normalised so a constant spectrum 1 gives g = 1
  --spectral-bins N      bins per spectrum, 1 to 1024, or 'exact' to evaluate the
                         analytic spectra at each wavelength (default 16, more for
                         lights with narrow lines, exact with fluorescence)
  --threads T            worker threads (1 to 1024; default: all cores)
  --tile SHAPE           the tiles workers take (tiles schedule): N (N x N pixels), WxH,
                         rows[:N] (whole-width strips N pixels tall, default 1),
                         columns[:N] (whole-height strips) or pixel (1x1); sides 1 to
                         65536 (default 32). Does not change the image
  --queue KIND           how workers take their tasks: mutex (default: a locked deque),
                         ring (a lock-free ring) or atomic (one atomic counter over the
                         pass's tasks). Does not change the image
  --schedule NAME        tiles (default: each worker traces whole paths of its tiles) or
                         wavefront (batches of 16384 paths through stages: camera rays,
                         intersection, shading, shadow rays, film; every worker on each
                         stage). Path integrator with --sampler independent, no media
                         or textures. Does not change the image
  --seed S               random seed (0 to 2^64-1; default 0); same seed, same image
                         On SIGINT/SIGTERM the unfinished image is written beside each
                         output X.ext as X.partial.ext (X.ext is left as it was) and the
                         program exits with status 130/143.
  --sampler NAME         sobol (default for the path integrator on the tiles schedule:
                         Owen-scrambled Sobol points per pixel, each number at a fixed
                         dimension; bdpt, vcm and media take only the camera sample from
                         it) or independent (default elsewhere: PCG32 numbers)
  --wavelengths-per-path K   4 (default: hero wavelength set) or 1 (hero alone)
  --no-dispersion        give dispersive glass its mean index over 380-780 nm (to measure
                         what dispersion costs)
  --no-bvh               test every sphere and triangle in a loop, without a BVH (to
                         measure what the BVH buys; refused for quadrics and instances)
  --strict               every warning about the scene is an error: a pbrt-v4 parameter
                         or type this renderer does not support, an open glass mesh
  --integrator NAME      path (default: unidirectional path tracing), bdpt
                         (bidirectional: light and camera subpaths combined by MIS) or vcm
                         (bdpt plus vertex merging: photon density estimation as one more
                         MIS strategy, for caustics seen through glass; consistent, the
                         radius shrinks with the passes)
  --light-sampling MODE  path: mis (default: light sampling and BSDF sampling combined by
                         multiple importance sampling), bsdf (emitters found only by paths
                         that hit them) or light (light sampling alone); to measure what MIS
                         buys. Point lights are always sampled
  --light-selection MODE path: how next-event estimation chooses one light: power (default:
                         in proportion to power) or bvh (a light BVH: by likely contribution
                         to the shading point, each emitting triangle on its own; for scenes
                         with many lights). A scene with one light renders the same either way
  --guiding on|off|auto path: path guiding (Mueller et al. 2017): the first samples learn
                         where light comes from (a tree over space and direction, in
                         iterations of 1, 2, 4, ... spp, up to half the samples) and later
                         ones sample it beside the BSDF, each region of space choosing how
                         often. auto (default) is off: at equal time it has not yet beaten
                         plain path tracing in a measured scene (docs/GUIDING.md). Tiles
                         schedule; no media or fluorescence; the specular chains
                         (--caustic-nee) are off under it
  --guiding-field F      luminance (default: one field of the wavelengths' mean radiance)
                         or spectral (a field per quarter of the wavelength range, sampled
                         at the hero wavelength's)
  --caustic-nee on|off   path with --light-sampling mis: specular next-event estimation
                         through smooth glass spheres and off shiny ones (caustics of
                         emitting spheres and quads under glass balls and reflected by
                         mirror-coated or glass balls, weighted by MIS; default on)
  --plane-nee on|off     path: next-event estimation to emitting infinite planes (an
                         emitting ceiling), drawn from what the other planes leave open
                         (default on; off: emission found by BSDF sampling only)
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
  --passes A:B           render only passes A to B-1 (0 <= A < B <= the pass count) of the
                         render's automatic passes into .film outputs, to be merged with
                         the other parts (default: all passes). Not with --pass-spp,
                         --time-limit, checkpoints, previews, --sensor or --spectral-bands
  --print-passes         print 'passes N', 'spp_per_pass K' and 'spp S' of the render and
                         exit (N = ceil(S/K); for splitting it into --passes ranges)
  --quiet                no progress bar and no summary
  --list-scenes          list the built-in scenes
  --export-pbrt FILE.pbrt  write the scene (with --width, --height, --spp applied) as a
                         pbrt-v4 scene file, with the meshes and images it needs that are not
                         on disk beside it, and exit without rendering
  -h, --help             this text
  --version              the program version

Merging: 'pathtracer merge PARTS... -o FILE' combines partial films of one render (same
scene file, settings and seed; disjoint passes, in any order) into the image one render of
all their passes makes, bit for bit. Outputs as above (a .film output: the merged film, if
its samples are contiguous); output options (--color-space, --exposure, --auto-exposure,
--tonemap, --white-balance, --color-resolution, --quiet) apply. Passes missing from every
part are allowed only with .exr outputs (their spp attribute says the samples held).

Diagnostics:
  --rgb-to-spectrum R,G,B  print the spectrum fitted to a linear sRGB reflectance (each in
                         [0, 1]) as 'rgb_sigmoid c0 c1 c2' or 'constant v', and exit
  --print-adaptation WHITE  print the --white-balance WHITE matrix (XYZ to XYZ, to the white
                         of --color-space) with both whites' xy, and exit
)";
}

Options parse_options(const std::vector<std::string>& args) {
    Options o;
    bool scene_given = false, spectral_range_given = false;
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
        } else if (flag == "--export-pbrt") {
            o.export_pbrt = next_value();
            if (!o.export_pbrt.ends_with(".pbrt"))
                throw UsageError(flag + ": expected a file name ending in .pbrt, got '" + o.export_pbrt + "'");
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
        } else if (flag == "--white-balance" || flag == "--print-adaptation") {
            const std::string v = next_value();
            const std::optional<Chromaticity> white = parse_white(v);
            if (!white)
                throw UsageError(flag + ": expected A, D50, D55, D65, D75, E, F2, F11 or a "
                                        "temperature from 1000K to 25000K, got '" + v + "'." +
                                 suggestion(v, {"A", "D50", "D55", "D65", "D75", "E", "F2", "F11"}));
            (flag == "--white-balance" ? o.white_balance : o.print_adaptation) = white;
        } else if (flag == "--tonemap") {
            const std::string v = next_value();
            const std::optional<ToneMap> map = tone_map_from_name(lowercase(v));
            if (!map)
                throw UsageError(flag + ": expected neutral, pbr-neutral or clip, got '" + v + "'." +
                                 suggestion(v, {"neutral", "pbr-neutral", "clip"}));
            o.tone_map = *map;
        } else if (flag == "--auto-exposure") {
            o.auto_exposure = true;
        } else if (flag == "--scale") {
            o.scale = parse_real(flag, next_value(), 0.001, 100, "a factor from 0.001 to 100");
        } else if (flag == "--quiet") {
            o.quiet = true;
        } else if (flag == "--spp") {
            o.spp = parse_integer<int>(flag, next_value(), 1, 1000000, "an integer from 1 to 1000000");
        } else if (flag == "--width" || flag == "--height") {
            const int v = parse_integer<int>(flag, next_value(), 1, 65536, "an integer from 1 to 65536");
            (flag == "--width" ? o.width : o.height) = v;
        } else if (flag == "-o" || flag == "--output") {
            const std::string path = next_value();
            if (!image_format_from_path(path) && !is_partial_film_path(path))
                throw UsageError(flag + ": expected a file name ending in .png, .exr, .pfm, .ppm or .film, "
                                 "got '" + path + "'");
            o.outputs.push_back(path);
        } else if (flag == "--exposure") {
            o.exposure = parse_real(flag, next_value(), -20, 20, "a number of stops from -20 to 20");
        } else if (flag == "--color-resolution") {
            o.color_resolution = parse_integer<std::uint64_t>(flag, next_value(), 2, 1ull << 62,
                                                              "an integer from 2 to 2^62");
        } else if (flag == "--color-space") {
            o.color_space = lowercase(next_value());
            if (!color_space_by_name(o.color_space))
                throw UsageError(flag + ": expected srgb, rec2020, acescg or xyz, got '" +
                                 o.color_space + "'");
        } else if (flag == "--spectral-bins") {
            const std::string v = next_value();
            o.spectral.automatic = false;
            o.spectral.bins = equal_ignoring_case(v, "exact") ? SpectralResolution::kExact
                                           : parse_integer<int>(flag, v, SpectralResolution::kMinBins,
                                                                SpectralResolution::kMaxBins,
                                                                "an integer from 1 to 1024 or 'exact'");
        } else if (flag == "--spectral-bands") {
            o.spectral_bands.count =
                parse_integer<int>(flag, next_value(), 1, 4096, "an integer from 1 to 4096");
        } else if (flag == "--spectral-range") {
            const std::string v = next_value();
            const std::size_t colon = v.find(':');
            const char* what = "MIN:MAX in nm, 100 <= MIN < MAX <= 3000";
            if (colon == std::string::npos)
                throw UsageError(flag + ": expected " + what + ", got '" + v + "'");
            o.spectral_bands.min_nm = parse_real(flag, v.substr(0, colon), 100, 3000, what);
            o.spectral_bands.max_nm = parse_real(flag, v.substr(colon + 1), 100, 3000, what);
            if (!(o.spectral_bands.min_nm < o.spectral_bands.max_nm))
                throw UsageError(flag + ": expected " + what + ", got '" + v + "'");
            spectral_range_given = true;
        } else if (flag == "--sensor") {
            o.sensor = next_value();
            if (o.sensor.empty()) throw UsageError(flag + ": expected a file name (.csv)");
        } else if (flag == "--threads") {
            o.threads = parse_integer<int>(flag, next_value(), 1, 1024, "an integer from 1 to 1024");
        } else if (flag == "--tile") {
            const std::string v = next_value();
            const std::optional<TileShape> shape = parse_tile_shape(lowercase(v));
            if (!shape)
                throw UsageError(flag + ": expected N, WxH, rows[:N], columns[:N] or pixel (sides 1 to 65536), got '" +
                                 v + "'");
            o.tile = *shape;
        } else if (flag == "--queue") {
            const std::string v = next_value();
            const std::optional<QueueKind> kind = queue_kind_from_name(lowercase(v));
            if (!kind)
                throw UsageError(flag + ": expected mutex, ring or atomic, got '" + v + "'." +
                                 suggestion(v, {"mutex", "ring", "atomic"}));
            o.queue = *kind;
        } else if (flag == "--schedule") {
            const std::string v = next_value();
            const std::string name = lowercase(v);
            if (name != "tiles" && name != "wavefront")
                throw UsageError(flag + ": expected tiles or wavefront, got '" + v + "'." +
                                 suggestion(v, {"tiles", "wavefront"}));
            o.schedule = name == "tiles" ? Schedule::tiles : Schedule::wavefront;
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
            o.integrator = integrator_from_name(v);
            if (!o.integrator)
                throw UsageError(flag + ": expected path, bdpt or vcm, got '" + v + "'." +
                                 suggestion(v, integrator_names()));
        } else if (flag == "--sampler") {
            const std::string v = next_value();
            const std::optional<SamplerKind> kind = sampler_from_name(v);
            if (!kind)
                throw UsageError(flag + ": expected independent or sobol, got '" + v + "'." +
                                 suggestion(v, sampler_names()));
            o.sampler = *kind;
        } else if (flag == "--light-sampling") {
            const std::string v = next_value();
            o.light_sampling = light_sampling_from_name(v);
            if (!o.light_sampling)
                throw UsageError(flag + ": expected mis, bsdf or light, got '" + v + "'." +
                                 suggestion(v, light_sampling_names()));
        } else if (flag == "--light-selection") {
            const std::string v = next_value();
            const std::optional<LightSelection> mode = light_selection_from_name(v);
            if (!mode)
                throw UsageError(flag + ": expected power or bvh, got '" + v + "'." +
                                 suggestion(v, light_selection_names()));
            o.light_selection = *mode;
        } else if (flag == "--guiding") {
            const std::string v = next_value();
            if (v != "on" && v != "off" && v != "auto")
                throw UsageError(flag + ": expected on, off or auto, got '" + v + "'." +
                                 suggestion(v, {"on", "off", "auto"}));
            o.guiding = v == "auto" ? std::nullopt : std::optional<bool>(v == "on");
        } else if (flag == "--guiding-field") {
            const std::string v = next_value();
            if (v != "luminance" && v != "spectral")
                throw UsageError(flag + ": expected luminance or spectral, got '" + v + "'." +
                                 suggestion(v, {"luminance", "spectral"}));
            o.guiding_field = v == "spectral" ? GuidingMode::spectral : GuidingMode::luminance;
        } else if (flag == "--caustic-nee") {
            const std::string v = next_value();
            if (v != "on" && v != "off")
                throw UsageError(flag + ": expected on or off, got '" + v + "'." + suggestion(v, {"on", "off"}));
            o.caustic_nee = v == "on";
        } else if (flag == "--plane-nee") {
            const std::string v = next_value();
            if (v != "on" && v != "off")
                throw UsageError(flag + ": expected on or off, got '" + v + "'." + suggestion(v, {"on", "off"}));
            o.plane_nee = v == "on";
        } else if (flag == "--merge-radius") {
            o.merge_radius = parse_real(flag, next_value(), 1e-12, 1e12, "a radius from 1e-12 to 1e12");
        } else if (flag == "--no-dispersion") {
            o.dispersion = false;
        } else if (flag == "--no-bvh") {
            o.bvh = false;
        } else if (flag == "--strict") {
            o.strict = true;
        } else if (flag == "--pass-spp") {
            o.pass_spp = parse_integer<int>(flag, next_value(), 1, 1000000, "an integer from 1 to 1000000");
        } else if (flag == "--passes") {
            o.passes = parse_pass_range(flag, next_value());
        } else if (flag == "--print-passes") {
            o.print_passes = true;
        } else if (flag == "--max-depth") {
            o.max_depth = parse_integer<int>(flag, next_value(), 0, 100000, "an integer from 0 to 100000");
        } else if (!arg.empty() && arg[0] == '-') {
            throw UsageError(arg + ": unknown option (see --help)." + suggestion(flag, known_flags()));
        } else {
            if (scene_given)
                throw UsageError("SCENE: expected one scene, got '" + o.scene + "' and '" + arg + "'");
            o.scene = arg;
            scene_given = true;
        }
        if (flag.starts_with("--")) o.given.insert(flag);
        else if (flag == "-o") o.given.insert("--output");
        if (inline_value && (flag == "-h" || flag == "--help" || flag == "--version" ||
                             flag == "--list-scenes" || flag == "--quiet" ||
                             flag == "--no-dispersion" || flag == "--no-bvh" || flag == "--strict" ||
                             flag == "--auto-exposure" ||
                             flag == "--print-passes"))
            throw UsageError(flag + ": takes no value");
    }
    if (o.scale && (o.width || o.height))
        throw UsageError("--scale: cannot be combined with --width or --height");
    check_spectral_output(o, spectral_range_given);
    check_partial_film_options(o);
    // X.partial.ext is where the unfinished image of X.ext goes: it cannot be an output too.
    for (const std::string& path : o.outputs)
        if (std::find(o.outputs.begin(), o.outputs.end(), partial_output_name(path)) != o.outputs.end())
            throw UsageError("-o: expected names that are not the unfinished-image names of other "
                             "outputs, got '" + path + "' and '" + partial_output_name(path) + "'");
    return o;
}

}  // namespace spt

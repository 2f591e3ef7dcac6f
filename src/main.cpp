// The pathtracer program: parse flags, build the scene, render, write the images.
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "cli/options.h"
#include "cli/progress_bar.h"
#include "cli/render_metadata.h"
#include "io/atomic_file.h"
#include "io/image_writer.h"
#include "render/checkpoint.h"
#include "render/renderer.h"
#include "io/json.h"
#include "scene/scene_loader.h"
#include "spectral/rgb_to_spectrum.h"
#include "spectral/sensor.h"

namespace {

constexpr int kExitRuntimeError = 1;
constexpr int kExitUsage = 2;

// Set from the signal handler: lock-free atomics are async-signal-safe.
std::atomic<bool> g_cancel{false};
std::atomic<int> g_signal{0};
extern "C" void on_signal(int sig) {
    g_signal.store(sig);
    g_cancel.store(true);
}

void print_summary(const spt::Scene& scene, const spt::RenderSettings& rs, const spt::RenderStats& st,
                   const spt::Film& film, const std::string& bins) {
    const double s = st.seconds > 0 ? st.seconds : 1e-9;
    std::fprintf(stderr,
                 "%s: %dx%d, %d spp, %s spectral bins, %d thread(s), integrator %s\n"
                 "  time %.2f s, %.3g paths/s, %.3g rays/s (%.3g rays)\n"
                 "  effects: %s\n"
                 "  rejected samples: %llu non-finite, %llu negative\n",
                 scene.name.c_str(), rs.width, rs.height, rs.spp, bins.c_str(), rs.threads,
                 spt::integrator_name(rs.integrator.kind), st.seconds,
                 double(st.paths) / s, double(st.rays) / s, double(st.rays),
                 scene.effects.describe().c_str(),
                 static_cast<unsigned long long>(film.rejected_nonfinite()),
                 static_cast<unsigned long long>(film.rejected_negative()));
}

void write_outputs(const spt::Options& opt, const std::vector<std::string>& outputs,
                   const spt::Film& film, std::vector<spt::ExrAttribute> metadata) {
    const spt::ColorSpace space = *spt::color_space_by_name(opt.color_space);
    // A sensor's raw camera RGB is written as it is, in every format (no colour space).
    const bool raw = !opt.sensor.empty();
    const spt::Image image = raw ? film.develop_raw() : film.develop(space);
    spt::SpectralImage spectral;
    if (film.has_bands()) spectral = {film.bands(), film.develop_bands()};
    // A PNG is an sRGB file by definition: it is always developed to sRGB, whatever the
    // --color-space of the linear outputs.
    std::optional<spt::Image> srgb_image;
    spt::ImageWriteOptions wo;
    wo.exposure_stops = opt.exposure;
    wo.color_resolution = opt.color_resolution;
    wo.chromaticities = {{float(space.red[0]), float(space.red[1])},
                         {float(space.green[0]), float(space.green[1])},
                         {float(space.blue[0]), float(space.blue[1])},
                         {float(space.white[0]), float(space.white[1])}};
    wo.exr_chromaticities = !raw;
    wo.exr_attributes = std::move(metadata);
    if (film.has_bands()) wo.spectral = &spectral;
    std::vector<std::pair<std::string, std::string>> files;
    for (const std::string& path : outputs) {
        const spt::ImageFormat format = *spt::image_format_from_path(path);  // checked by the parser
        const spt::Image* source = &image;
        if (format == spt::ImageFormat::Png && space.name != "srgb" && !raw) {
            if (!srgb_image) srgb_image = film.develop(spt::srgb_color_space());
            source = &*srgb_image;
        }
        try {
            files.emplace_back(path, spt::encode_image(*source, format, wo));
        } catch (const std::invalid_argument& e) {
            throw std::runtime_error("cannot write '" + path + "': " + e.what());
        }
    }
    spt::write_files_atomically(files);  // all or nothing
}

/// SCENE is a built-in name or a path to a scene file (anything ending in .json or naming an
/// existing file); anything else is a usage error.
std::optional<spt::Scene> load_scene(const spt::Options& opt) {
    if (std::optional<spt::Scene> scene = spt::load_builtin_scene(opt.scene, opt.spectral)) return scene;
    std::error_code ec;
    if (opt.scene.ends_with(".json") || std::filesystem::is_regular_file(opt.scene, ec))
        return spt::load_scene_file(opt.scene, opt.spectral);
    std::string names;
    for (const std::string& n : spt::builtin_scene_names()) names += (names.empty() ? "" : ", ") + n;
    throw spt::UsageError("SCENE: expected a scene file (.json) or one of " + names + ", got '" + opt.scene + "'");
}

int run(const spt::Options& opt) {
    std::optional<spt::Scene> scene = load_scene(opt);
    if (!opt.dispersion) scene->disable_dispersion();
    spt::RenderSettings rs;
    rs.width = opt.width.value_or(scene->width);
    rs.height = opt.height.value_or(scene->height);
    rs.spp = opt.spp.value_or(scene->spp);
    rs.seed = opt.seed;
    rs.threads = opt.threads > 0 ? opt.threads
                                 : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    rs.integrator.max_depth = opt.max_depth;
    rs.integrator.kind = opt.integrator;
    rs.integrator.merge_radius = static_cast<float>(opt.merge_radius);
    rs.integrator.light_sampling = opt.light_sampling;
    rs.integrator.wavelengths_per_path = opt.wavelengths_per_path;
    rs.pass_spp = opt.pass_spp;
    rs.time_limit = opt.time_limit;

    std::vector<std::string> outputs = opt.outputs;
    if (outputs.empty()) outputs.push_back(scene->name + ".png");
    // Fail before a long render, not after it, when an image cannot be written there.
    for (const std::string& path : outputs) {
        const std::filesystem::path dir = std::filesystem::path(path).parent_path();
        if (!dir.empty() && !std::filesystem::is_directory(dir))
            throw std::runtime_error("cannot write '" + path + "': directory '" + dir.string() +
                                     "' does not exist");
        if (std::filesystem::is_directory(path))
            throw std::runtime_error("cannot write '" + path + "': it is a directory");
    }

    std::optional<spt::Observer> sensor;
    if (!opt.sensor.empty()) sensor.emplace(spt::load_sensor(opt.sensor));

    // ---- Checkpoints: what must match to resume, and the state of the last whole pass ----
    const char* light_sampling[] = {"", " light-sampling=bsdf", " light-sampling=light"};
    const std::string variant = "wavelengths-per-path=" + std::to_string(opt.wavelengths_per_path) +
                                light_sampling[static_cast<int>(opt.light_sampling)] +
                                " dispersion=" + (opt.dispersion ? "on" : "off") +
                                (opt.integrator == spt::IntegratorKind::path ? std::string()
                                    : std::string(" integrator=") + spt::integrator_name(opt.integrator)) +
                                (sensor ? " sensor=" + opt.sensor + "#" +
                                              std::to_string(sensor->fingerprint())
                                        : "");
    spt::CheckpointInfo info{opt.scene, variant, rs.width, rs.height, rs.spp, opt.spectral.bins,
                             opt.max_depth, rs.seed, 0};
    spt::Film film(rs.width, rs.height, sensor ? *sensor : spt::Cie1931::get());
    if (const spt::SpectralBands& bands = opt.spectral_bands; bands.count > 0) {
        film.enable_bands(bands);
        // Beyond 360-830 nm: wavelengths the XYZ film never sees, so neither the visible
        // density nor (unless exact) the scene's 380-780 nm bins cover them.
        if (bands.min_nm < spt::kLambdaMin || bands.max_nm > spt::kLambdaMax) {
            rs.wide_wavelengths = spt::WideWavelengthSampling::covering(
                static_cast<float>(bands.min_nm), static_cast<float>(bands.max_nm));
            if (opt.spectral.bins != spt::SpectralResolution::kExact)
                std::fprintf(stderr,
                             "pathtracer: warning: --spectral-range reaches beyond 360-830 nm, "
                             "where binned spectra (380-780 nm) hold their end values; "
                             "--spectral-bins exact evaluates the scene's analytic spectra there\n");
        }
    }
    if (!opt.resume.empty()) {
        const spt::CheckpointInfo saved = spt::read_checkpoint_info(opt.resume);
        if (!saved.same_render(info))
            throw std::runtime_error("cannot resume from '" + opt.resume + "': it holds a render of " +
                                     saved.describe() + ", but this run is " + info.describe());
        rs.first_sample = spt::load_checkpoint(opt.resume, film).samples_completed;
        info.samples_completed = rs.first_sample;
        if (!opt.quiet)
            std::fprintf(stderr, "resuming from %s after %d of %d spp\n", opt.resume.c_str(),
                         rs.first_sample, rs.spp);
    }
    // Film state at the last pass boundary: an interrupted render checkpoints whole passes only.
    std::string last_whole_pass = opt.checkpoint.empty() ? std::string() : film.save_state();
    int last_whole_samples = info.samples_completed;
    auto last_save = std::chrono::steady_clock::now();

    spt::ProgressBar bar(!opt.quiet);
    spt::RenderHooks hooks;
    hooks.progress = [&](std::uint64_t d, std::uint64_t t) { bar.update(d, t); };
    hooks.cancel = &g_cancel;
    if (!opt.checkpoint.empty()) {
        hooks.pass_completed = [&](int samples) {
            last_whole_pass = film.save_state();
            last_whole_samples = info.samples_completed = samples;
            const auto now = std::chrono::steady_clock::now();
            if (std::chrono::duration<double>(now - last_save).count() >= opt.checkpoint_interval) {
                spt::save_checkpoint(opt.checkpoint, info, last_whole_pass);
                last_save = now;
            }
        };
    }
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    const spt::RenderStats stats = spt::render(*scene, rs, film, hooks);
    bar.finish();

    write_outputs(opt, outputs, film, spt::render_metadata(opt, rs, stats, film.observer()));
    if (!opt.checkpoint.empty()) {
        info.samples_completed = stats.cancelled ? last_whole_samples : stats.samples_completed;
        spt::save_checkpoint(opt.checkpoint, info, stats.cancelled ? last_whole_pass : film.save_state());
    }

    if (!opt.quiet) {
        const std::string bins = opt.spectral.bins == spt::SpectralResolution::kExact
                                     ? "exact"
                                     : std::to_string(opt.spectral.bins);
        print_summary(*scene, rs, stats, film, bins);
        if (stats.time_limited)
            std::fprintf(stderr, "  stopped by --time-limit %g s after %d of %d spp\n", opt.time_limit,
                         stats.samples_completed, rs.spp);
        for (const std::string& path : outputs) std::fprintf(stderr, "  wrote %s\n", path.c_str());
    }
    if (stats.cancelled) {
        std::fprintf(stderr,
                     "pathtracer: interrupted by signal %d: wrote the image of %d of %d passes "
                     "(%d of %d spp, plus the tiles finished since)%s\n",
                     g_signal.load(), stats.passes_completed, stats.passes_total,
                     stats.samples_completed, rs.spp,
                     opt.checkpoint.empty() ? "" : "; the checkpoint holds the whole passes");
        return 128 + g_signal.load();
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const spt::Options opt = spt::parse_options(std::vector<std::string>(argv + 1, argv + argc));
        if (opt.show_help) {
            std::fputs(spt::usage_text().c_str(), stdout);
            return 0;
        }
        if (opt.show_version) {
            std::printf("pathtracer %s (%s build)\n", SPT_VERSION, SPT_BUILD_ISA);
            return 0;
        }
        if (opt.rgb_to_spectrum) {
            const spt::SpectrumSource s = spt::rgb_to_spectrum(*opt.rgb_to_spectrum);
            if (s.kind == spt::SpectrumSource::Kind::Constant) std::printf("constant %.17g\n", s.p[0]);
            else std::printf("rgb_sigmoid %.17g %.17g %.17g\n", s.p[0], s.p[1], s.p[2]);
            return 0;
        }
        if (opt.list_scenes) {
            for (const std::string& n : spt::builtin_scene_names()) std::printf("%s\n", n.c_str());
            return 0;
        }
        return run(opt);
    } catch (const spt::LocatedError& e) {  // a scene file: "file:line:column: message"
        std::fprintf(stderr, "%s\n", e.what());
        return kExitRuntimeError;
    } catch (const spt::UsageError& e) {
        std::fprintf(stderr, "pathtracer: %s\n", e.what());
        return kExitUsage;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "pathtracer: %s\n", e.what());
        return kExitRuntimeError;
    }
}

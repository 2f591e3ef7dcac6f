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

#include "cli/live_preview.h"
#include "cli/options.h"
#include "cli/output_names.h"
#include "cli/progress_bar.h"
#include "io/atomic_file.h"
#include "io/image_writer.h"
#include "render/checkpoint.h"
#include "render/renderer.h"
#include "io/json.h"
#include "scene/scene_loader.h"
#include "spectral/rgb_to_spectrum.h"

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

void write_outputs(const spt::Options& opt, const std::vector<std::string>& outputs, const spt::Film& film) {
    const spt::ColorSpace space = *spt::color_space_by_name(opt.color_space);
    const spt::Image image = film.develop(space);
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
    std::vector<std::pair<std::string, std::string>> files;
    for (const std::string& path : outputs) {
        const spt::ImageFormat format = *spt::image_format_from_path(path);  // checked by the parser
        const spt::Image* source = &image;
        if (format == spt::ImageFormat::Png && space.name != "srgb") {
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

    // ---- Checkpoints: what must match to resume, and the state of the last whole pass ----
    const char* light_sampling[] = {"", " light-sampling=bsdf", " light-sampling=light"};
    const std::string variant = "wavelengths-per-path=" + std::to_string(opt.wavelengths_per_path) +
                                light_sampling[static_cast<int>(opt.light_sampling)] +
                                " dispersion=" + (opt.dispersion ? "on" : "off") +
                                (opt.integrator == spt::IntegratorKind::path ? std::string()
                                    : std::string(" integrator=") + spt::integrator_name(opt.integrator));
    spt::CheckpointInfo info{opt.scene, variant, rs.width, rs.height, rs.spp, opt.spectral.bins,
                             opt.max_depth, rs.seed, 0};
    spt::Film film(rs.width, rs.height);
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

    // Interrupts are caught from here on (also while connecting to a display server): the
    // render then stops at once and its unfinished image is written under the partial names.
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    const spt::PreviewSettings preview_settings{outputs, opt.preview_interval, opt.display_server,
                                                *spt::color_space_by_name(opt.color_space), opt.quiet};
    spt::LivePreview preview(
        preview_settings,
        [&](const std::vector<std::string>& paths, const spt::Film& f) { write_outputs(opt, paths, f); },
        rs.width, rs.height);
    rs.pass_seconds = spt::preview_pass_seconds(preview_settings);

    spt::ProgressBar bar(!opt.quiet);
    spt::RenderHooks hooks;
    hooks.progress = [&](std::uint64_t d, std::uint64_t t) { bar.update(d, t); };
    hooks.cancel = &g_cancel;
    hooks.pass_completed = [&](int samples) {
        if (!opt.checkpoint.empty()) {
            last_whole_pass = film.save_state();
            last_whole_samples = info.samples_completed = samples;
            const auto now = std::chrono::steady_clock::now();
            if (std::chrono::duration<double>(now - last_save).count() >= opt.checkpoint_interval) {
                spt::save_checkpoint(opt.checkpoint, info, last_whole_pass);
                last_save = now;
            }
        }
        preview.pass_completed(film);
    };
    const spt::RenderStats stats = spt::render(*scene, rs, film, hooks);
    bar.finish();
    preview.render_ended(film);

    // An unfinished image never replaces an output: it goes beside it, under its partial name.
    const std::vector<std::string> written =
        stats.cancelled ? spt::partial_output_names(outputs) : outputs;
    write_outputs(opt, written, film);
    if (!stats.cancelled) preview.remove_preview_files();
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
        if (!stats.cancelled)
            for (const std::string& path : outputs) std::fprintf(stderr, "  wrote %s\n", path.c_str());
    }
    if (stats.cancelled) {
        const auto [fewest, most] = film.sample_count_range();
        const std::string spp = (fewest == most ? "" : std::to_string(fewest) + " to ") +
                                std::to_string(most) + " of " + std::to_string(rs.spp) + " spp";
        std::fprintf(stderr, "pathtracer: interrupted by signal %d: the outputs are left as they were; "
                     "the unfinished image is beside them:\n", g_signal.load());
        for (const std::string& path : written)
            std::fprintf(stderr, "  wrote %s (%s per pixel)\n", path.c_str(), spp.c_str());
        if (!opt.checkpoint.empty())
            std::fprintf(stderr, "  the checkpoint %s holds the whole passes: %d spp\n",
                         opt.checkpoint.c_str(), last_whole_samples);
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

// The pathtracer program: parse flags, build the scene, render, write the images.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <sys/resource.h>

#include <csignal>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "cli/distinct_files.h"
#include "cli/flag_warnings.h"
#include "cli/guiding_choice.h"
#include "cli/image_size.h"
#include "cli/integrator_choice.h"
#include "cli/live_preview.h"
#include "cli/options.h"
#include "cli/output_names.h"
#include "cli/partial_films.h"
#include "cli/progress_bar.h"
#include "cli/render_description.h"
#include "cli/render_metadata.h"
#include "core/parallel_rows.h"
#include "io/atomic_file.h"
#include "io/auto_exposure.h"
#include "io/image_writer.h"
#include "render/checkpoint.h"
#include "render/renderer.h"
#include "render/wavefront.h"
#include "io/located_error.h"
#include "scene/param_checker.h"
#include "scene/pbrt_scene_writer.h"
#include "scene/scene_builder.h"
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

/// Peak resident memory of the process in MiB (Linux reports ru_maxrss in KiB).
double peak_memory_mib() {
    rusage usage{};
    return getrusage(RUSAGE_SELF, &usage) == 0 ? double(usage.ru_maxrss) / 1024.0 : 0.0;
}

void print_summary(const spt::Scene& scene, const spt::RenderSettings& rs, const spt::RenderStats& st,
                   const spt::Film& film, const std::string& bins, const std::string& integrator_reason,
                   double load_seconds) {
    const double s = st.seconds > 0 ? st.seconds : 1e-9;
    // The samples the image holds (whole passes); what was asked for only when it differs.
    const std::string requested =
        st.samples_completed == rs.spp ? std::string() : " (of " + std::to_string(rs.spp) + " requested)";
    std::fprintf(stderr,
                 "%s: %dx%d, %d spp%s, %s, %d thread(s)\n"
                 "  integrator %s (%s)\n"
                 "  scene loaded in %.3f s (BVH built in %.3f s); peak memory %.0f MiB\n"
                 "  time %.2f s, %.3g paths/s, %.3g rays/s (%.3g rays)\n"
                 "  effects: %s\n"
                 "  rejected samples: %llu non-finite, %llu negative\n",
                 scene.name.c_str(), rs.width, rs.height, st.samples_completed, requested.c_str(), bins.c_str(),
                 rs.threads,
                 spt::integrator_name(rs.integrator.kind), integrator_reason.c_str(), load_seconds,
                 scene.bvh_build_seconds, peak_memory_mib(), st.seconds,
                 double(st.paths) / s, double(st.rays) / s, double(st.rays),
                 scene.effects.describe().c_str(),
                 static_cast<unsigned long long>(film.rejected_nonfinite()),
                 static_cast<unsigned long long>(film.rejected_negative()));
}

/// Writes every output; returns the stops --auto-exposure added to the PNGs (nullopt without it).
std::optional<double> write_outputs(const spt::Options& opt, const std::vector<std::string>& outputs,
                                    const spt::Film& film, std::vector<spt::ExrAttribute> metadata) {
    // White balance is a colour transform, so it reaches the linear outputs too.
    const auto balanced = [&](const spt::ColorSpace& cs) {
        return opt.white_balance ? spt::white_balanced(cs, *opt.white_balance) : cs;
    };
    const spt::ColorSpace space = balanced(*spt::color_space_by_name(opt.color_space));
    // A sensor's raw camera RGB is written as it is, in every format (no colour space).
    const bool raw = !opt.sensor.empty();
    const spt::Image image = raw ? film.develop_raw() : film.develop(space);
    spt::SpectralImage spectral;
    if (film.has_bands()) spectral = {film.bands(), film.develop_bands()};
    // A PNG is an sRGB file by definition: it is always developed to sRGB, whatever the
    // --color-space of the linear outputs.
    std::optional<spt::Image> srgb_image;
    const spt::ColorSpace srgb = balanced(spt::srgb_color_space());
    spt::ImageWriteOptions wo;
    wo.exposure_stops = opt.exposure;
    wo.tone_map = opt.tone_map;
    wo.color_resolution = opt.color_resolution;
    wo.chromaticities = {{float(space.red[0]), float(space.red[1])},
                         {float(space.green[0]), float(space.green[1])},
                         {float(space.blue[0]), float(space.blue[1])},
                         {float(space.white[0]), float(space.white[1])}};
    std::optional<double> auto_stops;
    wo.exr_chromaticities = !raw;
    wo.exr_attributes = std::move(metadata);
    if (film.has_bands()) wo.spectral = &spectral;
    std::vector<std::pair<std::string, std::string>> files;
    for (const std::string& path : outputs) {
        const spt::ImageFormat format = *spt::image_format_from_path(path);  // checked by the parser
        const spt::Image* source = &image;
        if (format == spt::ImageFormat::Png && space.name != "srgb" && !raw) {
            if (!srgb_image) srgb_image = film.develop(srgb);
            source = &*srgb_image;
        }
        spt::ImageWriteOptions file_options = wo;
        if (format == spt::ImageFormat::Png && opt.auto_exposure) {
            if (!auto_stops) auto_stops = spt::auto_exposure_stops(*source, srgb);
            file_options.exposure_stops += *auto_stops;
        }
        try {
            files.emplace_back(path, spt::encode_image(*source, format, file_options));
        } catch (const std::invalid_argument& e) {
            throw std::runtime_error("cannot write '" + path + "': " + e.what());
        }
    }
    spt::write_files_atomically(files);  // all or nothing
    return auto_stops;
}

/// --print-adaptation: both whites' xy, then the XYZ → XYZ matrix row by row.
void print_adaptation(const spt::Options& opt) {
    const spt::Chromaticity source = *opt.print_adaptation;
    const spt::Chromaticity target = spt::color_space_by_name(opt.color_space)->white;
    const spt::Matrix3 m = spt::bradford_adaptation(source, target);
    std::printf("source_xy %.17g %.17g\ntarget_xy %.17g %.17g\n", source[0], source[1], target[0],
                target[1]);
    for (const auto& row : m) std::printf("%.17g %.17g %.17g\n", row[0], row[1], row[2]);
}

/// SCENE is a built-in name or a path to a scene file (anything ending in .json or naming an
/// existing file); anything else is a usage error.
std::optional<spt::Scene> load_scene(const spt::Options& opt, spt::InputFiles& files) {
    if (std::optional<spt::Scene> scene = spt::load_builtin_scene(opt.scene, opt.spectral, &files)) return scene;
    std::error_code ec;
    if (opt.scene.ends_with(".json") || std::filesystem::is_regular_file(opt.scene, ec))
        return spt::load_scene_file(opt.scene, opt.spectral, &files);
    const std::vector<std::string> builtins = spt::builtin_scene_names();
    throw spt::UsageError("SCENE: expected a scene file (.json or .pbrt) or one of " + spt::join(builtins) + ", got '" +
                          opt.scene + "'." + spt::suggestion(opt.scene, builtins));
}

/// --export-pbrt: the scene's description (with the image flags applied) as a pbrt-v4 file;
/// the file and the meshes and images copied beside it are written all or nothing.
int export_pbrt(const spt::Options& opt) {
    std::optional<spt::SceneSource> source = spt::read_scene_source(opt.scene);
    if (!source) {
        const std::vector<std::string> builtins = spt::builtin_scene_names();
        throw spt::UsageError("SCENE: expected a scene file (.json) or one of " + spt::join(builtins) + ", got '" +
                              opt.scene + "'." + spt::suggestion(opt.scene, builtins));
    }
    // The scene is built first, as a render would, so that only a scene this program accepts
    // is written (the writer reads the description as it is, checked).
    const spt::Scene scene = spt::build_scene(source->description, opt.spectral, source->read_relative);
    const spt::ImageSize size = spt::resolve_image_size(scene.width, scene.height, opt.width, opt.height, opt.scale);
    spt::ParamValue& root = source->description.root;
    root.set("image", spt::ParamValue::dict({{"width", spt::ParamValue::number(size.width)},
                                             {"height", spt::ParamValue::number(size.height)},
                                             {"spp", spt::ParamValue::number(opt.spp.value_or(scene.spp))}}));
    spt::PbrtExportSettings settings;
    settings.output_path = opt.export_pbrt;
    settings.scene_folder = source->folder;
    settings.read_relative = source->read_relative;
    const spt::PbrtExport exported = spt::export_pbrt(source->description, settings);
    std::vector<std::pair<std::string, std::string>> files = exported.files;
    files.emplace_back(opt.export_pbrt, exported.text);
    spt::write_files_atomically(files);
    if (!opt.quiet)
        for (const auto& [path, bytes] : files) std::fprintf(stderr, "  wrote %s\n", path.c_str());
    return 0;
}

/// --list-scenes: one line per built-in scene, the name first (scripts take the first word).
void list_scenes() {
    const std::vector<std::string> names = spt::builtin_scene_names();
    int width = 0;
    for (const std::string& name : names) width = std::max(width, static_cast<int>(name.size()));
    for (const std::string& name : names) {
        const spt::Scene scene = *spt::load_builtin_scene(name, spt::SpectralResolution{});
        const std::string size = std::to_string(scene.width) + "x" + std::to_string(scene.height);
        std::printf("%-*s %-9s %5d spp  %-4s  %s\n", width, name.c_str(), size.c_str(), scene.spp,
                    spt::integrator_name(scene.integrator.kind.value_or(spt::IntegratorKind::path)),
                    scene.summary.c_str());
    }
}

int run(const spt::Options& opt) {
    spt::set_load_threads(opt.threads);  // large scene data (environment maps) is built on the render's threads
    const auto load_start = std::chrono::steady_clock::now();
    spt::InputFiles scene_files;
    std::optional<spt::Scene> scene = load_scene(opt, scene_files);
    const double load_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - load_start).count();
    const spt::IntegratorChoice integrator = spt::choose_integrator(opt, *scene);
    if (opt.spectral_bands.count > 0 && integrator.settings.kind != spt::IntegratorKind::path)
        throw spt::UsageError(std::string("--spectral-bands: only with the path integrator (bdpt and vcm splats are "
                                          "not binned); the scene file chooses ") +
                              spt::integrator_name(integrator.settings.kind) + ", add --integrator path");
    std::vector<std::string> outputs = opt.outputs;
    if (outputs.empty()) outputs.push_back(scene->output.empty() ? scene->name + ".png" : scene->output);
    std::vector<std::string> warnings = scene->warnings;
    for (const std::string& w : spt::ineffective_flag_warnings(opt, integrator.settings, outputs, *scene))
        warnings.push_back(w);
    if (opt.strict && !scene->warnings.empty()) {
        for (const std::string& w : scene->warnings) std::fprintf(stderr, "pathtracer: error: %s\n", w.c_str());
        throw spt::UsageError("--strict: the scene has " + std::to_string(scene->warnings.size()) +
                              " warning(s), each an error with --strict; expected none");
    }
    for (const std::string& w : warnings) std::fprintf(stderr, "pathtracer: warning: %s\n", w.c_str());
    if (!opt.dispersion) scene->disable_dispersion();
    if (!opt.bvh && !scene->disable_bvh())
        throw spt::UsageError("--no-bvh: scene '" + scene->name +
                              "' has shapes only the BVH intersects (quadrics, disks or instances); "
                              "expected spheres, planes, quads and meshes only");
    spt::RenderSettings rs;
    const spt::ImageSize size =
        spt::resolve_image_size(scene->width, scene->height, opt.width, opt.height, opt.scale);
    rs.width = size.width;
    rs.height = size.height;
    rs.spp = opt.spp.value_or(scene->spp);
    rs.seed = opt.seed;
    rs.threads = opt.threads > 0 ? opt.threads
                                 : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    rs.integrator = integrator.settings;
    rs.tile = opt.tile;
    rs.queue = opt.queue;
    rs.schedule = opt.schedule;
    rs.sampler = opt.sampler.value_or(
        spt::default_sampler(rs.integrator.kind, rs.schedule == spt::Schedule::wavefront));
    if (const char* feature = rs.schedule == spt::Schedule::wavefront
                                  ? spt::wavefront_unsupported(*scene, rs.integrator, rs.sampler) : nullptr)
        throw spt::UsageError(std::string("--schedule wavefront: does not support ") + feature + " (scene '" +
                              scene->name + "'); expected --schedule tiles" +
                              (rs.sampler != spt::SamplerKind::independent ? " or --sampler independent" : ""));
    rs.pass_spp = opt.pass_spp;
    rs.time_limit = opt.time_limit;
    const spt::GuidingChoice guiding = spt::choose_guiding(opt, *scene, rs);
    rs.guiding = guiding.mode;
    if (opt.print_passes) {
        std::printf("passes %d\nspp_per_pass %d\nspp %d\n", spt::pass_count(rs), spt::chunk_spp(rs), rs.spp);
        return 0;
    }
    // Every output is a .film or none is (checked by the parser).
    const bool partial_film = spt::is_partial_film_path(outputs.front());
    if (partial_film) {
        const auto [first, end] = spt::pass_samples(rs, opt.passes.value_or(std::pair{0, spt::pass_count(rs)}));
        rs.first_sample = first;
        rs.end_sample = end;
    }

    // Fail before a long render, not after it, when an image cannot be written there.
    for (const std::string& path : outputs) {
        const std::filesystem::path dir = std::filesystem::path(path).parent_path();
        if (!dir.empty() && !std::filesystem::is_directory(dir))
            throw std::runtime_error("cannot write '" + path + "': directory '" + dir.string() +
                                     "' does not exist");
        if (std::filesystem::is_directory(path))
            throw std::runtime_error("cannot write '" + path + "': it is a directory");
    }

    {
        std::vector<spt::FileRole> files;
        for (const std::string& path : outputs) {
            files.push_back({path, "-o", true});
            if (!partial_film)  // an interrupt or a preview writes the unfinished image there
                files.push_back({spt::partial_output_name(path), "the unfinished image of -o", true});
        }
        if (!opt.checkpoint.empty()) files.push_back({opt.checkpoint, "--checkpoint", true});
        if (!opt.resume.empty()) files.push_back({opt.resume, "--resume", false});
        // One image written twice is one image; a checkpoint is resumed and then replaced.
        spt::check_distinct_files(files, {{"-o", "-o"},
                                          {"the unfinished image of -o", "the unfinished image of -o"},
                                          {"--checkpoint", "--resume"}});
    }

    std::optional<spt::Observer> sensor;
    if (!opt.sensor.empty()) sensor.emplace(spt::load_sensor(opt.sensor));

    // The options as rendered: with the spectra's resolution the scene was built with
    // (build_scene may raise it), which checkpoints, parts and image metadata record, so
    // work at another resolution is never resumed or merged into this one.
    spt::Options as_rendered = opt;
    as_rendered.spectral = scene->spectral_resolution;

    // ---- Checkpoints: what must match to resume, and the state of the last whole pass ----
    spt::CheckpointInfo info{spt::describe_render(as_rendered, rs, scene_files, sensor ? &*sensor : nullptr), 0,
                             rs.first_sample};
    spt::Film film(rs.width, rs.height, sensor ? *sensor : spt::Cie1931::get());
    if (const spt::SpectralBands& bands = opt.spectral_bands; bands.count > 0) {
        film.enable_bands(bands);
        // Beyond 360-830 nm: wavelengths the XYZ film never sees, so neither the visible
        // density nor (unless exact) the scene's 380-780 nm bins cover them.
        if (bands.min_nm < spt::kLambdaMin || bands.max_nm > spt::kLambdaMax) {
            rs.wide_wavelengths = spt::WideWavelengthSampling::covering(
                static_cast<float>(bands.min_nm), static_cast<float>(bands.max_nm));
            if (scene->spectral_resolution.bins != spt::SpectralResolution::kExact)
                std::fprintf(stderr,
                             "pathtracer: warning: --spectral-range reaches beyond 360-830 nm, "
                             "where binned spectra (380-780 nm) hold their end values; "
                             "--spectral-bins exact evaluates the scene's analytic spectra there\n");
        }
    }
    if (!opt.resume.empty()) {
        const spt::CheckpointInfo saved = spt::read_checkpoint_info(opt.resume);
        if (const std::string diff = saved.render.difference(info.render); !diff.empty())
            throw std::runtime_error("cannot resume from '" + opt.resume + "': it holds another render than this "
                                     "run's (" + diff + ")");
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
        // Previews carry no render metadata (the EXR attributes describe a finished render).
        [&](const std::vector<std::string>& paths, const spt::Film& f) { write_outputs(opt, paths, f, {}); },
        rs.width, rs.height);
    rs.pass_seconds = spt::preview_pass_seconds(preview_settings);

    spt::ProgressBar bar(!opt.quiet, rs.time_limit);
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
    std::optional<double> auto_stops;
    if (!partial_film) {
        // An interrupted pass leaves some pixels with more samples than the whole passes hold.
        const auto [fewest, most] = film.sample_count_range();
        const std::pair<int, int> per_pixel =
            stats.cancelled ? std::pair{int(fewest), int(most)} : std::pair{stats.samples_completed, stats.samples_completed};
        auto_stops = write_outputs(opt, written, film,
                                   spt::render_metadata(as_rendered, rs, stats, film.observer(), per_pixel));
    } else if (!stats.cancelled) {  // an unfinished part is not written: rendered again, it is whole
        info.samples_completed = stats.samples_completed;
        const std::string state = film.save_state();
        for (const std::string& path : outputs) spt::save_checkpoint(path, info, state, spt::FilmFile::partial);
    }
    if (!stats.cancelled) preview.remove_preview_files();
    if (!opt.checkpoint.empty()) {
        info.samples_completed = stats.cancelled ? last_whole_samples : stats.samples_completed;
        spt::save_checkpoint(opt.checkpoint, info, stats.cancelled ? last_whole_pass : film.save_state());
    }

    if (!opt.quiet) {
        const spt::SpectralResolution used = scene->spectral_resolution;
        std::string bins = used.bins == spt::SpectralResolution::kExact ? "exact spectra"
                                                                         : std::to_string(used.bins) + " spectral bins";
        if (!scene->spectral_resolution_reason.empty()) bins += " (" + scene->spectral_resolution_reason + ")";
        print_summary(*scene, rs, stats, film, bins, integrator.reason, load_seconds);
        if (rs.integrator.kind == spt::IntegratorKind::path)
            std::fprintf(stderr, "  guiding %s (%s)\n", spt::guiding_mode_name(rs.guiding), guiding.reason.c_str());
        if (const std::string note = spt::missed_light_paths(rs.integrator, *scene); !note.empty())
            std::fprintf(stderr, "  note: %s\n", note.c_str());
        if (stats.time_limited)
            std::fprintf(stderr, "  stopped by --time-limit %g s after %d of %d spp\n", opt.time_limit,
                         stats.samples_completed, rs.spp);
        if (auto_stops) std::fprintf(stderr, "  auto exposure: %+.1f stops\n", *auto_stops);
        if (!stats.cancelled)
            for (const std::string& path : outputs) std::fprintf(stderr, "  wrote %s\n", path.c_str());
    }
    if (stats.cancelled && partial_film) {
        std::fprintf(stderr, "pathtracer: interrupted by signal %d: no partial film written (a part is "
                     "whole passes; render it again)\n", g_signal.load());
        return 128 + g_signal.load();
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

/// `pathtracer merge PARTS... -o FILE...`: the partial films merged into images (or a film).
int run_merge(const std::vector<std::string>& args) {
    // .film outputs are taken out here (the render's parser refuses them beside images).
    std::vector<std::string> parts, films, rest;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const bool output_flag = args[i] == "-o" || args[i] == "--output";
        if (output_flag && i + 1 < args.size() && spt::is_partial_film_path(args[i + 1]))
            films.push_back(args[++i]);
        else
            (spt::is_partial_film_path(args[i]) ? parts : rest).push_back(args[i]);
    }
    spt::Options opt = spt::parse_options(rest);
    const std::set<std::string> output_flags = {"--output", "--color-space", "--exposure", "--auto-exposure",
                                                "--tonemap", "--white-balance", "--color-resolution", "--quiet"};
    for (const std::string& flag : opt.given)
        if (!output_flags.contains(flag))
            throw spt::UsageError("merge: " + flag + " is not an output option (the parts hold the render's settings)");
    if (opt.scene != spt::Options{}.scene)
        throw spt::UsageError("merge: expected partial films (.film), got '" + opt.scene + "'");
    if (opt.outputs.empty() && films.empty()) throw spt::UsageError("merge: expected -o FILE (the merged image)");
    {
        std::vector<spt::FileRole> files;
        for (const std::string& path : parts) files.push_back({path, "the part", false});
        for (const std::vector<std::string>* list : {&opt.outputs, &films})
            for (const std::string& path : *list) files.push_back({path, "-o", true});
        spt::check_distinct_files(files, {{"-o", "-o"}});
    }
    const spt::MergedParts merged = spt::merge_partial_films(parts);

    const std::vector<std::string>& images = opt.outputs;
    if (!merged.missing.empty()) {
        for (const std::string& path : images)
            if (spt::image_format_from_path(path) != spt::ImageFormat::Exr)
                throw std::runtime_error("cannot write '" + path + "': samples " + merged.missing +
                                         " of the render are in no part, and only an .exr output records how "
                                         "many samples it holds");
        if (!films.empty() && merged.ranges.size() > 1)
            throw std::runtime_error("cannot write '" + films.front() + "': a partial film holds one range of "
                                     "samples, and samples " + merged.missing + " are in no part");
        std::fprintf(stderr, "pathtracer: warning: samples %s of the render are in no part: the image holds "
                     "%d of %d spp\n", merged.missing.c_str(), merged.samples, merged.info.render.spp);
    }
    // The render's settings, for the EXR metadata.
    opt.scene = merged.info.render.scene;
    opt.spectral.bins = merged.info.render.spectral_bins;
    opt.wavelengths_per_path = merged.info.render.wavelengths_per_path;
    const spt::RenderSettings rs = spt::settings_of(merged.info.render);
    spt::RenderStats stats;
    stats.samples_completed = merged.samples;
    std::vector<spt::ExrAttribute> metadata = spt::render_metadata(opt, rs, stats, merged.film->observer(), {merged.samples, merged.samples});
    std::vector<std::string> ranges;
    for (const auto& [first, end] : merged.ranges) ranges.push_back(std::to_string(first) + "-" + std::to_string(end));
    metadata.push_back(spt::ExrAttribute::text("sampleRanges", spt::join(ranges)));
    if (!images.empty()) write_outputs(opt, images, *merged.film, std::move(metadata));
    for (const std::string& path : films)
        spt::save_checkpoint(path, merged.info, merged.film->save_state(), spt::FilmFile::partial);
    if (!opt.quiet)
        for (const std::vector<std::string>& list : {images, films})
            for (const std::string& path : list)
                std::fprintf(stderr, "  wrote %s (%zu parts, %d of %d spp)\n", path.c_str(), parts.size(),
                             merged.samples, merged.info.render.spp);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        if (argc > 1 && std::string(argv[1]) == "merge")
            return run_merge(std::vector<std::string>(argv + 2, argv + argc));
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
        if (opt.print_adaptation) {
            print_adaptation(opt);
            return 0;
        }
        if (opt.list_scenes) {
            list_scenes();
            return 0;
        }
        if (!opt.export_pbrt.empty()) return export_pbrt(opt);
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

// The pathtracer program: parse flags, build the scene, render, write the images.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "cli/options.h"
#include "cli/progress_bar.h"
#include "io/image_writer.h"
#include "render/renderer.h"
#include "io/json.h"
#include "scene/scene_loader.h"
#include "spectral/rgb_to_spectrum.h"

namespace {

constexpr int kExitRuntimeError = 1;
constexpr int kExitUsage = 2;

void print_summary(const spt::Scene& scene, const spt::RenderSettings& rs, const spt::RenderStats& st,
                   const spt::Film& film, const std::string& bins) {
    const double s = st.seconds > 0 ? st.seconds : 1e-9;
    std::fprintf(stderr,
                 "%s: %dx%d, %d spp, %s spectral bins, %d thread(s)\n"
                 "  time %.2f s, %.3g paths/s, %.3g rays/s (%.3g rays)\n"
                 "  effects: %s\n"
                 "  rejected samples: %llu non-finite, %llu negative\n",
                 scene.name.c_str(), rs.width, rs.height, rs.spp, bins.c_str(), rs.threads, st.seconds,
                 double(st.paths) / s, double(st.rays) / s, double(st.rays),
                 scene.effects.describe().c_str(),
                 static_cast<unsigned long long>(film.rejected_nonfinite()),
                 static_cast<unsigned long long>(film.rejected_negative()));
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
    spt::RenderSettings rs;
    rs.width = opt.width.value_or(scene->width);
    rs.height = opt.height.value_or(scene->height);
    rs.spp = opt.spp.value_or(scene->spp);
    rs.seed = opt.seed;
    rs.threads = opt.threads > 0 ? opt.threads
                                 : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    rs.integrator.max_depth = opt.max_depth;

    std::vector<std::string> outputs = opt.outputs;
    if (outputs.empty()) outputs.push_back(scene->name + ".png");

    spt::Film film(rs.width, rs.height);
    spt::ProgressBar bar(!opt.quiet);
    const spt::RenderStats stats =
        spt::render(*scene, rs, film, [&](std::uint64_t d, std::uint64_t t) { bar.update(d, t); });
    bar.finish();

    const spt::ColorSpace space = *spt::color_space_by_name(opt.color_space);
    const spt::Image image = film.develop(space);
    spt::ImageWriteOptions wo;
    wo.exposure_stops = opt.exposure;
    wo.color_resolution = opt.color_resolution;
    wo.chromaticities = {{float(space.red[0]), float(space.red[1])},
                         {float(space.green[0]), float(space.green[1])},
                         {float(space.blue[0]), float(space.blue[1])},
                         {float(space.white[0]), float(space.white[1])}};
    for (const std::string& path : outputs) spt::write_image(path, image, wo);

    if (!opt.quiet) {
        const std::string bins = opt.spectral.bins == spt::SpectralResolution::kExact
                                     ? "exact"
                                     : std::to_string(opt.spectral.bins);
        print_summary(*scene, rs, stats, film, bins);
        for (const std::string& path : outputs) std::fprintf(stderr, "  wrote %s\n", path.c_str());
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
            std::printf("pathtracer %s\n", SPT_VERSION);
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

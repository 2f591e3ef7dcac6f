// The functions of scene_loader.h, the scene files' front door: the reader table, files from disk
// and the built-in scenes.
#include "scene/scene_loader.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "io/checksums.h"
#include "io/embedded_files.h"
#include "io/inflate.h"
#include "scene/json_scene_reader.h"
#include "scene/pbrt_scene_reader.h"
#include "scene/scene_builder.h"

namespace spt {

namespace {

std::string read_whole_file(const std::filesystem::path& path, std::string& error) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
        error = "no such file";
        return {};
    }
    if (std::filesystem::is_directory(path, ec)) {
        error = "it is a directory";
        return {};
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        error = "cannot open it";
        return {};
    }
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) error = "read error";
    if (error.empty() && path.extension() == ".gz" && is_gzip(text)) {
        try {
            return gzip_decompress(text);
        } catch (const InflateError& e) {
            error = std::string("corrupt gzip data: ") + e.what();
            return {};
        }
    }
    return text;
}

}  // namespace

const std::vector<SceneReader>& scene_readers() {
    static const std::vector<SceneReader> readers = {
        {"JSON", ".json",
         [](std::string_view text, const std::string& origin, const std::string& name, const RelativeFileReader&) {
             return read_json_scene(text, origin, name);
         }},
        {"pbrt-v4", ".pbrt", read_pbrt_scene},
    };
    return readers;
}

Scene load_scene_text(std::string_view text, const std::string& origin, const std::string& scene_name,
                      SpectralResolution resolution, const RelativeFileReader& read_relative,
                      InputFiles* input_files) {
    InputFiles inputs{{origin, fnv1a64(text)}};
    const RelativeFileReader recording = [&](const std::string& rel, std::string& contents, std::string& display,
                                             std::string& why) {
        if (!read_relative(rel, contents, display, why)) return false;
        const auto same = [&](const auto& input) { return input.first == display; };
        if (std::none_of(inputs.begin(), inputs.end(), same)) inputs.emplace_back(display, fnv1a64(contents));
        return true;
    };
    const SceneReader* reader = &scene_readers().front();
    const std::string_view format_name = std::string_view(origin).ends_with(".gz")
                                             ? std::string_view(origin).substr(0, origin.size() - 3)
                                             : std::string_view(origin);
    for (const SceneReader& r : scene_readers())
        if (format_name.ends_with(r.extension)) reader = &r;
    const SceneDescription description = reader->read(text, origin, scene_name, recording);
    Scene scene = build_scene(description, resolution, recording);
    scene.warnings.insert(scene.warnings.begin(), description.warnings.begin(), description.warnings.end());
    if (input_files) *input_files = std::move(inputs);
    return scene;
}

Scene load_scene_file(const std::string& path, SpectralResolution resolution, InputFiles* input_files) {
    std::string error;
    const std::string text = read_whole_file(path, error);
    if (!error.empty()) throw LocatedError(path, {1, 1}, "cannot read the scene file: " + error + "; expected a readable scene file");
    const std::filesystem::path base = std::filesystem::path(path).parent_path();
    const RelativeFileReader reader = [&](const std::string& rel, std::string& contents, std::string& display,
                                          std::string& why) {
        const std::filesystem::path full = base / rel;
        display = full.string();
        contents = read_whole_file(full, why);
        return why.empty();
    };
    std::filesystem::path name = std::filesystem::path(path).stem();
    if (std::filesystem::path(path).extension() == ".gz") name = name.stem();  // scene.pbrt.gz is "scene"
    return load_scene_text(text, path, name.string(), resolution, reader, input_files);
}

std::vector<std::string> builtin_scene_names() {
    std::vector<std::string> names;
    for (std::size_t i = 0; i < kEmbeddedScenes_count; ++i) {
        const std::string_view file = kEmbeddedScenes[i].name ? kEmbeddedScenes[i].name : "";
        if (file.starts_with("scenes/") && file.ends_with(".json"))
            names.emplace_back(file.substr(7, file.size() - 12));
    }
    std::sort(names.begin(), names.end(), [](const std::string& a, const std::string& b) {
        if ((a == kDefaultScene) != (b == kDefaultScene)) return a == kDefaultScene;
        return a < b;
    });
    return names;
}

std::optional<Scene> load_builtin_scene(const std::string& name, SpectralResolution resolution,
                                        InputFiles* input_files) {
    if (name.find('/') != std::string::npos) return std::nullopt;
    const std::string file = "scenes/" + name + ".json";
    const EmbeddedFile* embedded = find_embedded(file);
    if (!embedded) return std::nullopt;
    const RelativeFileReader reader = [](const std::string& rel, std::string& contents, std::string& display,
                                         std::string& why) {
        display = (std::filesystem::path("scenes") / rel).lexically_normal().generic_string();
        const EmbeddedFile* f = find_embedded(display);
        if (!f) {
            why = "no such built-in file";
            return false;
        }
        contents = f->bytes();
        return true;
    };
    return load_scene_text(embedded->text, file, name, resolution, reader, input_files);
}

}  // namespace spt
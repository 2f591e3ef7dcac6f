// The functions of scene_loader.h, the scene files' front door: the reader table, files from disk
// and the built-in scenes.
#include "scene/scene_loader.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "io/checksums.h"
#include "io/embedded_files.h"
#include "scene/json_scene_reader.h"
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
    return text;
}

}  // namespace

const std::vector<SceneReader>& scene_readers() {
    static const std::vector<SceneReader> readers = {
        {"JSON", ".json", read_json_scene},
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
    for (const SceneReader& r : scene_readers())
        if (origin.ends_with(r.extension)) reader = &r;
    Scene scene = build_scene(reader->read(text, origin, scene_name), resolution, recording);
    if (input_files) *input_files = std::move(inputs);
    return scene;
}

Scene load_scene_file(const std::string& path, SpectralResolution resolution, InputFiles* input_files) {
    std::string error;
    const std::string text = read_whole_file(path, error);
    if (!error.empty()) throw LocatedError(path, {1, 1}, "cannot read the scene file: " + error + "; expected a readable JSON file");
    const std::filesystem::path base = std::filesystem::path(path).parent_path();
    const RelativeFileReader reader = [&](const std::string& rel, std::string& contents, std::string& display,
                                          std::string& why) {
        const std::filesystem::path full = base / rel;
        display = full.string();
        contents = read_whole_file(full, why);
        return why.empty();
    };
    return load_scene_text(text, path, std::filesystem::path(path).stem().string(), resolution, reader, input_files);
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

std::optional<SceneSource> read_scene_source(const std::string& scene) {
    const auto reader_for = [](const std::string& origin) {
        const SceneReader* reader = &scene_readers().front();
        for (const SceneReader& r : scene_readers())
            if (origin.ends_with(r.extension)) reader = &r;
        return reader;
    };
    if (scene.find('/') == std::string::npos) {
        const std::string file = "scenes/" + scene + ".json";
        if (const EmbeddedFile* embedded = find_embedded(file)) {
            SceneSource s;
            s.description = reader_for(file)->read(embedded->text, file, scene);
            s.read_relative = [](const std::string& rel, std::string& contents, std::string& display, std::string& why) {
                display = (std::filesystem::path("scenes") / rel).lexically_normal().generic_string();
                const EmbeddedFile* f = find_embedded(display);
                if (!f) {
                    why = "no such built-in file";
                    return false;
                }
                contents = f->bytes();
                return true;
            };
            return s;
        }
    }
    std::error_code ec;
    if (!scene.ends_with(".json") && !std::filesystem::is_regular_file(scene, ec)) return std::nullopt;
    std::string error;
    const std::string text = read_whole_file(scene, error);
    if (!error.empty()) throw LocatedError(scene, {1, 1}, "cannot read the scene file: " + error + "; expected a readable scene file");
    SceneSource s;
    s.description = reader_for(scene)->read(text, scene, std::filesystem::path(scene).stem().string());
    s.folder = std::filesystem::path(scene).parent_path().string();
    if (s.folder.empty()) s.folder = ".";
    s.read_relative = [base = std::filesystem::path(s.folder)](const std::string& rel, std::string& contents,
                                                               std::string& display, std::string& why) {
        const std::filesystem::path full = base / rel;
        display = full.string();
        contents = read_whole_file(full, why);
        return why.empty();
    };
    return s;
}

}  // namespace spt

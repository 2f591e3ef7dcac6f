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

/// The reader of a scene file's format, by its name's ending (a ".gz" after it is the
/// compression); the first reader for names without a listed ending.
const SceneReader& reader_for(std::string_view origin) {
    if (origin.ends_with(".gz")) origin.remove_suffix(3);
    for (const SceneReader& r : scene_readers())
        if (origin.ends_with(r.extension)) return r;
    return scene_readers().front();
}

/// The scene's name: its file name without the format's ending (scene.pbrt.gz is "scene").
std::string scene_name_of(const std::filesystem::path& path) {
    std::filesystem::path name = path.stem();
    if (path.extension() == ".gz") name = name.stem();
    return name.string();
}

/// The files a scene on disk names, relative to its folder.
RelativeFileReader files_beside(const std::filesystem::path& folder) {
    return [folder](const std::string& rel, std::string& contents, std::string& display, std::string& why) {
        const std::filesystem::path full = folder / rel;
        display = full.string();
        contents = read_whole_file(full, why);
        return why.empty();
    };
}

/// The files a built-in scene names: compiled in, under scenes/.
RelativeFileReader builtin_files() {
    return [](const std::string& rel, std::string& contents, std::string& display, std::string& why) {
        display = (std::filesystem::path("scenes") / rel).lexically_normal().generic_string();
        const EmbeddedFile* f = find_embedded(display);
        if (!f) {
            why = "no such built-in file";
            return false;
        }
        contents = f->bytes();
        return true;
    };
}

const EmbeddedFile* builtin_scene_file(const std::string& name) {
    if (name.find('/') != std::string::npos) return nullptr;
    return find_embedded("scenes/" + name + ".json");
}

std::string read_scene_file(const std::string& path) {
    std::string error;
    std::string text = read_whole_file(path, error);
    if (!error.empty()) throw LocatedError(path, {1, 1}, "cannot read the scene file: " + error + "; expected a readable scene file");
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
    const SceneDescription description = reader_for(origin).read(text, origin, scene_name, recording);
    Scene scene = build_scene(description, resolution, recording);
    scene.warnings.insert(scene.warnings.begin(), description.warnings.begin(), description.warnings.end());
    if (input_files) *input_files = std::move(inputs);
    return scene;
}

Scene load_scene_file(const std::string& path, SpectralResolution resolution, InputFiles* input_files) {
    const std::string text = read_scene_file(path);
    return load_scene_text(text, path, scene_name_of(path), resolution, files_beside(std::filesystem::path(path).parent_path()),
                           input_files);
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
    const EmbeddedFile* embedded = builtin_scene_file(name);
    if (!embedded) return std::nullopt;
    return load_scene_text(embedded->text, embedded->name, name, resolution, builtin_files(), input_files);
}

std::optional<SceneSource> read_scene_source(const std::string& scene) {
    SceneSource s;
    if (const EmbeddedFile* embedded = builtin_scene_file(scene)) {
        s.read_relative = builtin_files();
        s.description = reader_for(embedded->name).read(embedded->text, embedded->name, scene, s.read_relative);
        return s;
    }
    std::error_code ec;
    if (!scene.ends_with(".json") && !std::filesystem::is_regular_file(scene, ec)) return std::nullopt;
    const std::string text = read_scene_file(scene);
    s.folder = std::filesystem::path(scene).parent_path().string();
    if (s.folder.empty()) s.folder = ".";
    s.read_relative = files_beside(s.folder);
    s.description = reader_for(scene).read(text, scene, scene_name_of(scene), s.read_relative);
    return s;
}

}  // namespace spt

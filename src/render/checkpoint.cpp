// Checkpoint file: a text header (one "key value" line per field of the render's description,
// then "end"), the film state, and an FNV-1a checksum of both, so a truncated or corrupted file
// is refused instead of resumed. The reader range-checks every field: the checksum catches
// accidents, not a header edited by hand with its checksum recomputed.
#include "render/checkpoint.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "io/atomic_file.h"
#include "io/checksums.h"
#include "render/integrator.h"

namespace spt {

namespace {

// Checkpoint version 3, partial film version 2: typed headers with every input's fingerprint.
const char* magic(FilmFile kind) { return kind == FilmFile::checkpoint ? "spt-checkpoint-3" : "spt-partial-film-2"; }

std::string error_prefix(FilmFile kind, const std::string& path) {
    return (kind == FilmFile::checkpoint ? "cannot resume from '" : "cannot merge '") + path + "': ";
}

std::string hex(std::uint64_t v) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
    return text;
}

const char* on_off(bool b) { return b ? "on" : "off"; }

std::string header(const CheckpointInfo& info, FilmFile kind) {
    const RenderDescription& r = info.render;
    char radius[32];
    std::snprintf(radius, sizeof radius, "%.9g", static_cast<double>(r.merge_radius));
    std::ostringstream s;
    s << magic(kind) << '\n'
      << "scene " << r.scene.size() << ':' << r.scene << '\n'
      << "size " << r.width << ' ' << r.height << '\n'
      << "spp " << r.spp << '\n'
      << "spectral-bins " << r.spectral_bins << '\n'
      << "max-depth " << r.max_depth << '\n'
      << "seed " << r.seed << '\n'
      << "integrator " << integrator_name(r.integrator) << '\n'
      << "light-sampling " << light_sampling_name(r.light_sampling) << '\n'
      << "sampler " << sampler_name(r.sampler) << '\n'
      << "wavelengths-per-path " << r.wavelengths_per_path << '\n'
      << "caustic-nee " << on_off(r.caustic_nee) << '\n'
      << "plane-nee " << on_off(r.plane_nee) << '\n'
      << "light-selection " << light_selection_name(r.light_selection) << '\n'
      << "guiding " << guiding_mode_name(r.guiding) << '\n'
      << "dispersion " << on_off(r.dispersion) << '\n'
      << "merge-radius " << radius << '\n'
      << "program " << hex(r.program) << '\n';
    for (const auto& [name, hash] : r.inputs) s << "input " << hex(hash) << ' ' << name.size() << ':' << name << '\n';
    s << "samples " << info.first_sample << ' ' << info.samples_completed << '\n' << "end\n";
    return s.str();
}

/// Reads the header field by field from the front of `in`, checking each value's range.
class HeaderReader {
public:
    HeaderReader(std::string_view in, std::string prefix) : m_in(in), m_prefix(std::move(prefix)) {}

    std::runtime_error fail(const std::string& why) const { return std::runtime_error(m_prefix + why); }

    /// The next line's key ("" at the end of the data).
    std::string key() {
        const std::size_t space = m_in.find_first_of(" \n");
        if (space == std::string_view::npos) throw fail("malformed header (no 'end' line)");
        std::string k(m_in.substr(0, space));
        m_in.remove_prefix(space + (m_in[space] == ' ' ? 1 : 0));
        return k;
    }
    std::string word() {
        const std::size_t end = m_in.find_first_of(" \n");
        if (end == std::string_view::npos || end == 0) throw fail("malformed header");
        std::string w(m_in.substr(0, end));
        m_in.remove_prefix(end + (m_in[end] == ' ' ? 1 : 0));
        return w;
    }
    /// A <length>:<bytes> string (it may hold spaces).
    std::string counted(const char* field) {
        const std::size_t colon = m_in.find(':');
        std::size_t n = 0;
        if (colon == std::string_view::npos || !parse(m_in.substr(0, colon), n) || n > m_in.size() - colon - 1)
            throw fail(std::string("header field '") + field + "' is malformed");
        const std::size_t end = colon + 1 + n;
        if (end < m_in.size() && m_in[end] != ' ' && m_in[end] != '\n')  // the count must be the length
            throw fail(std::string("header field '") + field + "' is malformed");
        std::string s(m_in.substr(colon + 1, n));
        m_in.remove_prefix(end);
        if (!m_in.empty() && m_in.front() == ' ') m_in.remove_prefix(1);
        return s;
    }
    template <typename T>
    T integer(const char* field, T lo, T hi) {
        const std::string w = word();
        T v{};
        if (!parse(w, v) || v < lo || v > hi)
            throw fail(std::string("header field '") + field + "' is " + w + "; expected an integer from " +
                       std::to_string(lo) + " to " + std::to_string(hi));
        return v;
    }
    std::uint64_t hex64(const char* field) {
        const std::string w = word();
        std::uint64_t v = 0;
        const auto [ptr, ec] = std::from_chars(w.data(), w.data() + w.size(), v, 16);
        if (ec != std::errc() || ptr != w.data() + w.size())
            throw fail(std::string("header field '") + field + "' is " + w + "; expected a hexadecimal hash");
        return v;
    }
    bool flag(const char* field) {
        const std::string w = word();
        if (w != "on" && w != "off")
            throw fail(std::string("header field '") + field + "' is " + w + "; expected on or off");
        return w == "on";
    }
    template <typename Enum, std::size_t N>
    Enum name(const char* field, const Enum (&values)[N], const char* (*name_of)(Enum)) {
        const std::string w = word();
        for (Enum e : values)
            if (w == name_of(e)) return e;
        throw fail(std::string("header field '") + field + "' is " + w + "; expected a name this program knows");
    }
    float non_negative(const char* field) {
        const std::string w = word();
        char* end = nullptr;
        const float v = std::strtof(w.c_str(), &end);
        if (end != w.c_str() + w.size() || !std::isfinite(v) || v < 0.f)
            throw fail(std::string("header field '") + field + "' is " + w + "; expected a finite number >= 0");
        return v;
    }
    void end_of_line() {
        if (m_in.empty() || m_in.front() != '\n') throw fail("malformed header (extra values on a line)");
        m_in.remove_prefix(1);
    }
    std::string_view rest() const { return m_in; }

private:
    template <typename T>
    static bool parse(std::string_view t, T& v) {
        const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
        return !t.empty() && ec == std::errc() && ptr == t.data() + t.size();
    }
    std::string_view m_in;
    std::string m_prefix;
};

struct Parsed {
    CheckpointInfo info;
    std::string_view film_state;
};

Parsed parse(const std::string& path, const std::string& bytes, FilmFile kind) {
    const std::string prefix = error_prefix(kind, path);
    auto fail = [&](const std::string& why) { return std::runtime_error(prefix + why); };
    if (bytes.size() < 8) throw fail("file is truncated");
    std::uint64_t stored;
    std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
    const std::string_view body(bytes.data(), bytes.size() - 8);
    if (fnv1a64(body) != stored) throw fail("checksum mismatch (file is truncated or corrupt)");
    const std::string tag = std::string(magic(kind)) + '\n';
    if (!body.starts_with(tag))
        throw fail(kind == FilmFile::checkpoint ? "not a checkpoint of this program version"
                                                : "not a partial film of this program version");
    HeaderReader h(body.substr(tag.size()), prefix);
    Parsed p;
    RenderDescription& r = p.info.render;
    std::map<std::string, int> seen;
    for (std::string key = h.key(); key != "end"; key = h.key()) {
        if (key != "input" && seen[key]++) throw fail("header field '" + key + "' appears twice");
        if (key == "scene") r.scene = h.counted("scene");
        else if (key == "size") {
            r.width = h.integer("width", 1, 65536);
            r.height = h.integer("height", 1, 65536);
        } else if (key == "spp") r.spp = h.integer("spp", 1, 1000000);
        else if (key == "spectral-bins") r.spectral_bins = h.integer("spectral-bins", 0, 1024);
        else if (key == "max-depth") r.max_depth = h.integer("max-depth", IntegratorSettings::kUnbounded, 100000);
        else if (key == "seed") r.seed = h.integer<std::uint64_t>("seed", 0, UINT64_MAX);
        else if (key == "integrator") r.integrator = h.name("integrator", kIntegratorKinds, integrator_name);
        else if (key == "light-sampling")
            r.light_sampling = h.name("light-sampling", kLightSamplingModes, light_sampling_name);
        else if (key == "sampler") r.sampler = h.name("sampler", kSamplerKinds, sampler_name);
        else if (key == "wavelengths-per-path") {
            r.wavelengths_per_path = h.integer("wavelengths-per-path", 1, kLambdaCount);
        } else if (key == "caustic-nee") r.caustic_nee = h.flag("caustic-nee");
        else if (key == "plane-nee") r.plane_nee = h.flag("plane-nee");
        else if (key == "light-selection")
            r.light_selection = h.name("light-selection", kLightSelectionModes, light_selection_name);
        else if (key == "guiding") r.guiding = h.name("guiding", kGuidingModes, guiding_mode_name);
        else if (key == "dispersion") r.dispersion = h.flag("dispersion");
        else if (key == "merge-radius") r.merge_radius = h.non_negative("merge-radius");
        else if (key == "program") r.program = h.hex64("program");
        else if (key == "input") {
            const std::uint64_t hash = h.hex64("input");
            r.inputs.emplace_back(h.counted("input"), hash);
        } else if (key == "samples") {
            p.info.first_sample = h.integer("first sample", 0, 1000000);
            p.info.samples_completed = h.integer("samples completed", 0, 1000000);
        } else {
            throw fail("unknown header field '" + key + "'");
        }
        h.end_of_line();
    }
    h.end_of_line();
    for (const char* key : {"scene", "size", "spp", "spectral-bins", "max-depth", "seed", "integrator",
                            "light-sampling", "sampler", "wavelengths-per-path", "caustic-nee", "plane-nee",
                            "dispersion", "merge-radius", "program", "samples"})
        if (!seen.contains(key)) throw fail(std::string("header field '") + key + "' is missing");
    const bool partial = kind == FilmFile::partial;
    if (p.info.samples_completed > r.spp || p.info.first_sample > p.info.samples_completed ||
        (partial && p.info.first_sample == p.info.samples_completed) || (!partial && p.info.first_sample != 0))
        throw fail("header field 'samples' is " + std::to_string(p.info.first_sample) + " " +
                   std::to_string(p.info.samples_completed) + "; expected FIRST END with 0 <= FIRST " +
                   (partial ? "<" : "=") + " END <= spp (" + std::to_string(r.spp) + ")" +
                   (partial ? "" : ", FIRST 0"));
    p.film_state = h.rest();
    // Every pixel takes several bytes of film state: a size the data cannot hold is refused
    // here, before a film of that size is allocated.
    if (static_cast<std::uint64_t>(r.width) * static_cast<std::uint64_t>(r.height) > p.film_state.size())
        throw fail("header field 'size' is " + std::to_string(r.width) + " " + std::to_string(r.height) +
                   "; the film data (" + std::to_string(p.film_state.size()) + " bytes) holds fewer pixels");
    return p;
}

std::string read_all(const std::string& path, FilmFile kind) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(error_prefix(kind, path) + "cannot open the file");
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

std::string RenderDescription::difference(const RenderDescription& o) const {
    auto differs = [](const char* what, const auto& mine, const auto& theirs) {
        std::ostringstream s;
        s << what << ' ' << mine << ", not " << theirs;
        return s.str();
    };
    if (scene != o.scene) return differs("scene", scene, o.scene);
    if (width != o.width || height != o.height)
        return differs("size", std::to_string(width) + "x" + std::to_string(height),
                       std::to_string(o.width) + "x" + std::to_string(o.height));
    if (spp != o.spp) return differs("spp", spp, o.spp);
    if (seed != o.seed) return differs("seed", seed, o.seed);
    if (spectral_bins != o.spectral_bins) return differs("spectral bins", spectral_bins, o.spectral_bins);
    if (max_depth != o.max_depth) return differs("max depth", max_depth, o.max_depth);
    if (integrator != o.integrator) return differs("integrator", integrator_name(integrator), integrator_name(o.integrator));
    if (light_sampling != o.light_sampling)
        return differs("light sampling", light_sampling_name(light_sampling), light_sampling_name(o.light_sampling));
    if (sampler != o.sampler) return differs("sampler", sampler_name(sampler), sampler_name(o.sampler));
    if (wavelengths_per_path != o.wavelengths_per_path)
        return differs("wavelengths per path", wavelengths_per_path, o.wavelengths_per_path);
    if (caustic_nee != o.caustic_nee) return differs("caustic NEE", on_off(caustic_nee), on_off(o.caustic_nee));
    if (plane_nee != o.plane_nee) return differs("plane NEE", on_off(plane_nee), on_off(o.plane_nee));
    if (light_selection != o.light_selection)
        return differs("light selection", light_selection_name(light_selection), light_selection_name(o.light_selection));
    if (guiding != o.guiding) return differs("guiding", guiding_mode_name(guiding), guiding_mode_name(o.guiding));
    if (dispersion != o.dispersion) return differs("dispersion", on_off(dispersion), on_off(o.dispersion));
    if (merge_radius != o.merge_radius) return differs("merge radius", merge_radius, o.merge_radius);
    for (const auto& [name, hash] : inputs) {
        const auto other = std::find_if(o.inputs.begin(), o.inputs.end(), [&](const auto& i) { return i.first == name; });
        if (other == o.inputs.end()) return "the file '" + name + "' is an input of one render and not of the other";
        if (other->second != hash) return "the file '" + name + "' differs (its contents changed)";
    }
    for (const auto& input : o.inputs)
        if (std::none_of(inputs.begin(), inputs.end(), [&](const auto& i) { return i.first == input.first; }))
            return "the file '" + input.first + "' is an input of one render and not of the other";
    if (program != o.program)
        return "another build of the program (build id " + hex(program) + ", not " + hex(o.program) + ")";
    return {};
}

std::string RenderDescription::describe() const {
    std::ostringstream s;
    s << "scene " << scene << ", " << width << "x" << height << ", " << spp << " spp, seed " << seed << ", integrator "
      << integrator_name(integrator) << ", sampler " << sampler_name(sampler);
    return s.str();
}

void save_checkpoint(const std::string& path, const CheckpointInfo& info, const std::string& film_state,
                     FilmFile kind) {
    std::string bytes = header(info, kind) + film_state;
    const std::uint64_t sum = fnv1a64(bytes);
    bytes.append(reinterpret_cast<const char*>(&sum), sizeof sum);
    write_file_atomically(path, bytes);
}

CheckpointInfo read_checkpoint_info(const std::string& path, FilmFile kind) {
    const std::string bytes = read_all(path, kind);
    return parse(path, bytes, kind).info;
}

CheckpointInfo load_checkpoint(const std::string& path, Film& film, FilmFile kind) {
    const std::string bytes = read_all(path, kind);
    const Parsed p = parse(path, bytes, kind);
    try {
        film.restore_state(p.film_state);
    } catch (const std::runtime_error& e) {
        throw std::runtime_error(error_prefix(kind, path) + e.what());
    }
    return p.info;
}

}  // namespace spt

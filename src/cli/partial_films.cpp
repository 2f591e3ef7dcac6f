#include "cli/partial_films.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <stdexcept>

#include "scene/param_checker.h"

namespace spt {

bool is_partial_film_path(const std::string& path) {
    return path.size() > 5 && path.ends_with(".film");
}

std::pair<int, int> parse_pass_range(const std::string& flag, const std::string& text) {
    const char* what = "A:B with 0 <= A < B <= 1000000 (passes A to B-1)";
    const std::size_t colon = text.find(':');
    int a = -1, b = -1;
    auto number = [&](std::string_view t, int& v) {
        const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
        return !t.empty() && ec == std::errc() && ptr == t.data() + t.size();
    };
    if (colon == std::string::npos || !number(std::string_view(text).substr(0, colon), a) ||
        !number(std::string_view(text).substr(colon + 1), b) || a < 0 || b <= a || b > 1000000)
        throw UsageError(flag + ": expected " + what + ", got '" + text + "'");
    return {a, b};
}

void check_partial_film_options(const Options& o) {
    const auto films = std::count_if(o.outputs.begin(), o.outputs.end(), is_partial_film_path);
    if (films == 0) {
        if (o.passes) throw UsageError("--passes: needs .film outputs (-o PART.film) to hold the passes");
        return;
    }
    if (films != static_cast<long>(o.outputs.size()))
        throw UsageError("-o: .film outputs cannot be mixed with images (merge the parts into images)");
    // A part must hold whole chunks of the render's automatic passes, nothing else.
    const std::pair<const char*, bool> refused[] = {
        {"--pass-spp", o.pass_spp > 0},
        {"--time-limit", o.time_limit > 0},
        {"--checkpoint", !o.checkpoint.empty()},
        {"--resume", !o.resume.empty()},
        {"--preview-interval", o.preview_interval.has_value()},
        {"--display-server", o.display_server.has_value()},
        {"--sensor", !o.sensor.empty()},
        {"--spectral-bands", o.spectral_bands.count > 0},
    };
    for (const auto& [flag, given] : refused)
        if (given) throw UsageError(std::string(flag) + ": not with .film outputs (partial films hold whole "
                                    "automatic passes of the CIE XYZ film only)");
}

int pass_count(const RenderSettings& settings) {
    const int chunk = chunk_spp(settings);
    return (settings.spp + chunk - 1) / chunk;
}

std::pair<int, int> pass_samples(const RenderSettings& settings, std::pair<int, int> passes) {
    const int count = pass_count(settings);
    if (passes.second > count)
        throw UsageError("--passes: this render has " + std::to_string(count) + " passes (0:" +
                         std::to_string(count) + " is all of them), got " + std::to_string(passes.first) + ":" +
                         std::to_string(passes.second));
    const int chunk = chunk_spp(settings);
    return {passes.first * chunk, std::min(settings.spp, passes.second * chunk)};
}

namespace {

std::string range_text(int first, int end) { return std::to_string(first) + "-" + std::to_string(end); }

}  // namespace

MergedParts merge_partial_films(const std::vector<std::string>& paths) {
    if (paths.empty()) throw UsageError("merge: expected one or more partial films (PART.film)");
    struct Part {
        std::string path;
        CheckpointInfo info;
    };
    std::vector<Part> parts;
    for (const std::string& path : paths) {
        parts.push_back({path, read_checkpoint_info(path, FilmFile::partial)});
        const Part& p = parts.back();
        if (const std::string diff = p.info.render.difference(parts.front().info.render); !diff.empty())
            throw std::runtime_error("cannot merge '" + path + "': it holds another render than '" +
                                     parts.front().path + "' (" + diff + ")");
    }
    std::stable_sort(parts.begin(), parts.end(),
                     [](const Part& a, const Part& b) { return a.info.first_sample < b.info.first_sample; });
    MergedParts m;
    m.info = parts.front().info;
    for (std::size_t k = 1; k < parts.size(); ++k) {
        const CheckpointInfo &a = parts[k - 1].info, &b = parts[k].info;
        if (b.first_sample < a.samples_completed)
            throw std::runtime_error("cannot merge '" + parts[k].path + "': its samples " +
                                     range_text(b.first_sample, b.samples_completed) + " overlap those of '" +
                                     parts[k - 1].path + "' (" + range_text(a.first_sample, a.samples_completed) +
                                     ")");
    }
    int covered = 0;
    std::vector<std::string> missing;
    for (const Part& p : parts) {
        if (p.info.first_sample > covered) missing.push_back(range_text(covered, p.info.first_sample));
        if (!m.ranges.empty() && m.ranges.back().second == p.info.first_sample)
            m.ranges.back().second = p.info.samples_completed;
        else
            m.ranges.emplace_back(p.info.first_sample, p.info.samples_completed);
        m.samples += p.info.samples_completed - p.info.first_sample;
        covered = p.info.samples_completed;
    }
    if (covered < m.info.render.spp) missing.push_back(range_text(covered, m.info.render.spp));
    m.missing = join(missing);
    m.info.first_sample = m.ranges.front().first;
    m.info.samples_completed = m.ranges.back().second;

    m.film = std::make_unique<Film>(m.info.render.width, m.info.render.height);
    for (const Part& p : parts) {
        Film film(m.info.render.width, m.info.render.height);
        load_checkpoint(p.path, film, FilmFile::partial);
        if (!film.is_folded())
            throw std::runtime_error("cannot merge '" + p.path + "': its sums are not folded (not a whole "
                                     "number of chunks)");
        m.film->merge(film);
    }
    return m;
}

}  // namespace spt

// Partial films: one render split into ranges of its passes (--passes A:B -o part.film), each
// rendered anywhere, then merged ('pathtracer merge') into the film of one uninterrupted
// render, bit for bit (the film's folded sums are exact: see render/exact_sum.h).
#pragma once
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cli/options.h"
#include "render/checkpoint.h"
#include "render/film.h"
#include "render/renderer.h"

namespace spt {

/// True for an output name ending in .film (a partial film rather than an image).
bool is_partial_film_path(const std::string& path);

/// Parses --passes A:B (0 <= A < B <= 1000000). Throws UsageError naming `flag`.
std::pair<int, int> parse_pass_range(const std::string& flag, const std::string& text);

/// Refuses (UsageError) what partial films do not support: .film outputs mixed with images,
/// --passes without .film outputs, and the settings a part cannot hold or split exactly.
void check_partial_film_options(const Options& options);

/// The passes of a render split by --passes: chunk_spp samples each (the last may be
/// shorter), the automatic passes of the same command without --passes.
int pass_count(const RenderSettings& settings);

/// Samples [first, end) of passes [A, B). Throws UsageError when B exceeds pass_count.
std::pair<int, int> pass_samples(const RenderSettings& settings, std::pair<int, int> passes);

/// The parts' films merged.
struct MergedParts {
    CheckpointInfo info;  ///< the render's; first_sample/samples_completed: the range held,
                          ///< when contiguous
    std::unique_ptr<Film> film;
    std::vector<std::pair<int, int>> ranges;  ///< sample ranges held, sorted and coalesced
    int samples = 0;                          ///< samples per pixel held
    /// The sample ranges of the render no part holds ("16-32, 48-64"); empty: none.
    std::string missing;
};

/// Reads and merges partial films. Throws std::runtime_error naming the file and the reason
/// when one is unreadable, truncated or corrupt, belongs to another render (scene, settings,
/// seed, size, input files, program build) than the first, or overlaps another part.
MergedParts merge_partial_films(const std::vector<std::string>& paths);

}  // namespace spt

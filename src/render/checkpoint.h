// Checkpoints: the film state plus everything that must match to continue a render, saved
// atomically (temporary file + rename) so a kill at any moment leaves the previous one intact.
// Partial films (.film: samples [first_sample, samples_completed) of a render, to be merged)
// are the same file under another name tag.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>

#include "render/film.h"

namespace spt {

/// What a resumed render must share with the one that wrote the checkpoint.
struct CheckpointInfo {
    std::string scene;
    std::string variant;  ///< other settings that change the image (e.g. "wpp=4 dispersion=1")
    int width = 0, height = 0, spp = 0, spectral_bins = 0, max_depth = 0;
    std::uint64_t seed = 0;
    int samples_completed = 0;  ///< samples per pixel in the saved film
    int first_sample = 0;       ///< partial films: the first sample they hold (checkpoints: 0)

    bool same_render(const CheckpointInfo& o) const {
        return scene == o.scene && variant == o.variant && width == o.width && height == o.height && spp == o.spp &&
               spectral_bins == o.spectral_bins && max_depth == o.max_depth && seed == o.seed;
    }
    std::string describe() const;
};

/// Which kind of film file: they differ in the tag of their first line (so one is never taken
/// for the other) and in the wording of their errors.
enum class FilmFile { checkpoint, partial };

/// FNV-1a 64-bit hash of bytes (the files' checksum; also the scene file's fingerprint).
std::uint64_t fnv1a(std::string_view bytes);

/// Writes info + a film state (Film::save_state) to `path` atomically (throws
/// std::runtime_error naming the file).
void save_checkpoint(const std::string& path, const CheckpointInfo& info, const std::string& film_state,
                     FilmFile kind = FilmFile::checkpoint);

/// Reads a checkpoint; the film must already have the checkpoint's size. Throws
/// std::runtime_error naming the file when it is unreadable, corrupt or of another version.
CheckpointInfo load_checkpoint(const std::string& path, Film& film, FilmFile kind = FilmFile::checkpoint);

/// Reads only the info block (to check it before allocating a film).
CheckpointInfo read_checkpoint_info(const std::string& path, FilmFile kind = FilmFile::checkpoint);

}  // namespace spt

// Checkpoints: the film state plus everything that must match to continue a render, saved
// atomically (temporary file + rename) so a kill at any moment leaves the previous one intact.
#pragma once
#include <cstdint>
#include <string>

#include "render/film.h"

namespace spt {

/// What a resumed render must share with the one that wrote the checkpoint.
struct CheckpointInfo {
    std::string scene;
    std::string variant;  ///< other settings that change the image (e.g. "wpp=4 dispersion=1")
    int width = 0, height = 0, spp = 0, spectral_bins = 0, max_depth = 0;
    std::uint64_t seed = 0;
    int samples_completed = 0;  ///< samples per pixel in the saved film

    bool same_render(const CheckpointInfo& o) const {
        return scene == o.scene && variant == o.variant && width == o.width && height == o.height && spp == o.spp &&
               spectral_bins == o.spectral_bins && max_depth == o.max_depth && seed == o.seed;
    }
    std::string describe() const;
};

/// Writes info + a film state (Film::save_state) to `path` atomically (throws
/// std::runtime_error naming the file).
void save_checkpoint(const std::string& path, const CheckpointInfo& info, const std::string& film_state);

/// Reads a checkpoint; the film must already have the checkpoint's size. Throws
/// std::runtime_error naming the file when it is unreadable, corrupt or of another version.
CheckpointInfo load_checkpoint(const std::string& path, Film& film);

/// Reads only the info block (to check it before allocating a film).
CheckpointInfo read_checkpoint_info(const std::string& path);

}  // namespace spt

// Checkpoints: the film state plus the typed description of the render it belongs to (what
// must match to continue it), saved atomically (temporary file + rename) so a kill at any
// moment leaves the previous one intact. Partial films (.film: samples [first_sample,
// samples_completed) of a render, to be merged) are the same file under another name tag.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "render/film.h"
#include "render/integrator_kind.h"
#include "render/sampler_kind.h"

namespace spt {

/// Everything that decides a render's image: a resumed render or a merged part must share all
/// of it. `inputs` are the files the render read (scene text, meshes, textures, grids, sensor
/// curve) with the FNV-1a hash of their bytes; `program` identifies the build (two builds
/// may round differently).
struct RenderDescription {
    std::string scene;  ///< a built-in scene's name or the scene file's path as given
    int width = 0, height = 0, spp = 0;
    int spectral_bins = 0;  ///< SpectralResolution::bins (0: exact)
    int max_depth = 0;      ///< IntegratorSettings::kUnbounded (-1) or 0 to 100000
    std::uint64_t seed = 0;
    IntegratorKind integrator = IntegratorKind::path;
    LightSampling light_sampling = LightSampling::mis;
    SamplerKind sampler = SamplerKind::independent;
    int wavelengths_per_path = 4;
    bool caustic_nee = true, plane_nee = true, dispersion = true;
    /// Files without the field were rendered by power.
    LightSelection light_selection = LightSelection::power;
    /// Files without the field were rendered without guiding.
    GuidingMode guiding = GuidingMode::off;
    float merge_radius = 0.f;  ///< vcm's first-pass radius; 0: the default
    std::uint64_t program = 0;
    std::vector<std::pair<std::string, std::uint64_t>> inputs;

    /// What differs from `other` in words ("seed 5, not 6"; "the file 'mesh.ply' differs"),
    /// empty when nothing does.
    std::string difference(const RenderDescription& other) const;
    /// One line for messages: scene, size, spp, seed and the settings that are not defaults.
    std::string describe() const;
};

/// A render's description and how many of its samples per pixel a film file holds.
struct CheckpointInfo {
    RenderDescription render;
    int samples_completed = 0;  ///< samples per pixel in the saved film (its end sample)
    int first_sample = 0;       ///< partial films: the first sample they hold (checkpoints: 0)
};

/// Which kind of film file: they differ in the tag of their first line (so one is never taken
/// for the other) and in the wording of their errors.
enum class FilmFile { checkpoint, partial };

/// Writes info + a film state (Film::save_state) to `path` atomically (throws
/// std::runtime_error naming the file).
void save_checkpoint(const std::string& path, const CheckpointInfo& info, const std::string& film_state,
                     FilmFile kind = FilmFile::checkpoint);

/// Reads a checkpoint; the film must already have the checkpoint's size. Throws
/// std::runtime_error naming the file when it is unreadable, corrupt, of another version, or
/// holds a field out of range (its checksum does not vouch for a header edited by hand).
CheckpointInfo load_checkpoint(const std::string& path, Film& film, FilmFile kind = FilmFile::checkpoint);

/// Reads only the info block (to check it before allocating a film).
CheckpointInfo read_checkpoint_info(const std::string& path, FilmFile kind = FilmFile::checkpoint);

}  // namespace spt
